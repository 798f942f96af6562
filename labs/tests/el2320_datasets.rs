//! The reference filter reaches the lab's published error bounds on the three original
//! data sets, with the lab's settings.

use labs::dataset::{Dataset, parse_map, parse_sensor_log};
use labs::ekf::{Run, Settings, UpdateMode, run};

fn load(sensor: &str, map: &str) -> Option<Dataset> {
    let map_text = testdata::read(&format!("el2320/datasets/{map}"))?;
    let sensor_text = testdata::read(&format!("el2320/datasets/{sensor}"))?;
    let map = parse_map(&map_text, map).unwrap();
    let log = parse_sensor_log(&sensor_text, sensor, &map).unwrap();
    Some(Dataset { map, log })
}

fn mae(run: &Run) -> [f64; 3] {
    run.summary.mean_absolute_error.into()
}

fn with_mode(settings: Settings, mode: UpdateMode) -> Settings {
    Settings { mode, ..settings }
}

#[test]
fn o3_is_within_one_centimetre() {
    let Some(data) = load("so_o3_ie.txt", "map_o3.txt") else {
        return;
    };
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

#[test]
fn pb_10_rejects_its_outliers_and_is_within_six_centimetres() {
    let Some(data) = load("so_pb_10_outlier.txt", "map_pent_big_10.txt") else {
        return;
    };
    for mode in [UpdateMode::Sequential, UpdateMode::Batch] {
        let run = run(&data, &with_mode(Settings::lab_outliers(), mode)).unwrap();
        eprintln!("pb_10 {mode:?}: {:?}", run.summary);
        assert!(
            mae(&run).iter().all(|&e| e < 0.06),
            "{mode:?}: {:?}",
            mae(&run)
        );
    }
}

#[test]
fn pb_40_needs_the_batch_update() {
    let Some(data) = load("so_pb_40_no.txt", "map_pent_big_40.txt") else {
        return;
    };
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
