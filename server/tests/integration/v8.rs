//! Students' JavaScript on V8, graded as the server grades it: Node in the operating
//! system's sandbox running the harness and the student's file
//! (`server/src/sandbox/native/harness.node.js`), a run in a process of its own, function
//! phases each in a fresh realm, on the whole data sets. The correct files score 1 and a
//! sample of classic mistakes is caught; on the same plan V8 and QuickJS give the same
//! results; and what a student might try is stopped with a precise message, while the
//! other tests of the file pass. Needs `bwrap` and Node (which `scripts/test` installs,
//! and the browser side requires).

use crate::student;

use estlab::sandbox::{Code, JavaScript, Sandbox};
use labs::exercises::ekf_localization;
use labs::grading::{GradeResult, Hidden, Plan, Reach, Status, Subject};
use labs::{Exercise, Language};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use student::catalogue::{Seeds, failing_alone, function_test, parallel, run_test};
use student::{CORRECT, Mistake};

const SEEDS: [Seeds; 2] = [(1, 0x5eed_0001), (2320, 9_876_543_210)];

fn sandbox() -> Sandbox {
    Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 2)
}

fn hidden((_, hidden): Seeds) -> Hidden {
    Hidden {
        cases: hidden,
        class: hidden,
    }
}

fn grade(exercise: Exercise, source: &str) -> GradeResult {
    let (seed, _) = SEEDS[0];
    sandbox().grade(
        exercise,
        Code::javascript(source),
        seed,
        Some(hidden(SEEDS[0])),
    )
}

#[test]
fn javascript_runs_on_v8_here() {
    sandbox().v8().expect("V8's sandbox starts on this machine");
    assert_eq!(sandbox().reach(Language::JavaScript), Reach::Whole);
    assert_eq!(sandbox().reach(Language::Python), Reach::Prefix);
    let quickjs = sandbox().with_javascript(JavaScript::QuickJs);
    assert_eq!(quickjs.reach(Language::JavaScript), Reach::Prefix);
}

#[test]
fn the_correct_files_score_1_on_the_whole_data_sets() {
    for files in [student::odometry::FILES, student::sensor_fusion::FILES] {
        files.check_the_correct_file(&SEEDS);
    }
    for seeds in SEEDS {
        let (seed, _) = seeds;
        let result = sandbox().grade(
            Exercise::EkfLocalization,
            Code::javascript(CORRECT),
            seed,
            Some(hidden(seeds)),
        );
        assert_eq!(result.score, 1.0, "{seeds:?}: {:?}", result.tests);
        // Every reading of each data set, as the reference reads it.
        let whole = ekf_localization::Plan::reaching(seed, Some(seeds.1), Reach::Whole);
        let prefix = ekf_localization::Plan::reaching(seed, Some(seeds.1), Reach::Prefix);
        for (run, cut) in whole.runs.iter().zip(&prefix.runs) {
            let readings = run.data.log.readings();
            assert!(readings > 2 * cut.data.log.readings(), "{}", run.name);
            let kind = run.name.split('/').next().unwrap_or_default();
            let test = run_test(&result, kind);
            let said = format!("over the whole {:.0} s ({readings} readings)", {
                run.data.log.steps.last().map_or(0.0, |step| step.t.round())
            });
            assert!(test.message.contains(&said), "{said}: {}", test.message);
        }
    }
}

#[test]
fn a_sample_of_mistakes_each_fails_its_function_with_its_hint() {
    for files in [student::odometry::FILES, student::sensor_fusion::FILES] {
        files.check_a_sample_of_mistakes(&SEEDS[..1]);
    }
    let mistakes: Vec<Mistake> = Mistake::all()
        .into_iter()
        .filter(|m| m.breaks != "init")
        .step_by(3)
        .collect();
    let results = parallel(&mistakes, |mistake| {
        grade(Exercise::EkfLocalization, &mistake.source().unwrap())
    });
    for (mistake, result) in mistakes.iter().zip(results) {
        let test = function_test(&result, &mistake.breaks);
        assert_eq!(test.status, Status::Failed, "{}", mistake.name);
        let hinted: Vec<serde_json::Value> = test
            .failures
            .iter()
            .filter_map(|failure| failure.hint.as_ref())
            .map(|hint| serde_json::to_value(hint.kind).unwrap())
            .collect();
        assert!(
            hinted.contains(&serde_json::json!(mistake.hint)),
            "{}: expected the hint {:?} in {hinted:?}: {}",
            mistake.name,
            mistake.hint,
            test.message
        );
    }
}

/// On the plan QuickJS grades (the first readings of each data set), V8 gives the same
/// result: the same score and the same tests, passed and failed alike, and the same
/// messages for every test passed (a filter a mistake has sent astray amplifies the
/// engines' last bits of `Math.sin` into other figures, and an engine's words for an
/// exception are its own).
#[test]
fn v8_and_quickjs_agree_on_the_same_plan() {
    let v8 = sandbox();
    let quickjs = sandbox().with_javascript(JavaScript::QuickJs);
    let mut files: Vec<(Exercise, String)> = vec![
        (Exercise::EkfLocalization, CORRECT.to_owned()),
        (
            Exercise::Odometry,
            student::odometry::FILES.correct.to_owned(),
        ),
        (
            Exercise::SensorFusion,
            student::sensor_fusion::FILES.correct.to_owned(),
        ),
    ];
    files.extend(
        Mistake::all()
            .into_iter()
            .step_by(4)
            .map(|m| (Exercise::EkfLocalization, m.source().unwrap())),
    );
    let (seed, _) = SEEDS[1];
    let compared = parallel(&files, |(exercise, source)| {
        let plan = Plan::new(*exercise, seed, Some(hidden(SEEDS[1])));
        let code = Code::javascript(source);
        (v8.grade_plan(&plan, code), quickjs.grade_plan(&plan, code))
    });
    for ((exercise, _), (on_v8, on_quickjs)) in files.iter().zip(compared) {
        assert_eq!(on_v8.score, on_quickjs.score, "{exercise:?}");
        for (a, b) in on_v8.tests.iter().zip(&on_quickjs.tests) {
            assert_eq!(
                (&a.subject, a.status),
                (&b.subject, b.status),
                "{exercise:?}"
            );
            if a.status == Status::Passed {
                assert_eq!(a.message, b.message, "{exercise:?}");
            }
        }
    }
}

