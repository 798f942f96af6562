//! `estlab fusion` and the real data sets of `--datasets`, run as a user runs them.

use crate::command;

use command::{estlab, stderr, stdout};
use estlab::datasets::Datasets;
use labs::fusion::{Settings, Summary};
use serde::Deserialize;

#[derive(Deserialize)]
struct Report {
    settings: Settings,
    summary: Summary,
}

fn json(args: &[&str]) -> Report {
    let out = estlab(&[&["fusion", "--json"], args].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_str(&stdout(&out)).unwrap()
}

#[test]
fn a_generated_trial_is_fused_and_its_file_gives_the_same_figures() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("trial.csv");
    let file = file.to_str().unwrap();
    let generated = json(&["--seed", "4", "--waypoints", "6", "--write-trial", file]);
    let s = &generated.summary;
    assert!(s.filter.mean < s.odometry.mean && s.filter.mean < s.sensor.unwrap().mean);
    assert_eq!(generated.settings, Settings::default());
    // The file holds six decimals: the figures agree to about that.
    let read = json(&["--trial", file]);
    assert_eq!(read.summary.filter.steps, s.filter.steps);
    assert!((read.summary.filter.mean - s.filter.mean).abs() < 1e-4);
    assert!((read.summary.odometry.mean - s.odometry.mean).abs() < 1e-5);

    let out = estlab(&["fusion", "--seed", "4", "--waypoints", "6"]);
    let text = stdout(&out);
    for line in [
        "trial: generated (seed 4, 6 waypoints)",
        "filter ",
        "odometry ",
        "sensor alone ",
    ] {
        assert!(text.contains(line), "no '{line}' in:\n{text}");
    }
    assert!(
        text.contains("truth inside the 3-sigma ellipse: "),
        "{text}"
    );
}

#[test]
fn settings_change_the_filter_and_tuning_finds_better_ones() {
    let base = json(&["--seed", "2", "--waypoints", "5"]);
    let loose = json(&[
        "--seed",
        "2",
        "--waypoints",
        "5",
        "--process-xy",
        "0.5",
        "--gate",
        "1",
    ]);
    assert_eq!(loose.settings.process_xy, 0.5);
    assert_ne!(loose.summary.filter, base.summary.filter);
    let tuned = json(&["--seed", "2", "--waypoints", "5", "--tune"]);
    assert!(tuned.summary.filter.mean <= base.summary.filter.mean);
}

#[test]
fn bad_settings_and_files_are_named() {
    let out = estlab(&["fusion", "--gate", "1.5"]);
    assert!(!out.status.success());
    assert_eq!(
        stderr(&out),
        "estlab: gate: must be a probability in (0, 1]\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("broken.csv");
    std::fs::write(
        &file,
        "odom_x,odom_y,odom_theta,gt_x,gt_y,gt_theta\n0,0,0,0,0,0\n1,2,x,0,0,0\n",
    )
    .unwrap();
    let out = estlab(&["fusion", "--trial", file.to_str().unwrap()]);
    assert_eq!(
        stderr(&out),
        "estlab: broken.csv:3: odom_theta is 'x', which is not a finite number\n"
    );
    let out = estlab(&["fusion", "--report-trial", "trial1"]);
    assert!(stderr(&out).contains("--datasets"), "{}", stderr(&out));
    let out = estlab(&[
        "fusion",
        "--datasets",
        dir.path().join("none").to_str().unwrap(),
        "--report-trial",
        "trial1",
    ]);
    assert!(
        stderr(&out).ends_with("none: no such folder\n"),
        "{}",
        stderr(&out)
    );
    let out = estlab(&[
        "fusion",
        "--datasets",
        dir.path().to_str().unwrap(),
        "--report-trial",
        "trial1",
    ]);
    assert!(
        stderr(&out).ends_with("holds no trial of the report\n"),
        "{}",
        stderr(&out)
    );
}

testdata::data_tests!(the_reports_trials_come_from_the_datasets_folder);

fn the_reports_trials_come_from_the_datasets_folder() {
    let data = testdata::shared_data();
    let datasets = Datasets::load(&data).unwrap();
    let names: Vec<(&str, usize)> = datasets
        .northstar
        .iter()
        .map(|t| (t.name.as_str(), t.trial.steps.len()))
        .collect();
    assert_eq!(names, [("trial1", 33), ("trial2", 20)]);
    let dir = data.to_str().unwrap();
    for (name, report) in [("trial1", 0.139), ("trial2", 0.057)] {
        let r = json(&["--datasets", dir, "--report-trial", name]);
        let s = r.summary;
        assert!(
            (s.report.unwrap().mean - report).abs() < 0.0005,
            "{name}: {s:?}"
        );
        assert!(s.filter.mean < report, "{name}: {s:?}");
    }
    let out = estlab(&["fusion", "--datasets", dir, "--report-trial", "trial3"]);
    assert!(
        stderr(&out).ends_with("holds trial1, trial2\n"),
        "{}",
        stderr(&out)
    );
}
