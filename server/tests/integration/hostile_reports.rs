//! Hostile student files (`tests/student/hostile/`, each put after the EKF exercise's
//! correct.js) that once broke the harness's report or were blamed on the sandbox, graded
//! through the real sandbox (a worker process of `estlab` running QuickJS, as the server
//! grades where V8's sandbox does not start; `v8.rs` holds V8 to the same):
//!
//! - a text clipped in the middle of an emoji no longer spoils the report, and the cases
//!   that pass keep their points;
//! - whatever the student's code throws or returns (a Proxy whose traps throw, null, a
//!   top-level `return`) the harness describes, and the host never says "the sandbox
//!   failed" nor takes the student's text for its own causes;
//! - running out of memory is named as such, from the engine's state;
//! - a text read from the student's values is read once and bounded as it is built;
//! - a single built-in call that stalls is ended by the watchdog, which names the phase
//!   and the call.

use crate::student;

use estlab::sandbox::{Code, JavaScript, Sandbox};
use labs::Exercise;
use labs::exercises::ekf_localization::FUNCTIONS;
use labs::grading::{GradeResult, Status, Test};
use std::path::PathBuf;
use student::CORRECT;

/// The runs of the EKF exercise's loop, as their tests and messages name them.
const RUNS: [&str; 3] = ["o3/sequential", "outliers/sequential", "no-odometry/batch"];

/// correct.js with the hostile file `name` after it, graded in a worker process.
fn grade(name: &str) -> (String, GradeResult) {
    let path = format!(
        "{}/../tests/student/hostile/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    let hostile = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let source = format!("{CORRECT}\n{hostile}");
    let sandbox = Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 2)
        .with_javascript(JavaScript::QuickJs);
    let result = sandbox.grade(
        Exercise::EkfLocalization,
        Code::javascript(&source),
        2320,
        None,
    );
    assert!(result.gradable, "{name}: not gradable: {:?}", result.reason);
    (source, result)
}

/// The line of `source` (numbered from 1, as an editor does) that contains `text`.
fn line_of(source: &str, text: &str) -> usize {
    source
        .lines()
        .position(|line| line.contains(text))
        .unwrap_or_else(|| panic!("no line with {text:?}"))
        + 1
}

fn function_test<'a>(result: &'a GradeResult, function: &str) -> &'a Test {
    find(result, &format!("{function}:"))
}

fn run_test<'a>(result: &'a GradeResult, run: &str) -> &'a Test {
    let data_set = run.split('/').next().unwrap();
    find(result, &format!("{data_set} data set"))
}

fn find<'a>(result: &'a GradeResult, prefix: &str) -> &'a Test {
    result
        .tests
        .iter()
        .find(|t| t.name.starts_with(prefix))
        .unwrap_or_else(|| panic!("no test {prefix}"))
}

/// Every function but those of `broken` passes its test with all its points.
fn others_pass(result: &GradeResult, broken: &[&str]) {
    for function in FUNCTIONS.iter().filter(|f| !broken.contains(f)) {
        let test = function_test(result, function);
        assert_eq!(
            test.status,
            Status::Passed,
            "{}: {}",
            test.name,
            test.message
        );
    }
}

#[track_caller]
fn says(test: &Test, part: &str) {
    assert!(
        test.message.contains(part),
        "the test {} should say {part:?}; it says:\n{}",
        test.name,
        test.message
    );
}

#[track_caller]
fn does_not_say(test: &Test, part: &str) {
    assert!(
        !test.message.contains(part),
        "the test {} should not say {part:?}; it says:\n{}",
        test.name,
        test.message
    );
}

/// Item 8: a message clipped at 300 characters where an emoji's surrogate pair begins.
#[test]
fn a_message_clipped_inside_an_emoji_keeps_the_report_readable() {
    let (source, result) = grade("emoji-at-the-clip.js");
    let predict = function_test(&result, "predict");
    assert_eq!(predict.status, Status::Failed);
    assert!(
        predict.points > 0.0 && predict.points < predict.max_points,
        "the cases that pass keep their points: {} of {}: {}",
        predict.points,
        predict.max_points,
        predict.message
    );
    let line = line_of(&source, "'x'.repeat(299)");
    says(
        predict,
        &format!("threw Error: {}... (line {line})", "x".repeat(299)),
    );
    does_not_say(predict, "unreadable");
    does_not_say(predict, "\u{FFFD}");
    others_pass(&result, &["predict"]);
}

