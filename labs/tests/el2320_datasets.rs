//! The reference filter reaches the lab's published error bounds on the three original
//! data sets, with the lab's settings.

use labs::angle::wrap;
use labs::dataset::{Dataset, parse_map, parse_sensor_log};
use labs::ekf::{Run, Settings, UpdateMode, observation_model, run};

testdata::data_tests!(
    o3_is_within_one_centimetre,
    pb_10_rejects_its_outliers_and_is_within_six_centimetres,
    pb_40_needs_the_batch_update,
);

fn load(sensor: &str, map: &str) -> Dataset {
    let map_text = testdata::read(&format!("el2320/datasets/{map}"));
    let sensor_text = testdata::read(&format!("el2320/datasets/{sensor}"));
    let map = parse_map(&map_text, map).unwrap();
    let log = parse_sensor_log(&sensor_text, sensor, &map).unwrap();
    Dataset { map, log }
}

fn mae(run: &Run) -> [f64; 3] {
    run.summary.mean_absolute_error.into()
}

fn with_mode(settings: Settings, mode: UpdateMode) -> Settings {
    Settings { mode, ..settings }
}

fn o3_is_within_one_centimetre() {
    let data = load("so_o3_ie.txt", "map_o3.txt");
    for mode in [UpdateMode::Sequential, UpdateMode::Batch] {
        let run = run(&data, &with_mode(Settings::lab_o3(), mode)).unwrap();
        eprintln!("o3 {mode:?}: {:?}", run.summary);
        assert!(
            mae(&run).iter().all(|&e| e < 0.01),
            "{mode:?}: {:?}",
            mae(&run)
        );
    }
}

fn pb_10_rejects_its_outliers_and_is_within_six_centimetres() {
    let data = load("so_pb_10_outlier.txt", "map_pent_big_10.txt");
    // How far each reading is from what the true pose sees of the landmark that made it:
    // the file's noise has a standard deviation of 0.2 (m and rad), its outliers are
    // far beyond.
    let offsets: Vec<(f64, f64)> = data
        .log
        .steps
        .iter()
        .flat_map(|step| {
            step.readings.iter().map(|reading| {
                let landmark = data.map.landmarks()[reading.landmark].position;
                let z_hat = observation_model(&step.truth, &landmark);
                (
                    (reading.z.x - z_hat.x).abs(),
                    wrap(reading.z.y - z_hat.y).abs(),
                )
            })
        })
        .collect();
    let beyond = |(range, bearing): (f64, f64), limit: f64| range > limit || bearing > limit;
    let gross = offsets.iter().filter(|&&o| beyond(o, 1.0)).count();
    assert_eq!(gross, 54, "readings more than 1 m or 1 rad off");

    let mut rejected_by_mode = Vec::new();
    for mode in [UpdateMode::Sequential, UpdateMode::Batch] {
        let run = run(&data, &with_mode(Settings::lab_outliers(), mode)).unwrap();
        eprintln!("pb_10 {mode:?}: {:?}", run.summary);
        assert!(
            mae(&run).iter().all(|&e| e < 0.06),
            "{mode:?}: {:?}",
            mae(&run)
        );
        assert_eq!(run.readings.len(), offsets.len());
        let rejected: Vec<usize> = (0..offsets.len())
            .filter(|&i| run.readings[i].outlier)
            .collect();
        assert_eq!(run.summary.rejected, rejected.len(), "{mode:?}");
        assert_eq!(rejected.len(), 57, "{mode:?}");
        // Every gross outlier is rejected, and nothing within 3 sigma of the truth is.
        for (i, &offset) in offsets.iter().enumerate() {
            if beyond(offset, 1.0) {
                assert!(
                    rejected.contains(&i),
                    "{mode:?}: reading {i} {offset:?} accepted"
                );
            }
            if !beyond(offset, 0.6) {
                assert!(
                    !rejected.contains(&i),
                    "{mode:?}: reading {i} {offset:?} rejected"
                );
            }
        }
        rejected_by_mode.push(rejected);
    }
    assert_eq!(
        rejected_by_mode[0], rejected_by_mode[1],
        "sequential vs batch"
    );
}

fn pb_40_needs_the_batch_update() {
    let data = load("so_pb_40_no.txt", "map_pent_big_40.txt");
    let batch = run(&data, &Settings::lab_no_odometry()).unwrap();
    let sequential = run(
        &data,
        &with_mode(Settings::lab_no_odometry(), UpdateMode::Sequential),
    )
    .unwrap();
    eprintln!(
        "pb_40 batch: {:?}\npb_40 sequential: {:?}",
        batch.summary, sequential.summary
    );
    assert!(
        mae(&batch).iter().all(|&e| e < 0.1),
        "batch: {:?}",
        mae(&batch)
    );
    // "Clearly worse": the sequential update's position error at least ten times the batch's.
    let (b, s) = (mae(&batch), mae(&sequential));
    assert!(
        s[0] + s[1] >= 10.0 * (b[0] + b[1]),
        "sequential {s:?} vs batch {b:?}"
    );
}
