//! The catalogue of classic mistakes (`tests/student/mistakes.json`) against the test
//! cases, over many seeds, with the student's code run in QuickJS by the same harness the
//! grader uses (`static/src/harness.js`), one function's cases at a time:
//!
//! - every mistake fails at least one case of its function in the variant of every seed
//!   (`init` mistakes are caught by the data-set runs, which `grade.rs` checks);
//! - `correct.js` fails no case of any seed, and neither does `correct-alt.js` (the same
//!   contract written another way: the likelihood itself, the Joseph form, another angle
//!   wrap) in every fourth seed;
//! - every mistake the lab's original fixture suite catches, the generated cases catch too
//!   (the fixtures come from the shared data, see `testdata`).
//!
//! `estlab grade` (in `grade.rs`) checks the hints on one seed; here thousands of phases
//! run in-process, which a full grading per seed would make far too slow.

use crate::student;

use labs::exercises::ekf_localization::{Case, FIXTURE_FILES, FUNCTIONS, generate, load_fixtures};
use labs::grading::{Contract, Tolerance};
use rquickjs::{CatchResultExt, Context, Function, Object, Runtime};
use serde_json::Value;
use std::collections::BTreeMap;
use std::thread;
use student::{CORRECT, CORRECT_ALT, Mistake};

const HARNESS: &str = include_str!("../../../static/src/harness.js");

/// The seeds every mistake must be caught in.
const SEEDS: u64 = 200;
/// Cases of each function in a student's variant (`grading::plan::CASES_PER_FUNCTION`).
const PER_FUNCTION: usize = 6;

/// The mistakes that break a function with cases of its own.
fn mistakes() -> Vec<(Mistake, String)> {
    Mistake::all()
        .into_iter()
        .filter(|m| m.breaks != "init")
        .map(|m| {
            let source = m.source().unwrap();
            (m, source)
        })
        .collect()
}

/// The harness in a QuickJS engine of its own (one per thread).
struct Engine {
    context: Context,
    _runtime: Runtime,
}

impl Engine {
    fn new() -> Engine {
        let runtime = Runtime::new().unwrap();
        // A bound against hanging (a mistake that loops) on all this engine's work,
        // several times what it takes.
        let started = std::time::Instant::now();
        runtime.set_interrupt_handler(Some(Box::new(move || {
            started.elapsed() > std::time::Duration::from_secs(600)
        })));
        let context = Context::full(&runtime).unwrap();
        context.with(|ctx| ctx.eval::<(), _>(HARNESS).catch(&ctx).unwrap());
        Engine {
            context,
            _runtime: runtime,
        }
    }

    /// Whether `source` fails any of `cases` (all of one function), as the grader judges
    /// it: an error, an output that differs from the reference, or a second call (in a
    /// fresh copy of the file) that does.
    fn fails(&self, source: &str, cases: &[&Case]) -> bool {
        // A case serialises its arguments in the contract's order, which JavaScript's
        // objects keep: Object.values gives them as the harness's call list.
        let cases_json = serde_json::to_string(cases).unwrap();
        let output: String = self.context.with(|ctx| {
            let harness: Object = ctx.globals().get("estlabHarness").unwrap();
            let call: Function = harness.get("callFunction").unwrap();
            let phase: String = ctx
                .eval::<Function, _>(
                    "(function (text) { const cases = JSON.parse(text); return JSON.stringify({ \
                       function: cases[0].function, limit_ms: 60000, \
                       calls: cases.map((c) => ({ id: c.id, args: Object.values(c.args) })) }); })",
                )
                .unwrap()
                .call((cases_json,))
                .unwrap();
            let progress = Function::new(ctx.clone(), |_: String| {}).unwrap();
            call.call((source, phase, progress)).catch(&ctx).unwrap()
        });
        let output: Value = serde_json::from_str(&output).unwrap();
        // A file that does not run is a broken entry of the catalogue, not a caught mistake.
        if let Some(error) = output.get("error") {
            panic!(
                "{}: the file did not run: {error}",
                cases[0].call.function()
            );
        }
        let answers = |list: &str| -> BTreeMap<String, Option<Value>> {
            output[list]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| {
                    (
                        r["id"].as_str().unwrap().to_owned(),
                        r.get("output").cloned(),
                    )
                })
                .collect()
        };
        let (results, repeats) = (answers("results"), answers("repeats"));
        cases.iter().any(|case| {
            [&results, &repeats].iter().any(|answers| {
                match answers.get(&case.id).cloned().flatten() {
                    Some(got) => !case.check(&got, Tolerance::default()).is_empty(),
                    None => true,
                }
            })
        })
    }
}

