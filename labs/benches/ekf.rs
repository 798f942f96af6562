//! Whole runs of the reference EKF on the three original EL2320 data sets (from
//! `ESTLAB_SHARED_DATA`) and on generated ones, sequential and batch, and single steps.
//!
//! `cargo test --all-targets` (as `scripts/test` runs it) runs each benchmark once as a
//! test, which shows only that every benchmarked call completes without a panic: the
//! results are not checked here (the tests in `labs/tests/` do that) and no time is
//! asserted. Without the shared data the original data sets are left out, with a note.

use criterion::{Criterion, criterion_group, criterion_main};
use labs::dataset::{Dataset, Kind, parse_map, parse_sensor_log, simulate};
use labs::ekf::{
    Belief, Settings, UpdateMode, batch_associate, batch_update, lambda_m, most_likely, predict,
    run, update,
};
use nalgebra::Vector3;
use std::hint::black_box;

fn original(sensor: &str, map: &str) -> Option<Dataset> {
    let map_text = testdata::read_if_present(&format!("el2320/datasets/{map}"))?;
    let sensor_text = testdata::read_if_present(&format!("el2320/datasets/{sensor}"))?;
    let map = parse_map(&map_text, map).unwrap();
    let log = parse_sensor_log(&sensor_text, sensor, &map).unwrap();
    Some(Dataset { map, log })
}

fn whole_runs(c: &mut Criterion) {
    let mut group = c.benchmark_group("whole run");
    let originals = [
        ("so_o3_ie", "so_o3_ie.txt", "map_o3.txt", Kind::O3),
        (
            "so_pb_10_outlier",
            "so_pb_10_outlier.txt",
            "map_pent_big_10.txt",
            Kind::Outliers,
        ),
        (
            "so_pb_40_no",
            "so_pb_40_no.txt",
            "map_pent_big_40.txt",
            Kind::NoOdometry,
        ),
    ];
    for (name, sensor, map, kind) in originals {
        let generated = (
            format!("generated {} seed 1", kind.name()),
            Some(simulate(kind, 1)),
        );
        for (label, data) in [(name.to_owned(), original(sensor, map)), generated] {
            let Some(data) = data else { continue };
            for mode in [UpdateMode::Sequential, UpdateMode::Batch] {
                let settings = Settings {
                    mode,
                    ..kind.lab_settings()
                };
                group.bench_function(format!("{label} {mode:?}"), |b| {
                    b.iter(|| run(black_box(&data), black_box(&settings)).unwrap())
                });
            }
        }
    }
    group.finish();
}

fn single_steps(c: &mut Criterion) {
    let data = simulate(Kind::O3, 1);
    let settings = Kind::O3.lab_settings();
    // A belief and a time step from the middle of the run.
    let result = run(&data, &settings).unwrap();
    let k = data.log.steps.len() / 2;
    let belief = Belief::new(result.steps[k - 1].mu, result.steps[k - 1].sigma);
    let step = &data.log.steps[k];
    let z: Vec<_> = step.readings.iter().map(|r| r.z).collect();
    let lambda = lambda_m(settings.delta_m);
    let u = Vector3::new(0.09, 0.001, 0.002);
    let bar = predict(&belief, &u, &settings.r);
    let m = most_likely(&bar, &z[0], &data.map, lambda, &settings.q);

    let mut group = c.benchmark_group("single step");
    group.bench_function("predict", |b| {
        b.iter(|| predict(black_box(&belief), black_box(&u), &settings.r))
    });
    group.bench_function(
        format!("associate one reading, {} landmarks", data.map.len()),
        |b| {
            b.iter(|| {
                most_likely(
                    black_box(&bar),
                    black_box(&z[0]),
                    &data.map,
                    lambda,
                    &settings.q,
                )
            })
        },
    );
    group.bench_function("update one reading", |b| {
        b.iter(|| {
            update(
                black_box(&bar),
                &m.candidate.h,
                &m.candidate.s,
                &m.candidate.nu,
            )
        })
    });
    let matches = batch_associate(&bar, &z, &data.map, lambda, &settings.q);
    group.bench_function(format!("batch associate {} readings", z.len()), |b| {
        b.iter(|| {
            batch_associate(
                black_box(&bar),
                black_box(&z),
                &data.map,
                lambda,
                &settings.q,
            )
        })
    });
    group.bench_function(format!("batch update {} readings", z.len()), |b| {
        b.iter(|| {
            let readings = matches.iter().map(|m| (&m.candidate.h, &m.candidate.nu));
            batch_update(black_box(&bar), readings, &settings.q)
        })
    });
    group.finish();
}

fn parsing(c: &mut Criterion) {
    let (Some(map_text), Some(sensor_text)) = (
        testdata::read_if_present("el2320/datasets/map_o3.txt"),
        testdata::read_if_present("el2320/datasets/so_o3_ie.txt"),
    ) else {
        return;
    };
    let map = parse_map(&map_text, "map_o3.txt").unwrap();
    c.bench_function("parse so_o3_ie.txt", |b| {
        b.iter(|| parse_sensor_log(black_box(&sensor_text), "so_o3_ie.txt", &map).unwrap())
    });
}

criterion_group!(benches, whole_runs, single_steps, parsing);
criterion_main!(benches);
