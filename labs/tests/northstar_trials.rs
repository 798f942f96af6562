//! The fusion filter on the Northstar report's own two trials (read from the shared data).

use labs::fusion::{Detector, REPORT_FIGURES, ReportFigures, Settings, Summary, Trial, run, tune};

testdata::data_tests!(
    the_report_figures_come_back_from_its_files,
    settings_tuned_on_one_trial_beat_the_report_on_the_other,
    round_settings_beat_the_report_on_both,
);

/// The report's trial `name` (`trial1`), read from its two files.
fn trial(name: &str) -> Trial {
    let sensor = format!("northstar/{name}_odometry_northstar.csv");
    let estimate = format!("northstar/{name}_kalman_groundtruth.csv");
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
    for ReportFigures {
        trial: name,
        kalman,
        odometry,
        sensor,
    } in REPORT_FIGURES
    {
        let s = summary(&trial(name), &Settings::default());
        let close = |a: f64, b: f64| (a - b).abs() < 0.0005;
        assert!(close(s.report.unwrap().mean, kalman), "{name}: {s:?}");
        assert!(close(s.odometry.mean, odometry), "{name}: {s:?}");
        assert!(close(s.sensor.unwrap().mean, sensor), "{name}: {s:?}");
    }
}

/// Tuning the process noise on one trial and running on the other: the filter still
/// beats the report's own estimate there.
fn settings_tuned_on_one_trial_beat_the_report_on_the_other() {
    let detector = Detector::default();
    let trials = REPORT_FIGURES.map(|r| trial(r.trial));
    for (tuned_on, tested_on) in [(0, 1), (1, 0)] {
        let base = Settings::default();
        let (settings, _) = tune(&trials[tuned_on], &base, &detector);
        let s = summary(&trials[tested_on], &settings);
        let report = REPORT_FIGURES[tested_on];
        assert!(
            s.filter.mean < report.kalman,
            "tuned on {}, on {}: {:.3} m, the report {}",
            REPORT_FIGURES[tuned_on].trial,
            report.trial,
            s.filter.mean,
            report.kalman
        );
    }
}

fn round_settings_beat_the_report_on_both() {
    for report in REPORT_FIGURES {
        let s = summary(&trial(report.trial), &Settings::default());
        assert!(s.filter.mean < report.kalman, "{}: {s:?}", report.trial);
    }
}
