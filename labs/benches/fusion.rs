//! Whole runs of the fusion filter over generated trials and over the Northstar report's
//! two trials (from `ESTLAB_SHARED_DATA`), a trial generated, and the process-noise grid
//! search.
//!
//! `cargo test --all-targets` runs each benchmark once as a test, which shows only that
//! every benchmarked call completes: results are checked by the tests in `labs/tests/`,
//! and no time is asserted. Without the shared data the report's trials are left out,
//! with a note.

use criterion::{Criterion, criterion_group, criterion_main};
use labs::fusion::{Detector, Settings, Trial, TrialParams, generate, run, tune};
use std::hint::black_box;

fn report_trial(n: u32) -> Option<Trial> {
    let sensor = format!("northstar/trial{n}_odometry_northstar.csv");
    let estimate = format!("northstar/trial{n}_kalman_groundtruth.csv");
    let sensor_text = testdata::read_if_present(&sensor)?;
    let estimate_text = testdata::read_if_present(&estimate)?;
    Some(Trial::from_report((&sensor_text, &sensor), (&estimate_text, &estimate)).unwrap())
}

fn fusion(c: &mut Criterion) {
    let detector = Detector::default();
    let settings = Settings::default();
    let mut group = c.benchmark_group("fusion");
    let generated = generate(&TrialParams::default()).unwrap();
    let mut trials = vec![("generated seed 1".to_owned(), generated)];
    for n in [1, 2] {
        if let Some(trial) = report_trial(n) {
            trials.push((format!("report trial {n}"), trial));
        }
    }
    for (name, trial) in &trials {
        group.bench_function(format!("whole run, {name}"), |b| {
            b.iter(|| run(black_box(trial), &settings, &detector))
        });
    }
    group.bench_function("generate a trial, seed 1", |b| {
        b.iter(|| generate(black_box(&TrialParams::default())))
    });
    group.bench_function("tune on generated seed 1 (36 runs)", |b| {
        b.iter(|| tune(black_box(&trials[0].1), &settings, &detector))
    });
    group.finish();
}

criterion_group!(benches, fusion);
criterion_main!(benches);