/// Item 9: a thrown Proxy whose getPrototypeOf trap throws the Proxy itself.
#[test]
fn a_thrown_proxy_whose_traps_throw_is_described_by_the_harness() {
    let (_, result) = grade("proxy-thrown.js");
    let update = function_test(&result, "update");
    says(update, "update/p1");
    says(update, "threw a value that is not an Error: {}");
    does_not_say(update, "sandbox");
    does_not_say(update, "0x");
    for run in &RUNS[..2] {
        says(
            run_test(&result, run),
            &format!("{run}: at time step 1, update: threw a value that is not an Error: {{}}"),
        );
    }
    others_pass(&result, &["update"]);
}

/// Item 9: a trap that throws an Error reading like the host's own words.
#[test]
fn a_thrown_text_does_not_forge_the_hosts_causes() {
    let (_, result) = grade("forges-stack-overflow.js");
    let observation_model = function_test(&result, "observation_model");
    // Through a Proxy the error's stack (an accessor of real errors) is not there, nor
    // its line.
    says(observation_model, "threw Error: recursion is fine\n");
    does_not_say(observation_model, "recursion too deep");
    does_not_say(observation_model, "sandbox");
    others_pass(
        &result,
        &["observation_model", "associate", "batch_associate"],
    );
}

/// Item 9: a `return` at the top level of the file, returning an object whose getter
/// throws "out of memory".
#[test]
fn a_return_at_the_top_level_is_said_to_be_one() {
    let (_, result) = grade("return-at-top-level.js");
    assert_eq!(result.score, 0.0);
    for test in &result.tests {
        says(
            test,
            "Your file returns at its top level: a return statement outside any function",
        );
        does_not_say(test, "out of memory");
        does_not_say(test, "sandbox");
    }
}

/// Item 9: a function that returns null is told so, not "not run".
#[test]
fn a_function_that_returns_null_is_told_what_it_returned() {
    let (_, result) = grade("returns-null.js");
    let predict = function_test(&result, "predict");
    assert_eq!(predict.status, Status::Failed);
    says(
        predict,
        "predict/p1 (a general step): output: expected \"an object with the fields mu_bar, sigma_bar\", got null",
    );
    does_not_say(predict, "not run");
    others_pass(&result, &["predict"]);
}

/// Item 9: running out of memory, caught by the student's code, which leaves the harness
/// none: named as such, from the engine's state, for the call that ran out.
#[test]
fn running_out_of_memory_is_named_as_such() {
    let (_, result) = grade("hoards-memory.js");
    let predict = function_test(&result, "predict");
    says(
        predict,
        "Stopped while running predict/p1: out of memory (the limit is 64 MB): far too much data allocated.",
    );
    for run in RUNS {
        let test = run_test(&result, run);
        says(
            test,
            &format!("{run}: Stopped while running {run}: at time step 1, predict: out of memory"),
        );
        does_not_say(test, "sandbox");
    }
    others_pass(&result, &["predict"]);
}

/// Item 10: an error's name that is a string when first read and a megabyte when read
/// again.
#[test]
fn a_thrown_value_is_read_once_and_its_text_bounded() {
    let (source, result) = grade("name-getter.js");
    let line = line_of(&source, "const error = new Error(message);");
    // batch_associate calls associate.
    let broken = [
        "predict",
        "update",
        "batch_update",
        "associate",
        "batch_associate",
    ];
    for function in broken {
        let test = function_test(&result, function);
        assert_eq!(test.status, Status::Failed, "{}", test.name);
        says(test, &format!("threw Error: shifty name (line {line})"));
        does_not_say(test, "64 MB");
    }
    others_pass(&result, &broken);
}

/// Item 11: one built-in call that stalls in predict: the watchdog names the phase and the
/// call it stalled in. (It ends the call within a second of CPU time without the engine
/// looking at its clock: see `sandbox::watchdog`.)
#[test]
fn a_stalled_call_is_named_by_the_watchdog() {
    let (_, result) = grade("stalls-in-predict.js");
    assert_eq!(result.score, 0.0);
    let message = &function_test(&result, "calculate_odometry").message;
    let tail = ": a single call ran for more than a second of CPU time where the time limit cannot interrupt it (a built-in function on huge data, such as indexOf on long strings?), and every test fails.";
    let named = message.lines().any(|line| {
        RUNS.iter().any(|run| {
            line == format!("Stopped while running {run}: at time step 1, predict{tail}")
        }) || (1..=12).any(|case| line == format!("Stopped while running predict/p{case}{tail}"))
    });
    assert!(
        named,
        "the message names no phase and call of predict:\n{message}"
    );
    for test in &result.tests {
        assert_eq!(test.status, Status::Failed, "{}", test.name);
        says(test, tail);
    }
}
