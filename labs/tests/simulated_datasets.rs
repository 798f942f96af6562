//! Generated data sets have the statistics of the originals, read back from their files
//! exactly, and meet the lab's bounds with the lab's settings.

use labs::angle::wrap;
use labs::dataset::{
    Dataset, Kind, parse_map, parse_sensor_log, simulate, write_map, write_sensor_log,
};
use labs::ekf::{Run, UpdateMode, run};

fn mae(run: &Run) -> [f64; 3] {
    run.summary.mean_absolute_error.into()
}

fn run_in(data: &Dataset, kind: Kind, mode: UpdateMode) -> Run {
    run(
        data,
        &labs::ekf::Settings {
            mode,
            ..kind.lab_settings()
        },
    )
    .unwrap()
}

#[test]
fn every_kind_meets_the_lab_bounds_for_the_first_five_seeds() {
    for seed in 1..=5 {
        for kind in [Kind::O3, Kind::Outliers] {
            let bound = if kind == Kind::O3 { 0.01 } else { 0.06 };
            let data = simulate(kind, seed);
            for mode in [UpdateMode::Sequential, UpdateMode::Batch] {
                let r = run_in(&data, kind, mode);
                assert!(
                    mae(&r).iter().all(|&e| e < bound),
                    "{kind:?} seed {seed} {mode:?}: {:?}",
                    mae(&r)
                );
            }
        }
        let data = simulate(Kind::NoOdometry, seed);
        let (b, s) = (
            mae(&run_in(&data, Kind::NoOdometry, UpdateMode::Batch)),
            mae(&run_in(&data, Kind::NoOdometry, UpdateMode::Sequential)),
        );
        assert!(
            b.iter().all(|&e| e < 0.1),
            "no-odometry seed {seed}: batch {b:?}"
        );
        assert!(
            s[0] + s[1] >= 10.0 * (b[0] + b[1]),
            "no-odometry seed {seed}: sequential {s:?} vs batch {b:?}"
        );
    }
}

/// Whether the sequential update loses track depends on the noise draws, on the
/// original file as on generated ones; with generated data it does most of the time.
#[test]
fn without_odometry_the_sequential_update_usually_diverges() {
    let diverged = (1..=20)
        .filter(|&seed| {
            let data = simulate(Kind::NoOdometry, seed);
            let b = mae(&run_in(&data, Kind::NoOdometry, UpdateMode::Batch));
            let s = mae(&run_in(&data, Kind::NoOdometry, UpdateMode::Sequential));
            s[0] + s[1] >= 10.0 * (b[0] + b[1])
        })
        .count();
    assert!(
        diverged >= 16,
        "the sequential update diverged on only {diverged} of 20 data sets"
    );
}

#[test]
fn the_same_seed_gives_the_same_data_set_and_another_seed_another() {
    for kind in Kind::ALL {
        assert_eq!(simulate(kind, 3), simulate(kind, 3));
        assert_ne!(
            simulate(kind, 3).log.steps[10].readings,
            simulate(kind, 4).log.steps[10].readings
        );
    }
}

#[test]
fn files_read_back_exactly() {
    for kind in Kind::ALL {
        let data = simulate(kind, 11);
        let map = parse_map(&write_map(&data.map), "map.txt").unwrap();
        let log = parse_sensor_log(&write_sensor_log(&data.log), "so.txt", &map).unwrap();
        assert_eq!(Dataset { map, log }, data, "{kind:?}");
    }
}

/// What the original files show, measured the same way on generated ones.
struct Statistics {
    dt: f64,
    duration: f64,
    path_length: f64,
    readings_per_step: (usize, usize),
    range_noise: f64,
    bearing_noise: f64,
    outlier_rate: f64,
    odometry_zero: bool,
}

