//! Whole runs of the three filters over robot 1 of MRCLAM data set 6 (from
//! `ESTLAB_SHARED_DATA`: about 770 s, 38,594 steps at 50 Hz), the particle filter with
//! 2,000 particles; and the noise learned from the robot's recording.
//!
//! `cargo test --all-targets` runs each benchmark once as a test, which shows only that
//! every benchmarked call completes: results are checked by `labs/tests/mrclam_dataset6.rs`,
//! and no time is asserted. Without the shared data there is nothing to run, with a note.

use criterion::{Criterion, criterion_group, criterion_main};
use labs::mrclam::ekf::Ekf;
use labs::mrclam::format::{parse_robot, parse_world};
use labs::mrclam::grid::Run;
use labs::mrclam::particle::{ParticleFilter, Settings};
use labs::mrclam::ukf::Ukf;
use labs::mrclam::{Robot, World, learn, run};
use labs::rng::Rng;
use std::hint::black_box;

const DIR: &str = "mrclam/MRCLAM_Dataset6";

fn robot_one() -> Option<(Robot, World)> {
    let file = |name: &str| {
        let path = format!("{DIR}/{name}");
        testdata::read_if_present(&path).map(|text| (text, path))
    };
    let [odometry, measurements, truth, posts, barcodes] = [
        "Robot1_Odometry.dat",
        "Robot1_Measurement.dat",
        "Robot1_Groundtruth.dat",
        "Landmark_Groundtruth.dat",
        "Barcodes.dat",
    ]
    .map(file);
    fn text(file: &Option<(String, String)>) -> Option<(&str, &str)> {
        file.as_ref()
            .map(|(text, path)| (text.as_str(), path.as_str()))
    }
    let robot = parse_robot(text(&odometry)?, text(&measurements)?, text(&truth)?).unwrap();
    let world = parse_world(text(&posts)?, text(&barcodes)?).unwrap();
    Some((robot, world))
}

fn mrclam(c: &mut Criterion) {
    let Some((robot, world)) = robot_one() else {
        return;
    };
    let grid = Run::new(&robot, &world).unwrap();
    let noise = learn::noise(&robot, &world, &grid).unwrap();
    let start = run::start(&grid);
    let mut group = c.benchmark_group("mrclam robot 1");
    group.sample_size(10);
    group.bench_function("learn the noise", |b| {
        b.iter(|| learn::noise(black_box(&robot), &world, &grid))
    });
    group.bench_function("EKF, whole run", |b| {
        b.iter(|| run::filter(black_box(&grid), &mut Ekf::new(start, noise)))
    });
    group.bench_function("UKF, whole run", |b| {
        b.iter(|| run::filter(black_box(&grid), &mut Ukf::new(start, noise)))
    });
    group.bench_function("particle filter (2,000), whole run", |b| {
        b.iter(|| {
            let mut pf = ParticleFilter::new(start, noise, Settings::default(), Rng::new(1));
            run::filter(black_box(&grid), &mut pf)
        })
    });
    group.finish();
}

criterion_group!(benches, mrclam);
criterion_main!(benches);