/// The correct odometry file with `wheel_noise` replaced by `replacement` (a later
/// declaration wins), graded with hidden cases: what its test says, failing alone.
fn contained(replacement: &str, expected: &str) {
    let source = format!("{}\n\n{replacement}\n", student::odometry::FILES.correct);
    let message = failing_alone(&grade(Exercise::Odometry, &source), "wheel_noise");
    assert!(
        message.contains(expected),
        "expected {expected:?} in: {message}"
    );
}

#[test]
fn nothing_of_node_reaches_the_file() {
    contained(
        "function wheel_noise() { return require('fs').readdirSync('/'); }",
        "threw Error: require is not available here",
    );
    contained(
        "function wheel_noise() { return process.env; }",
        "threw Error: process is not available here",
    );
    // The context's global holds the built-ins alone, and their constructors are the
    // context's: code made from a string sees no more.
    contained(
        "function wheel_noise() { return Function('return typeof process + typeof require + typeof setTimeout')(); }",
        "got \"undefinedundefinedundefined\"",
    );
    contained(
        "function wheel_noise() { return globalThis.constructor.constructor('return process')(); }",
        "threw ReferenceError: process is not defined",
    );
}

#[test]
fn endless_work_sleep_memory_and_huge_answers_are_stopped_with_a_message() {
    contained(
        "function wheel_noise() { for (;;) {} }",
        "Stopped after 2 s, the time limit, while running wheel_noise/",
    );
    contained(
        "function wheel_noise() { Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0); }",
        "your code waited for 2 s without computing",
    );
    contained(
        "function wheel_noise() { const kept = []; for (;;) kept.push(new Array(1e5).fill(0.5)); }",
        "out of memory (the limit is 256 MB)",
    );
    contained(
        "function wheel_noise() { return new Array(1e6).fill(0); }",
        "returned more than 2000 values",
    );
}

/// Function phases go on in one process on V8, but never in one realm: what a file's top
/// level leaves on a built-in in one phase is not there in the next (a phase loads the
/// file at most twice: for its calls, then afresh for the calls again), neither on its
/// realm's `Math` nor on any other realm's it can reach (the Function constructor of its
/// global object's constructor is its own realm's).
#[test]
fn each_function_phase_has_a_realm_of_its_own() {
    let source = format!(
        "for (const math of new Set([Math, globalThis.constructor.constructor('return Math')()])) {{\n\
           math.loads = (math.loads || 0) + 1;\n\
           if (math.loads > 2) throw new Error('an earlier test left this behind');\n\
         }}\n{}",
        student::odometry::FILES.correct
    );
    let result = grade(Exercise::Odometry, &source);
    assert_eq!(result.score, 1.0, "{:?}", result.tests);
}

#[test]
fn a_loop_at_the_top_level_is_stopped_once() {
    let source = format!("{}\nfor (;;) {{}}\n", student::odometry::FILES.correct);
    let result = grade(Exercise::Odometry, &source);
    assert!(result.gradable, "{:?}", result.reason);
    for test in &result.tests {
        assert_eq!(test.status, Status::Failed);
        assert!(
            test.message.contains("the top level of your file"),
            "{}",
            test.message
        );
    }
}

/// A function that runs forever after hundreds of quick calls is named where it stopped:
/// the step and the function, told before each call.
#[test]
fn a_run_stopped_for_time_names_its_step_and_function() {
    let stalled = format!(
        "{CORRECT}\nlet calls = 0;\nconst quick = associate;\nassociate = function () {{ if (++calls > 500) for (;;) {{}} return quick.apply(null, arguments); }};\n"
    );
    let result = grade(Exercise::EkfLocalization, &stalled);
    let test = run_test(&result, "o3");
    assert_eq!(test.status, Status::Failed);
    assert!(
        test.message.contains("at time step") && test.message.contains(", associate"),
        "{}",
        test.message
    );
}

#[test]
fn a_file_scores_the_same_beside_busy_processes() {
    let alone = grade(Exercise::EkfLocalization, CORRECT);
    let busy = AtomicBool::new(true);
    let beside = std::thread::scope(|scope| {
        for _ in 0..4 {
            scope.spawn(|| {
                let mut x = 0u64;
                while busy.load(Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_mul(31).wrapping_add(7));
                }
            });
        }
        let result = grade(Exercise::EkfLocalization, CORRECT);
        busy.store(false, Ordering::Relaxed);
        result
    });
    assert_eq!(alone.score, 1.0);
    assert_eq!(beside.tests, alone.tests);
    let subjects = beside
        .tests
        .iter()
        .filter(|t| matches!(t.subject, Subject::Run(_)));
    assert_eq!(subjects.count(), 3);
}
