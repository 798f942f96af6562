//! The `estlab` command line, run as a user runs it.

use crate::command;

use command::{estlab, stderr, stdout};
use labs::car::{CarParams, CarRun};
use std::path::Path;

/// The three numbers of a printed "(a, b, c)" line that starts with `label`.
fn triple(text: &str, label: &str) -> [f64; 3] {
    let line = text
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no '{label}' in:\n{text}"));
    let inner = &line[line.rfind('(').unwrap() + 1..line.rfind(')').unwrap()];
    let values: Vec<f64> = inner
        .split(',')
        .map(|v| v.trim().parse().unwrap())
        .collect();
    values.try_into().unwrap()
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn simulate_then_run_meets_the_bound() {
    let dir = tempfile::tempdir().unwrap();
    let out = estlab(&[
        "simulate",
        "--kind",
        "o3",
        "--seed",
        "3",
        "--out",
        path(dir.path()),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (sensor, map) = (
        dir.path().join("so_o3_3.txt"),
        dir.path().join("map_o3_3.txt"),
    );
    assert_eq!(
        stdout(&out),
        format!("{}\n{}\n", map.display(), sensor.display())
    );

    let out = estlab(&["run", path(&sensor), path(&map)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        triple(&text, "mean absolute error")
            .iter()
            .all(|&e| e < 0.01),
        "{text}"
    );
    assert!(
        text.contains("sequential update") && text.contains("rejected readings: "),
        "{text}"
    );

    let out = estlab(&["run", path(&sensor), path(&map), "--batch", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["settings"]["mode"], "batch");
    let steps = json["steps"].as_array().unwrap().len();
    assert_eq!(json["summary"]["steps"].as_u64().unwrap() as usize, steps);
}

testdata::data_tests!(the_original_o3_run_prints_the_lab_figures);

fn the_original_o3_run_prints_the_lab_figures() {
    let dir = testdata::shared_data().join("el2320/datasets");
    let out = estlab(&[
        "run",
        path(&dir.join("so_o3_ie.txt")),
        path(&dir.join("map_o3.txt")),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let mae = triple(&text, "mean absolute error");
    for (got, expected) in mae.iter().zip([0.003173, 0.003925, 0.002562]) {
        assert!((got - expected).abs() < 1e-6, "{text}");
    }
    assert!(text.contains("rejected readings: 1 of 5462"), "{text}");

    let out = estlab(&[
        "run",
        path(&dir.join("so_pb_40_no.txt")),
        path(&dir.join("map_pent_big_40.txt")),
        "--batch",
        "--R",
        "1,1,1",
        "--Q",
        "0.01,0.01",
        "--delta-m",
        "1",
    ]);
    let text = stdout(&out);
    assert!(
        triple(&text, "mean absolute error")
            .iter()
            .all(|&e| e < 0.1),
        "{text}"
    );
    assert!(text.contains("Lambda_M = inf"), "{text}");
}

#[test]
fn a_broken_file_is_named_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("map.txt");
    let sensor = dir.path().join("so_broken.txt");
    std::fs::write(&map, "1 0 5\n2 5 0\n").unwrap();
    std::fs::write(
        &sensor,
        "0 0 0 0 0 0 0 0 0 1 1 0.1 5\n0.2 0 0 0 3 3 0 0 0 2 1 0.1 5 2\n",
    )
    .unwrap();
    let out = estlab(&["run", path(&sensor), path(&map)]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "estlab: so_broken.txt:2: n = 2 readings (id bearing range each) need 16 values on the line, found 14: reading 2 of 2 is incomplete\n"
    );

    let out = estlab(&["run", path(&dir.path().join("nothing.txt")), path(&map)]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("nothing.txt: No such file"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_flags_are_refused() {
    let out = estlab(&["run", "so.txt", "map.txt", "--R", "1,2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("expected 3 comma-separated numbers, got 2"),
        "{}",
        stderr(&out)
    );

    let out = estlab(&["simulate", "--kind", "indoor", "--out", "x"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("'indoor' is none of o3, outliers, no-odometry"),
        "{}",
        stderr(&out)
    );

    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("map.txt");
    std::fs::write(&map, "1 0 5\n").unwrap();
    std::fs::write(dir.path().join("so.txt"), "0 0 0 0 0 0 0 0 0 0\n").unwrap();
    let out = estlab(&[
        "run",
        path(&dir.path().join("so.txt")),
        path(&map),
        "--delta-m",
        "1.5",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        "estlab: delta_M: must lie in (0, 1], got 1.5\n"
    );
}

/// Every number of a line that starts with `label`.
fn numbers_on(text: &str, label: &str) -> Vec<f64> {
    let line = text
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no '{label}' in:\n{text}"));
    line.split(|c: char| !(c.is_ascii_digit() || ".-+e".contains(c)))
        .filter_map(|word| word.parse().ok())
        .collect()
}

fn assert_close(got: &[f64], expected: &[f64], tolerance: f64, text: &str) {
    assert_eq!(
        got.len(),
        expected.len(),
        "{got:?} vs {expected:?} in:\n{text}"
    );
    for (g, e) in got.iter().zip(expected) {
        assert!(
            (g - e).abs() <= tolerance,
            "{got:?} vs {expected:?} in:\n{text}"
        );
    }
}

#[test]
fn the_car_runs_the_reference_with_every_flag_and_names_bad_parameters() {
    // Each flag set to a value of its own, so that one landing in the wrong field shows.
    let flags = [
        "car",
        "--seed",
        "4",
        "--steps",
        "60",
        "--dt",
        "0.05",
        "--u",
        "0.3",
        "--x0",
        "2,0.1",
        "--process-std",
        "0.02,0.2",
        "--measurement-std",
        "0.3",
        "--R",
        "1e-3,2e-2",
        "--Q",
        "0.05",
        "--mu0",
        "0.5,1",
        "--sigma0",
        "2,3",
    ];
    let params = CarParams {
        seed: 4,
        steps: 60,
        dt: 0.05,
        u: 0.3,
        x0: [2.0, 0.1],
        process_std: [0.02, 0.2],
        measurement_std: 0.3,
        r: [[1e-3, 0.0], [0.0, 2e-2]],
        q: 0.05,
        mu0: [0.5, 1.0],
        sigma0: [[2.0, 0.0], [0.0, 3.0]],
    };
    let reference = labs::car::run(&params).unwrap();

    let out = estlab(&[&flags[..], &["--json"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let printed: CarParams = serde_json::from_value(json["params"].clone()).unwrap();
    assert_eq!(printed, params);
    let run: CarRun = serde_json::from_value(json["run"].clone()).unwrap();
    assert_eq!(run, reference);

    // The text: the final step and the second half's error spread, to the 4 decimals
    // printed.
    let out = estlab(&flags);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let last = reference.steps.last().unwrap();
    let final_line = [
        last.mu.x,
        last.mu.y,
        last.truth.x,
        last.truth.y,
        last.sigma[(0, 0)].sqrt(),
        last.sigma[(1, 1)].sqrt(),
    ];
    assert_close(&numbers_on(&text, "final: "), &final_line, 5e-5, &text);
    assert_close(
        &numbers_on(&text, "error std over the second half: "),
        &reference.error_std,
        5e-5,
        &text,
    );

    // The lab's defaults with seed 4, pinned; then a filter that trusts the measurements
    // 10^6 times too much, which follows their noise: both errors spread wider.
    let text = stdout(&estlab(&["car", "--seed", "4"]));
    assert_close(
        &numbers_on(&text, "final: "),
        &[11.8958, 1.3185, 11.9121, 1.4067, 0.0607, 0.2154],
        0.0,
        &text,
    );
    assert_close(
        &numbers_on(&text, "error std over the second half: "),
        &[0.0411, 0.1591],
        0.0,
        &text,
    );
    let text = stdout(&estlab(&["car", "--seed", "4", "--Q", "1e-8"]));
    assert_close(
        &numbers_on(&text, "error std over the second half: "),
        &[0.0794, 0.6244],
        0.0,
        &text,
    );

    let out = estlab(&["car", "--Q", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stderr(&out), "estlab: Q: must be a positive variance\n");
}
