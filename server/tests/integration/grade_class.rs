//! `estlab grade-class` on a folder as an LMS download gives it: 200 files named by
//! student id, correct ones, every classic mistake, hostile ones, an empty file, a
//! binary file and two files of one student. Every file has its row with the right
//! outcome, and its JSON result beside the CSV with that student's variant.

use labs::grading::student_seed;
use serde::Deserialize;
use std::collections::HashMap;
use std::process::Command;

use crate::student;

use student::{CORRECT, CORRECT_ALT, Mistake, STARTER};

const FILES: usize = 200;

/// What a row of the CSV must say of a file.
enum Expect {
    Perfect,
    /// Graded, losing points on the tests whose names contain this function's name.
    Breaks(String),
    /// Graded with the score 0 (the starter file, an empty file).
    Zero,
    /// Graded, losing points (a hostile file).
    Loses,
    /// Not graded, the reason containing this.
    NotGraded(&'static str),
}

/// The result of one student as written beside the CSV.
#[derive(Deserialize)]
struct Result {
    seed: u64,
    score: f64,
}

#[test]
fn every_file_of_a_class_gets_its_row_with_the_right_score_or_reason() {
    let dir = tempfile::tempdir().unwrap();
    let class = dir.path().join("download");
    std::fs::create_dir(&class).unwrap();
    // Each file: the student's id, the extension, the bytes, and what its row must say.
    let mut files: Vec<(String, &str, Vec<u8>, Expect)> = Vec::new();
    let mut add = |id: &str, extension: &'static str, bytes: &[u8], expect: Expect| {
        files.push((id.to_string(), extension, bytes.to_vec(), expect));
    };
    add("correct", "js", CORRECT.as_bytes(), Expect::Perfect);
    add("correct-alt", "js", CORRECT_ALT.as_bytes(), Expect::Perfect);
    for mistake in &Mistake::all() {
        let source = mistake.source().unwrap();
        add(
            &mistake.name,
            "js",
            source.as_bytes(),
            Expect::Breaks(mistake.breaks.clone()),
        );
    }
    let looping = format!("{CORRECT}\nfunction predict(mu, sigma, u, R) {{ for (;;) {{}} }}\n");
    add("hostile-loop", "js", looping.as_bytes(), Expect::Loses);
    let bomb = format!(
        "{CORRECT}\nfunction update(mu_bar, sigma_bar, H, S, nu) {{ const a = []; for (;;) a.push(new Float64Array(1 << 20)); }}\n"
    );
    add("hostile-memory", "js", bomb.as_bytes(), Expect::Loses);
    add(
        "hostile-top-level",
        "js",
        b"throw new Error('no');",
        Expect::Zero,
    );
    add("empty", "js", b"", Expect::Zero);
    add(
        "binary",
        "js",
        &[0xff, 0xfe, 0x00, 0x9f, 0x92, 0x96],
        Expect::NotGraded("not UTF-8"),
    );
    add(
        "twice",
        "js",
        STARTER.as_bytes(),
        Expect::NotGraded("more than one file"),
    );
    add(
        "twice",
        "txt",
        STARTER.as_bytes(),
        Expect::NotGraded("more than one file"),
    );
    for n in 1..=FILES - 36 {
        let id = format!("u{n:03}");
        add(
            &id,
            "js",
            format!("// {id}\n{STARTER}").as_bytes(),
            Expect::Zero,
        );
    }

    assert_eq!(files.len(), FILES);
    let mut expected = Vec::new();
    for (id, extension, bytes, expect) in files {
        std::fs::write(class.join(format!("{id}.{extension}")), bytes).unwrap();
        expected.push((id, expect));
    }

    let out = dir.path().join("grades.csv");
    let run = Command::new(env!("CARGO_BIN_EXE_estlab"))
        .args(["grade-class", class.to_str().unwrap(), "--course", "el2320"])
        .args(["--out", out.to_str().unwrap(), "--parallel", "2"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    // Not a terminal here: one plain line per file, then the summary.
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with('[')).count(),
        FILES,
        "{stderr}"
    );
    assert!(
        stdout.starts_with(&format!("{FILES} files: {} graded", FILES - 3)),
        "{stdout}"
    );
    assert!(stdout.contains("0 not gradable, 3 not graded"), "{stdout}");

    let mut reader = csv::Reader::from_path(&out).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        &header[..7],
        [
            "id",
            "file",
            "status",
            "score",
            "points",
            "max_points",
            "reason"
        ]
    );
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<HashMap<String, String>> = reader
        .records()
        .map(|r| {
            header
                .iter()
                .cloned()
                .zip(r.unwrap().iter().map(String::from))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), FILES, "a row per file");
    let mut problems = Vec::new();
    for (id, expect) in &expected {
        let Some(row) = rows.iter().find(|r| &r["id"] == id) else {
            problems.push(format!("{id}: no row"));
            continue;
        };
        let score: f64 = row["score"].parse().unwrap_or(f64::NAN);
        let fine = match expect {
            Expect::Perfect => row["status"] == "graded" && score == 1.0,
            Expect::Zero => row["status"] == "graded" && score == 0.0,
            Expect::Loses => row["status"] == "graded" && score < 1.0,
            Expect::Breaks(function) => {
                // `init` is not a test of its own: its mistakes fail data-set runs.
                let tests = |test: &&String| {
                    test.contains(function.as_str())
                        || function == "init" && test.contains("data set")
                };
                row["status"] == "graded"
                    && score < 1.0
                    && header[7..]
                        .iter()
                        .filter(tests)
                        .any(|test| row[test].parse::<f64>().unwrap() < 10.0)
            }
            Expect::NotGraded(reason) => {
                row["status"] == "not graded" && row["reason"].contains(reason)
            }
        };
        if !fine {
            problems.push(format!("{id}: {row:?}"));
        }
        if row["status"] == "graded" {
            let text =
                std::fs::read_to_string(dir.path().join("grades").join(format!("{id}.json")))
                    .unwrap();
            let result: Result = serde_json::from_str(&text).unwrap();
            if result.seed != student_seed("el2320", id) || (result.score - score).abs() > 1e-4 {
                problems.push(format!(
                    "{id}: its JSON has seed {} and score {}",
                    result.seed, result.score
                ));
            }
        }
    }
    let _ = column;
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
