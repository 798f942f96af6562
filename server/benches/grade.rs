//! Grading one whole submission as the server does it (`estlab grade`, which starts the
//! same sandbox worker process): the plan from the seed, every function suite and every
//! data-set run of the correct student file, the comparison; on V8 over the whole data
//! sets, and on QuickJS over their first readings. Run with `cargo bench -p estlab
//! --bench grade`; the budget (DESIGN.md) is 1 s.
//!
//! `cargo test --all-targets` (as `scripts/test` runs it) runs it once as a test, which
//! asserts only that `estlab grade` exits with 0, as it does whatever the score: the
//! grades themselves are checked in `server/tests/grade.rs`, and no time is asserted.

use criterion::{Criterion, criterion_group, criterion_main};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn grade(c: &mut Criterion) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/student/correct.js");
    let mut group = c.benchmark_group("grade");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(15));
    for (name, args) in [
        ("correct.js on V8, whole data sets", vec!["--seed", "1"]),
        (
            "correct.js on QuickJS, first readings",
            vec!["--seed", "1", "--javascript", "quickjs"],
        ),
        (
            "correct.js on V8, a student's variant",
            vec!["--student", "alice"],
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let output = Command::new(env!("CARGO_BIN_EXE_estlab"))
                    .arg("grade")
                    .arg(&file)
                    .args(&args)
                    .output()
                    .expect("estlab grade runs");
                assert!(output.status.success(), "estlab grade failed");
                output
            })
        });
    }
    group.finish();
}

criterion_group!(benches, grade);
criterion_main!(benches);
