//! The `estlab` command line, run as a user runs it.

use std::path::Path;
use std::process::{Command, Output};

fn estlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_estlab"))
        .args(args)
        .output()
        .unwrap()
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

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

#[test]
fn the_original_o3_run_prints_the_lab_figures() {
    let Some(data) = testdata::shared_data() else {
        return;
    };
    let dir = data.join("el2320/datasets");
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

#[test]
fn the_car_prints_its_summary_and_names_bad_parameters() {
    let out = estlab(&["car", "--seed", "4"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("error std over the second half: position "),
        "{text}"
    );

    let trusting = stdout(&estlab(&["car", "--seed", "4", "--Q", "1e-8"]));
    assert_ne!(trusting, text);

    let out = estlab(&["car", "--Q", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stderr(&out), "estlab: Q: must be a positive variance\n");
}
