//! `estlab mrclam` on MRCLAM data set 6 from the shared data, run as a user runs it.

use crate::command;

use command::{estlab, stderr, stdout};
use estlab::commands::mrclam::Report;

testdata::data_tests!(
    each_filter_localizes_the_robot_and_says_how_consistent_it_is,
    a_missing_data_set_or_a_wrong_knob_is_named,
);

fn json(args: &[&str]) -> Report {
    let data = testdata::shared_data();
    let data = data.to_str().unwrap();
    generated(&[&["--datasets", data], args].concat())
}

/// The report of `estlab mrclam --json` with `args` (a generated data set without
/// `--datasets`).
fn generated(args: &[&str]) -> Report {
    let out = estlab(&[&["mrclam", "--json"], args].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_str(&stdout(&out)).unwrap()
}

/// Without real data, a data set generated from a seed: its noise known, the filters
/// about consistent on it, unlike on the real one.
#[test]
fn a_generated_data_set_needs_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("recording.json");
    let report = generated(&[
        "--generate",
        "3",
        "--robot",
        "2",
        "--particles",
        "500",
        "--write-recording",
        file.to_str().unwrap(),
    ]);
    // The recording as the filters took it, which the page and the NumPy benchmark read.
    let recording: labs::mrclam::learn::Learned =
        serde_json::from_slice(&std::fs::read(&file).unwrap()).unwrap();
    assert_eq!(recording.run.steps.len(), report.steps);
    assert_eq!(recording.noise, report.noise);
    assert_eq!(recording.posts.len(), 15);
    assert_eq!(report.dataset, "generated from seed 3");
    assert!(
        (5990..=6001).contains(&report.steps),
        "{} steps",
        report.steps
    );
    for f in &report.filters {
        let c = &f.consistency;
        assert!(c.errors.rms < report.dead_reckoning.rms, "{f:?}");
        assert!(c.inside_three_sigma > 0.9, "{f:?}");
    }
    let out = estlab(&["mrclam", "--generate", "3", "--robot", "4"]);
    assert!(
        stderr(&out).contains("--robot 4: a generated data set has robots 1 to 3"),
        "{}",
        stderr(&out)
    );
    let out = estlab(&["mrclam", "--generate", "3", "--dataset", "6"]);
    assert!(
        stderr(&out).contains("'--generate <GENERATE>' cannot be used with '--dataset <DATASET>'"),
        "{}",
        stderr(&out)
    );
}

fn each_filter_localizes_the_robot_and_says_how_consistent_it_is() {
    let report = json(&["--robot", "2", "--particles", "300", "--seed", "4"]);
    assert_eq!(report.dataset, "MRCLAM data set 6");
    assert_eq!((report.robot, report.steps), (2, 45_001));
    let names: Vec<&str> = report.filters.iter().map(|f| f.filter.as_str()).collect();
    assert_eq!(names, ["EKF", "UKF", "particle filter"]);
    assert!(report.dead_reckoning.rms > 2.0);
    for f in &report.filters {
        let c = &f.consistency;
        assert!(c.errors.rms < 0.3, "{f:?}");
        assert!(c.inside_three_sigma < 0.9 && c.nees > 3.0, "{f:?}");
        assert!(f.readings.used > 2500, "{f:?}");
    }
    // The one knob: trusting the camera a hundred times less leaves the EKF nearer
    // its odometry.
    let wary = json(&["--robot", "2", "--filter", "ekf", "--rho", "100"]);
    assert_eq!(wary.filters.len(), 1);
    assert_eq!(
        wary.noise, report.noise,
        "the learned noise does not depend on rho"
    );
    assert!(wary.filters[0].consistency.errors.rms > report.filters[0].consistency.errors.rms);

    let data = testdata::shared_data();
    let out = estlab(&[
        "mrclam",
        "--datasets",
        data.to_str().unwrap(),
        "--filter",
        "ukf",
        "--learn-noise",
    ]);
    let text = stdout(&out);
    for line in [
        "MRCLAM data set 6, robot 1:",
        "Dead reckoning",
        "Learned noise: alpha = ",
        "UKF ",
    ] {
        assert!(text.contains(line), "no '{line}' in:\n{text}");
    }
}

fn a_missing_data_set_or_a_wrong_knob_is_named() {
    let data = testdata::shared_data();
    let data = data.to_str().unwrap();
    let out = estlab(&["mrclam", "--datasets", data, "--dataset", "9"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("MRCLAM_Dataset9: no such folder"),
        "{}",
        stderr(&out)
    );
    let out = estlab(&["mrclam", "--datasets", data, "--robot", "5"]);
    assert!(
        stderr(&out).contains("Robot5_Odometry.dat"),
        "{}",
        stderr(&out)
    );
    let out = estlab(&["mrclam", "--datasets", data, "--rho", "0"]);
    assert!(
        stderr(&out).contains("rho: a positive number"),
        "{}",
        stderr(&out)
    );
}