fn statistics(data: &Dataset) -> Statistics {
    let steps = &data.log.steps;
    let landmarks = data.map.landmarks();
    let (mut range_errors, mut bearing_errors, mut outliers, mut readings) = (vec![], vec![], 0, 0);
    for step in steps {
        for reading in &step.readings {
            let d = landmarks[reading.landmark].position - step.truth.xy();
            let range_error = reading.z.x - d.norm();
            let bearing_error = wrap(reading.z.y - (d.y.atan2(d.x) - step.truth.z));
            readings += 1;
            if range_error.abs() > 1.0 || bearing_error.abs() > 1.0 {
                outliers += 1;
            } else {
                range_errors.push(range_error);
                bearing_errors.push(bearing_error);
            }
        }
    }
    let rms = |v: &[f64]| (v.iter().map(|e| e * e).sum::<f64>() / v.len() as f64).sqrt();
    let counts = steps.iter().map(|s| s.readings.len());
    Statistics {
        dt: steps[1].t - steps[0].t,
        duration: steps.last().unwrap().t,
        path_length: steps
            .windows(2)
            .map(|w| (w[1].truth.xy() - w[0].truth.xy()).norm())
            .sum(),
        readings_per_step: (counts.clone().min().unwrap(), counts.max().unwrap()),
        range_noise: rms(&range_errors),
        bearing_noise: rms(&bearing_errors),
        outlier_rate: outliers as f64 / readings as f64,
        odometry_zero: steps
            .iter()
            .all(|s| s.encoders.right == 0.0 && s.encoders.left == 0.0),
    }
}

#[test]
fn generated_data_sets_have_the_statistics_of_the_originals() {
    for seed in 1..=3 {
        // so_o3_ie: dt 0.2 s, 118 s, 55 m, 4-14 readings a step, noise 0.01, no outliers.
        let s = statistics(&simulate(Kind::O3, seed));
        assert_eq!(s.dt, 0.2);
        assert!((100.0..140.0).contains(&s.duration) && (45.0..65.0).contains(&s.path_length));
        assert!(
            s.readings_per_step.0 >= 3 && s.readings_per_step.1 <= 18,
            "{:?}",
            s.readings_per_step
        );
        assert!((s.range_noise - 0.01).abs() < 0.001 && (s.bearing_noise - 0.01).abs() < 0.001);
        assert!(s.outlier_rate == 0.0 && !s.odometry_zero);

        // so_pb_10_outlier: dt 0.2 s, 239 s, 115 m, 1-2 readings, noise 0.2, 2.7 % outliers.
        let s = statistics(&simulate(Kind::Outliers, seed));
        assert_eq!(s.dt, 0.2);
        assert!((220.0..270.0).contains(&s.duration) && (105.0..125.0).contains(&s.path_length));
        assert!(
            s.readings_per_step.0 >= 1 && s.readings_per_step.1 <= 2,
            "{:?}",
            s.readings_per_step
        );
        assert!((s.range_noise - 0.2).abs() < 0.02 && (s.bearing_noise - 0.2).abs() < 0.02);
        assert!(
            (0.015..0.045).contains(&s.outlier_rate) && !s.odometry_zero,
            "{}",
            s.outlier_rate
        );

        // so_pb_40_no: dt 1 s, 238 s, 115 m, 6-7 readings, noise 0.1, 3 % outliers, no odometry.
        let s = statistics(&simulate(Kind::NoOdometry, seed));
        assert_eq!(s.dt, 1.0);
        assert!((220.0..270.0).contains(&s.duration) && (105.0..125.0).contains(&s.path_length));
        assert!(
            s.readings_per_step.0 >= 5 && s.readings_per_step.1 <= 8,
            "{:?}",
            s.readings_per_step
        );
        assert!((s.range_noise - 0.1).abs() < 0.01 && (s.bearing_noise - 0.1).abs() < 0.01);
        assert!(
            (0.015..0.045).contains(&s.outlier_rate) && s.odometry_zero,
            "{}",
            s.outlier_rate
        );
    }
}
