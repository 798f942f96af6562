//! The odometry exercise's student files graded as the server grades them: through the
//! real sandbox (a worker process of `estlab` running the harness in QuickJS), with hidden
//! cases and hidden paths, on several seeds.
//!
//! - `tests/student/odometry/correct.js` scores 1;
//! - the starter scores 0, and every test says what is not implemented;
//! - every classic mistake of `tests/student/odometry/mistakes.json` (the correct file with
//!   one function broken) fails the test of the function it breaks, every failing case of
//!   it with the mistake's hint and no other, passes the other functions' tests, and fails
//!   the path tests it breaks while passing the others.
//!
//! Gradings run in parallel, and the table-driven test collects every problem before
//! failing, so one run shows them all.

mod student;

use estlab::sandbox::Sandbox;
use labs::Exercise;
use labs::exercises::odometry::FUNCTIONS;
use labs::grading::{self, GradeResult, Status, Test};
use serde_json::json;
use std::path::PathBuf;
use std::thread;
use student::odometry::{CORRECT, Mistake, PATHS, STARTER};

/// The student seeds, each with the seed of its hidden cases and paths.
const SEEDS: [(u64, u64); 6] = [
    (1, 0x5eed_0001),
    (17, 4242),
    (2320, 9_876_543_210),
    (99, 1),
    (123_456_789, 31_337),
    (7, 2_718_281_828),
];

/// Grades `source` in a worker process, as the server does.
fn grade(source: &str, (seed, hidden): (u64, u64)) -> GradeResult {
    let sandbox = Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 1);
    let result = sandbox.grade(Exercise::Odometry, source, seed, Some(hidden));
    assert!(result.gradable, "seed {seed}: {:?}", result.reason);
    result
}

/// The test whose name starts with `prefix`.
fn test<'a>(result: &'a GradeResult, prefix: &str) -> &'a Test {
    result
        .tests
        .iter()
        .find(|t| t.name.starts_with(prefix))
        .unwrap_or_else(|| panic!("no test {prefix} in {:?}", names(result)))
}

fn names(result: &GradeResult) -> Vec<&str> {
    result.tests.iter().map(|t| t.name.as_str()).collect()
}

fn function_test<'a>(result: &'a GradeResult, function: &str) -> &'a Test {
    test(result, &format!("{function}:"))
}

fn path_test<'a>(result: &'a GradeResult, path: &str) -> &'a Test {
    test(result, &format!("{path} path:"))
}

/// `work` on every item, the items split among as many threads as there are cores;
/// results in order.
fn parallel<T: Sync, R: Send>(items: &[T], work: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = thread::available_parallelism().map_or(2, |n| n.get());
    let share = items.len().div_ceil(threads).max(1);
    thread::scope(|scope| {
        let workers: Vec<_> = items
            .chunks(share)
            .map(|part| scope.spawn(|| part.iter().map(&work).collect::<Vec<R>>()))
            .collect();
        workers
            .into_iter()
            .flat_map(|worker| worker.join().unwrap())
            .collect()
    })
}

#[test]
fn the_correct_file_scores_1_with_hidden_cases() {
    for (seeds, result) in SEEDS
        .iter()
        .zip(parallel(&SEEDS, |&seeds| grade(CORRECT, seeds)))
    {
        let failed: Vec<String> = result
            .tests
            .iter()
            .filter(|t| t.status != Status::Passed)
            .map(|t| format!("{}: {}", t.name, t.message))
            .collect();
        assert!(failed.is_empty(), "{seeds:?}:\n{}", failed.join("\n"));
        assert_eq!(result.score, 1.0);
        assert!(result.hidden_cases);
        assert_eq!(result.exercise, Exercise::Odometry);
        assert_eq!(
            result.tests.len(),
            FUNCTIONS.len() + PATHS.len(),
            "{:?}",
            names(&result)
        );
        for path in PATHS {
            assert!(path_test(&result, path).message.starts_with("Passed"));
        }
    }
}