/// The cases of `cases` of one function.
fn of<'a>(cases: &'a [Case], function: &str) -> Vec<&'a Case> {
    cases
        .iter()
        .filter(|c| c.call.function() == function)
        .collect()
}

/// `work` on every seed, split over the machine's cores, each with an engine of its own.
fn over_seeds<R: Send>(work: impl Fn(&Engine, u64) -> R + Sync) -> Vec<R> {
    let threads = thread::available_parallelism().map_or(2, |n| n.get()) as u64;
    let mut results: Vec<(u64, R)> = thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let work = &work;
                scope.spawn(move || {
                    let engine = Engine::new();
                    (1..=SEEDS)
                        .filter(|seed| seed % threads == t)
                        .map(|seed| (seed, work(&engine, seed)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    results.sort_by_key(|(seed, _)| *seed);
    results.into_iter().map(|(_, r)| r).collect()
}

#[test]
fn every_mistake_is_caught_in_every_seed_and_no_correct_file_is_failed() {
    let mistakes = mistakes();
    let correct = [("correct.js", CORRECT), ("correct-alt.js", CORRECT_ALT)];
    // Per seed: the mistakes not caught, and the functions a correct file fails.
    let found = over_seeds(|engine, seed| {
        let cases = generate(seed, PER_FUNCTION);
        // A few cases at a time, to stop at the first failure; more than one, as a
        // function that keeps state between calls shows only over several.
        let missed: Vec<&str> = mistakes
            .iter()
            .filter(|(m, source)| {
                !of(&cases, &m.breaks)
                    .chunks(3)
                    .any(|some| engine.fails(source, some))
            })
            .map(|(m, _)| m.name.as_str())
            .collect();
        // The second correct file, written another way, in every fourth seed.
        let checked = if seed % 4 == 0 {
            &correct[..]
        } else {
            &correct[..1]
        };
        let wrongly_failed: Vec<String> = checked
            .iter()
            .flat_map(|(name, source)| {
                FUNCTIONS
                    .iter()
                    .filter(|f| engine.fails(source, &of(&cases, f)))
                    .map(move |f| format!("{name} fails {f}"))
            })
            .collect();
        (missed, wrongly_failed)
    });
    let mut problems = Vec::new();
    let mut missed_in: BTreeMap<&str, Vec<u64>> = BTreeMap::new();
    for (seed, (missed, wrongly_failed)) in (1..=SEEDS).zip(&found) {
        for name in missed {
            missed_in.entry(name).or_default().push(seed);
        }
        for what in wrongly_failed {
            problems.push(format!("seed {seed}: {what}"));
        }
    }
    for (name, seeds) in &missed_in {
        problems.push(format!(
            "{name} passes every case of its function in {} of {SEEDS} seeds, e.g. {:?}",
            seeds.len(),
            &seeds[..seeds.len().min(5)]
        ));
    }
    eprintln!(
        "{} of {} mistakes caught in all {SEEDS} seeds",
        mistakes.len() - missed_in.len(),
        mistakes.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

testdata::data_tests!(what_the_original_fixtures_catch_the_generated_cases_catch);

fn what_the_original_fixtures_catch_the_generated_cases_catch() {
    let mut fixtures = Vec::new();
    for (function, file) in FIXTURE_FILES {
        let text = testdata::read(&format!("el2320/test_cases/{file}"));
        fixtures.extend(load_fixtures(function, file, &text).unwrap());
    }
    let engine = Engine::new();
    let mistakes = mistakes();
    assert!(!engine.fails(CORRECT, &of(&fixtures, "associate")));
    let caught: Vec<&(Mistake, String)> = mistakes
        .iter()
        .filter(|(m, source)| engine.fails(source, &of(&fixtures, &m.breaks)))
        .collect();
    // Caught by the generated cases of a seed: a few seeds suffice here, the test above
    // holds every mistake to every one of its seeds.
    let generated: Vec<Case> = (1..=5)
        .flat_map(|seed| generate(seed, PER_FUNCTION))
        .collect();
    let missed: Vec<&str> = caught
        .iter()
        .filter(|(m, source)| !engine.fails(source, &of(&generated, &m.breaks)))
        .map(|(m, _)| m.name.as_str())
        .collect();
    eprintln!(
        "the original fixtures catch {} of {} mistakes: {:?}",
        caught.len(),
        mistakes.len(),
        caught.iter().map(|(m, _)| &m.name).collect::<Vec<_>>()
    );
    assert!(
        missed.is_empty(),
        "the fixtures catch these and the generated cases of seeds 1-5 do not: {missed:?}"
    );
}
