//! The fusion filter on the Northstar report's own two trials (read from the shared data).

use labs::fusion::{Detector, REPORT_FIGURES, ReportFigures, Settings, Summary, Trial, run, tune};

testdata::data_tests!(
    the_report_figures_come_back_from_its_files,
    settings_tuned_on_one_trial_beat_the_report_on_the_other,
    round_settings_beat_the_report_on_both,
);

fn trial(n: u32) -> Trial {
    let sensor = format!("northstar/trial{n}_odometry_northstar.csv");
    let estimate = format!("northstar/trial{n}_kalman_groundtruth.csv");
    Trial::from_report(
        (&testdata::read(&sensor), &sensor),
        (&testdata::read(&estimate), &estimate),
    )
    .unwrap()
}

fn summary(trial: &Trial, settings: &Settings) -> Summary {
    Summary::of(trial, &run(trial, settings, &Detector::default()))
}

fn the_report_figures_come_back_from_its_files() {
    for (n, figures) in [1, 2].into_iter().zip(REPORT_FIGURES) {
        let ReportFigures {
            kalman,
            odometry,
            sensor,
        } = figures;
        let s = summary(&trial(n), &Settings::default());
        let close = |a: f64, b: f64| (a - b).abs() < 0.0005;
        assert!(close(s.report.unwrap().mean, kalman), "trial {n}: {s:?}");
        assert!(close(s.odometry.mean, odometry), "trial {n}: {s:?}");
        assert!(close(s.sensor.unwrap().mean, sensor), "trial {n}: {s:?}");
    }
}

/// Tuning the process noise on one trial and running on the other: the filter still
/// beats the report's own estimate there.
fn settings_tuned_on_one_trial_beat_the_report_on_the_other() {
    let detector = Detector::default();
    let trials = [trial(1), trial(2)];
    for (tuned_on, tested_on) in [(0, 1), (1, 0)] {
        let base = Settings::default();
        let (settings, _) = tune(&trials[tuned_on], &base, &detector);
        let s = summary(&trials[tested_on], &settings);
        let report = REPORT_FIGURES[tested_on].kalman;
        assert!(
            s.filter.mean < report,
            "tuned on trial {}, on trial {}: {:.3} m, the report {report}",
            tuned_on + 1,
            tested_on + 1,
            s.filter.mean
        );
    }
}

fn round_settings_beat_the_report_on_both() {
    for (n, report) in [1, 2].into_iter().zip(REPORT_FIGURES) {
        let s = summary(&trial(n), &Settings::default());
        assert!(s.filter.mean < report.kalman, "trial {n}: {s:?}");
    }
}