#[test]
fn the_starter_scores_0_and_says_what_is_not_implemented() {
    let result = grade(STARTER, SEEDS[0]);
    assert_eq!(result.score, 0.0);
    for function in FUNCTIONS {
        let test = function_test(&result, function);
        assert_eq!(test.points, 0.0, "{}", test.name);
        assert!(
            test.message
                .contains(&format!("threw Error: {function}: not implemented")),
            "{}: {}",
            test.name,
            test.message
        );
    }
    for path in PATHS {
        let test = path_test(&result, path);
        assert_eq!(test.status, Status::Failed);
        // The loop stops at its first call, pose_jacobian's.
        assert!(
            test.message.contains(&format!(
                "{path}: at step 1, pose_jacobian: threw Error: pose_jacobian: not implemented"
            )),
            "{}",
            test.message
        );
    }
}

/// What is wrong with the grading of `mistake` on one seed, if anything.
fn problems(mistake: &Mistake, seeds: (u64, u64)) -> Vec<String> {
    let source = match mistake.source() {
        Ok(source) => source,
        Err(e) => return vec![e],
    };
    let result = grade(&source, seeds);
    let name = format!("{} on {seeds:?}", mistake.name);
    let mut problems = Vec::new();
    let hint: grading::HintKind = serde_json::from_value(json!(mistake.hint))
        .unwrap_or_else(|e| panic!("{}: no hint {:?}: {e}", mistake.name, mistake.hint));
    for function in FUNCTIONS {
        let test = function_test(&result, function);
        if *function != mistake.breaks {
            if test.status != Status::Passed {
                problems.push(format!("{name}: fails {}: {}", test.name, test.message));
            }
            continue;
        }
        if test.status != Status::Failed {
            problems.push(format!("{name}: passes {}", test.name));
            continue;
        }
        let kinds: Vec<Option<grading::HintKind>> = test
            .failures
            .iter()
            .map(|f| f.hint.as_ref().map(|h| h.kind))
            .collect();
        let unhinted = |failure: &grading::Failure| {
            failure.hint.is_none() && mistake.unhinted.contains(&failure.note)
        };
        let wrong = test
            .failures
            .iter()
            .any(|f| f.hint.as_ref().map(|h| h.kind) != Some(hint) && !unhinted(f));
        if kinds.iter().all(Option::is_none) || wrong {
            problems.push(format!(
                "{name}: {} gives the hints {kinds:?}, not {}: {}",
                test.name, mistake.hint, test.message
            ));
        }
        // The message says each hint as its case gives it (a wrong shape says which).
        if let Some(unsaid) = test
            .failures
            .iter()
            .filter_map(|f| f.hint.as_ref())
            .find(|h| !test.message.contains(&format!("Hint: {}", h.text)))
        {
            problems.push(format!(
                "{name}: {} does not say the hint {:?}: {}",
                test.name, unsaid.text, test.message
            ));
        }
    }
    for path in PATHS {
        let test = path_test(&result, path);
        let failed = test.status == Status::Failed;
        if failed != mistake.breaks_path(path) {
            problems.push(format!(
                "{name}: the {path} path {}: {}",
                if failed { "fails" } else { "passes" },
                test.message
            ));
        }
        if failed
            && !test.message.contains(&format!(
                "These functions fail their own tests: {}.",
                mistake.breaks
            ))
        {
            problems.push(format!(
                "{name}: the {path} path does not name {}: {}",
                mistake.breaks, test.message
            ));
        }
    }
    problems
}

#[test]
fn every_mistake_fails_its_function_with_its_hint_and_the_paths_it_breaks() {
    let mistakes = Mistake::all();
    assert!(mistakes.len() >= 12, "{} mistakes", mistakes.len());
    for function in FUNCTIONS {
        assert!(
            mistakes.iter().any(|m| m.breaks == *function),
            "no mistake breaks {function}"
        );
    }
    let work: Vec<(&Mistake, (u64, u64))> = mistakes
        .iter()
        .flat_map(|m| SEEDS.iter().map(move |&seeds| (m, seeds)))
        .collect();
    let found: Vec<String> = parallel(&work, |(mistake, seeds)| problems(mistake, *seeds))
        .into_iter()
        .flatten()
        .collect();
    eprintln!(
        "{} mistakes graded on {} seeds each",
        mistakes.len(),
        SEEDS.len()
    );
    assert!(found.is_empty(), "{}", found.join("\n"));
}
