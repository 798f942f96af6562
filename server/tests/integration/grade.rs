//! `estlab grade`, run as an instructor runs it, on student files that are right, wrong
//! in a classic way, or hostile.
//!
//! - `tests/student/correct.js` scores 1 in every output format;
//! - every variant in `tests/student/mistakes.json` (correct.js with a classic mistake
//!   put in) loses points on the test of the function it breaks, and that test explains
//!   the mistake with the expected hint and no other;
//! - hostile and careless code (endless loops, allocation bombs, runaway recursion,
//!   throwing, NaN, wrong shapes, modules, network, tampered built-ins) is graded with a
//!   message that tells the student what happened, and never makes the result "not
//!   gradable" (that is for failures of the sandbox itself);
//! - a file over the size limit is refused.
//!
//! Most sources are correct.js with a function declared again after it: the last
//! declaration wins, so exactly that function is replaced. Gradings run in parallel, and
//! the table-driven tests collect every problem before failing, so one run shows them
//! all.

use crate::student;

use labs::exercises::ekf_localization::FUNCTIONS;
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread;
use student::{CORRECT, Mistake};

/// The data sets, each with a test of its own ("o3 data set, sequential update: ...").
const DATASETS: [&str; 3] = ["o3", "outliers", "no-odometry"];

// ---- running the binary ----

fn estlab_grade(file: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_estlab"))
        .arg("grade")
        .arg(file)
        .args(args)
        .output()
        .unwrap()
}

/// Grades `source` as a file of its own: stdout parsed as JSON when the command
/// succeeded, or what it said instead.
fn try_grade(source: &str, args: &[&str]) -> Result<Value, String> {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("student.js");
    std::fs::write(&file, source).unwrap();
    let out = estlab_grade(&file, args);
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        return Err(format!(
            "estlab grade exited with {}: {}{stdout}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    serde_json::from_str(&stdout).map_err(|e| format!("stdout is not JSON ({e}):\n{stdout}"))
}

fn grade(source: &str, args: &[&str]) -> Value {
    try_grade(source, args).unwrap_or_else(|e| panic!("{e}"))
}

/// `work` on every item, on as many threads as there are cores; results in order.
fn parallel<T: Sync, R: Send>(items: &[T], work: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = thread::available_parallelism().map_or(2, |n| n.get());
    let next = AtomicUsize::new(0);
    let mut results: Vec<Option<R>> = items.iter().map(|_| None).collect();
    thread::scope(|scope| {
        let workers: Vec<_> = (0..threads.min(items.len()))
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break done };
                        done.push((i, work(item)));
                    }
                })
            })
            .collect();
        for worker in workers {
            for (i, result) in worker.join().unwrap() {
                results[i] = Some(result);
            }
        }
    });
    results.into_iter().map(Option::unwrap).collect()
}

// ---- reading a result ----

fn tests(result: &Value) -> &[Value] {
    result["tests"].as_array().map_or(&[], Vec::as_slice)
}

/// The test of a function ("predict: 12 cases") or of a data set ("o3 data set, ...").
fn test<'a>(result: &'a Value, name: &str) -> &'a Value {
    let prefix = if DATASETS.contains(&name) {
        format!("{name} data set")
    } else {
        format!("{name}:")
    };
    tests(result)
        .iter()
        .find(|t| t["name"].as_str().is_some_and(|n| n.starts_with(&prefix)))
        .unwrap_or(&Value::Null)
}

fn passed(test: &Value) -> bool {
    test["status"] == "passed"
}

fn message(test: &Value) -> &str {
    test["message"].as_str().unwrap_or_default()
}

/// The hint kinds of a test's failing cases.
fn hint_kinds(test: &Value) -> BTreeSet<&str> {
    test["failures"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|f| f["hint"]["kind"].as_str())
        .collect()
}

// ---- checking a result, problem by problem ----

/// What is wrong with one grading, collected rather than stopping at the first.
#[derive(Default)]
struct Problems(Vec<String>);

impl Problems {
    fn expect(&mut self, ok: bool, what: impl FnOnce() -> String) {
        if !ok {
            self.0.push(what());
        }
    }

    /// The test's message contains every part.
    fn says(&mut self, result: &Value, name: &str, parts: &[&str]) {
        let text = message(test(result, name));
        let missing: Vec<&&str> = parts.iter().filter(|p| !text.contains(*p)).collect();
        self.expect(missing.is_empty(), || {
            format!(
                "the {name} test should say {missing:?}; it says:\n{}",
                quote(text)
            )
        });
    }

    /// The test's message contains at least one of the parts.
    fn says_any(&mut self, result: &Value, name: &str, parts: &[&str]) {
        let text = message(test(result, name));
        self.expect(parts.iter().any(|p| text.contains(p)), || {
            format!(
                "the {name} test should say one of {parts:?}; it says:\n{}",
                quote(text)
            )
        });
    }

    fn does_not_say(&mut self, result: &Value, name: &str, part: &str) {
        let text = message(test(result, name));
        self.expect(!text.contains(part), || {
            format!(
                "the {name} test should not say {part:?}; it says:\n{}",
                quote(text)
            )
        });
    }

    fn status(&mut self, result: &Value, names: &[&str], pass: bool) {
        for &name in names {
            let t = test(result, name);
            self.expect(!t.is_null() && passed(t) == pass, || {
                if t.is_null() {
                    return format!("there is no {name} test");
                }
                let status = if pass { "pass" } else { "fail" };
                format!(
                    "the {name} test should {status}; it says:\n{}",
                    quote(message(t))
                )
            });
        }
    }

    /// Exactly the function tests in `broken` fail, and the score shows it.
    fn only_these_fail(&mut self, result: &Value, broken: &[&str]) {
        let (fail, pass): (Vec<&str>, Vec<&str>) =
            FUNCTIONS.iter().partition(|f| broken.contains(f));
        self.status(result, &fail, false);
        self.status(result, &pass, true);
        self.score_below_one(result);
    }

    fn score_is(&mut self, result: &Value, expected: f64) {
        let score = result["score"].as_f64();
        self.expect(score == Some(expected), || {
            format!("the score is {score:?}, not {expected}")
        });
        self.expect(result["gradable"] == true, || {
            format!("not gradable: {}", result["reason"])
        });
    }

    fn score_is_below(&mut self, result: &Value, bound: f64) {
        let score = result["score"].as_f64();
        self.expect(score.is_some_and(|s| s < bound), || {
            format!("the score is {score:?}, not below {bound}")
        });
        self.expect(result["gradable"] == true, || {
            format!("not gradable: {}", result["reason"])
        });
    }

    fn score_below_one(&mut self, result: &Value) {
        let score = result["score"].as_f64();
        self.expect(score.is_some_and(|s| s < 1.0), || {
            format!("broken code should not score {score:?}")
        });
    }

    /// Every test fails, and a function's test and a data set's (they all say the same)
    /// say what is wrong with the whole file.
    fn whole_file_fails(&mut self, result: &Value, parts: &[&str]) {
        let all: Vec<&str> = FUNCTIONS.iter().chain(&DATASETS).copied().collect();
        self.status(result, &all, false);
        self.says(result, FUNCTIONS[0], parts);
        self.says(result, DATASETS[0], parts);
    }
}

/// The start of a message, set off for a report.
fn quote(text: &str) -> String {
    const SHOWN: usize = 4;
    let mut lines: Vec<String> = text
        .lines()
        .take(SHOWN)
        .map(|l| format!("      | {l}"))
        .collect();
    if text.lines().count() > SHOWN {
        lines.push("      | ...".to_owned());
    }
    lines.join("\n")
}

/// Grades `source` and checks the result: it was produced (exit code 0) and gradable
/// (whatever the code does, the sandbox's own kill must not strike), and `check` finds
/// no problem with it.
fn problems_of(source: &str, check: impl FnOnce(&Value, &mut Problems)) -> Vec<String> {
    problems_with(source, &[], check)
}

/// The problems of `source` graded with `estlab grade`'s further `args`.
fn problems_with(
    source: &str,
    args: &[&str],
    check: impl FnOnce(&Value, &mut Problems),
) -> Vec<String> {
    let result = match try_grade(source, args) {
        Ok(result) => result,
        Err(e) => return vec![e],
    };
    if result["gradable"] != true {
        return vec![format!("not gradable: {}", result["reason"])];
    }
    let mut problems = Problems::default();
    check(&result, &mut problems);
    problems.0
}

/// Passes when no item has a problem; else fails with every problem of every item.
#[track_caller]
fn assert_no_problems(what: &str, items: Vec<(String, Vec<String>)>) {
    let total = items.len();
    let report: Vec<String> = items
        .into_iter()
        .filter(|(_, problems)| !problems.is_empty())
        .map(|(name, problems)| format!("{name}:\n  {}", problems.join("\n  ")))
        .collect();
    assert!(
        report.is_empty(),
        "{} of {total} {what} are not graded as they should be:\n\n{}",
        report.len(),
        report.join("\n\n")
    );
}

// ---- sources ----

/// correct.js with `extra` after it: a function declared again there replaces the
/// correct one.
fn with(extra: &str) -> String {
    format!("{CORRECT}\n{extra}\n")
}

/// The line of the first line of `extra` in `with(extra)`, as the student's editor
/// numbers it.
fn extra_line() -> usize {
    CORRECT.matches('\n').count() + 2
}

// ---- the correct file ----

#[test]
fn the_correct_file_scores_one_in_every_format() {
    let formats = ["json", "gradescope", "prairielearn"];
    let results = parallel(&formats, |format| grade(CORRECT, &["--format", format]));
    let (json, gradescope, prairielearn) = (&results[0], &results[1], &results[2]);

    assert_eq!(json["lab"], "ekf-localization");
    assert_eq!(json["seed"], 1, "the default seed");
    assert_eq!(json["gradable"], true);
    assert_eq!(json["score"], 1.0);
    assert_eq!(json["points"], json["max_points"]);
    let n = tests(json).len();
    assert_eq!(n, FUNCTIONS.len() + DATASETS.len(), "{json:#}");
    for t in tests(json) {
        assert!(passed(t), "{t:#}");
        assert_eq!(t["points"], t["max_points"], "{t:#}");
        assert!(t.get("failures").is_none(), "{t:#}");
    }

    assert_eq!(gradescope["score"], json["points"]);
    assert_eq!(tests(gradescope).len(), n);
    for (g, t) in tests(gradescope).iter().zip(tests(json)) {
        assert_eq!(g["name"], t["name"]);
        assert_eq!(g["score"], g["max_score"]);
        assert_eq!(g["status"], "passed");
        assert_eq!(g["visibility"], "visible");
        assert_eq!(g["output"], t["message"]);
    }

    assert_eq!(prairielearn["gradable"], true);
    assert_eq!(prairielearn["score"], 1.0);
    assert_eq!(tests(prairielearn).len(), n);
    for (p, t) in tests(prairielearn).iter().zip(tests(json)) {
        assert_eq!(p["name"], t["name"]);
        assert_eq!(p["points"], p["max_points"]);
        assert_eq!(p["message"], t["message"]);
    }

    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("correct.js");
    std::fs::write(&file, CORRECT).unwrap();
    let out = estlab_grade(&file, &["--format", "text"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let max = json["max_points"].as_f64().unwrap();
    let summary = format!("{max} of {max} points (100%), {n} of {n} tests passed");
    assert_eq!(text.lines().next(), Some(summary.as_str()), "{text}");
    for t in tests(json) {
        let line = format!(
            "{} [{}/{}]",
            t["name"].as_str().unwrap(),
            t["points"].as_f64().unwrap(),
            t["max_points"].as_f64().unwrap()
        );
        assert!(text.contains(&line), "no {line:?} in:\n{text}");
    }
    assert_eq!(
        text.lines().nth(1),
        Some(
            "Graded on the shown cases only: the server also grades hidden cases drawn from its secret, and data sets you have not seen."
        ),
        "the command line says what it leaves out"
    );
    assert_eq!(json["hidden_cases"], false);
}

/// A second correct file, written another way (likelihoods rather than their logarithms,
/// the Joseph form of the update, another angle wrap), scores 1 for several students.
#[test]
fn a_correct_file_written_another_way_scores_one() {
    const ANOTHER_WAY: &str = include_str!("../../../tests/student/correct-alt.js");
    let students = ["carol", "dave", "erin"];
    let results = parallel(&students, |student| {
        grade(ANOTHER_WAY, &["--student", student])
    });
    for (student, result) in students.iter().zip(&results) {
        assert_eq!(result["score"], 1.0, "{student}: {result:#}");
    }
}

#[test]
fn each_student_gets_a_variant_of_their_own() {
    let students = ["alice", "bob"];
    let results = parallel(&students, |student| {
        grade(CORRECT, &["--student", student, "--course", "el2320"])
    });
    let (alice, bob) = (&results[0], &results[1]);
    for result in &results {
        assert_eq!(result["score"], 1.0, "{result:#}");
    }
    assert_ne!(alice["seed"], bob["seed"]);
    assert_ne!(alice["seed"], 1, "not the default seed");

    // The seed stands for the variant: graded by seed, alice's file gets the same result.
    let seed = alice["seed"].to_string();
    assert_eq!(&grade(CORRECT, &["--seed", &seed]), alice);
}

// ---- classic mistakes ----

/// What is wrong with how the grader handled one mistake.
fn mistake_problems(mistake: &Mistake) -> Vec<String> {
    let source = match mistake.source() {
        Ok(source) => source,
        Err(e) => return vec![e],
    };
    problems_of(&source, |result, p| {
        p.score_below_one(result);
        if mistake.breaks == "init" {
            // init has no test of its own: every run starts with it, and says what is wrong.
            let phrase = init_hint_phrase(&mistake.hint).unwrap_or_else(|| {
                panic!(
                    "no phrase known for the init hint {:?}: add one to init_hint_phrase",
                    mistake.hint
                )
            });
            for dataset in DATASETS {
                let broken = mistake
                    .datasets
                    .as_ref()
                    .is_none_or(|broken| broken.iter().any(|d| d == dataset));
                p.status(result, &[dataset], !broken);
                if broken {
                    p.says(result, dataset, &[&format!("init('{dataset}')"), phrase]);
                }
            }
            return;
        }
        let t = test(result, &mistake.breaks);
        p.status(result, &[&mistake.breaks], false);
        let kinds = hint_kinds(t);
        p.expect(kinds.contains(mistake.hint.as_str()), || {
            format!(
                "the {} test should hint {:?}; its hints are {kinds:?}; it says:\n{}",
                mistake.breaks,
                mistake.hint,
                quote(message(t))
            )
        });
        p.expect(kinds.iter().all(|k| *k == mistake.hint), || {
            format!(
                "the {} test should give no hint but {:?}, which explains every failure; its hints are {kinds:?}",
                mistake.breaks, mistake.hint
            )
        });
    })
}

/// What a data-set test says for a classic mistake in `init`.
fn init_hint_phrase(kind: &str) -> Option<&'static str> {
    match kind {
        "r_q_swapped" => Some("init returned R as a 2 x 2 and Q as a 3 x 3 matrix"),
        "init_settings" => Some(
            "does not return the lab's settings: Q is diag(0.0001, 0.000304617), the lab's is diag(0.04, 0.04)",
        ),
        _ => None,
    }
}

#[test]
fn every_classic_mistake_is_caught_and_explained() {
    let mistakes = Mistake::all();
    assert!(!mistakes.is_empty());
    let problems = parallel(&mistakes, mistake_problems);
    let named = mistakes
        .iter()
        .map(|m| format!("{} (breaks {})", m.name, m.breaks));
    assert_no_problems("mistakes", named.zip(problems).collect());
}

// ---- hostile and careless code ----

type Check = Box<dyn Fn(&Value, &mut Problems) + Sync>;

struct Hostile {
    name: &'static str,
    source: String,
    check: Check,
    /// `estlab grade`'s arguments beyond the file: the engine, where the file attacks one.
    args: &'static [&'static str],
}

impl Hostile {
    /// The file graded on QuickJS, whose weakness it attacks.
    fn on_quickjs(self) -> Hostile {
        Hostile {
            args: &["--javascript", "quickjs"],
            ..self
        }
    }
}

fn hostile(
    name: &'static str,
    source: String,
    check: impl Fn(&Value, &mut Problems) + Sync + 'static,
) -> Hostile {
    Hostile {
        name,
        source,
        check: Box::new(check),
        args: &[],
    }
}

/// Every hostile file, with what its grading must say.
fn hostile_suite() -> Vec<Hostile> {
    let line = extra_line();
    let at_line = move || format!("(line {line})");
    let syntax_line = CORRECT
        .lines()
        .position(|l| l.contains("return { mu_bar, sigma_bar };"))
        .expect("predict's return in correct.js")
        + 1;
    // Every message a student sees about `function`: its test and every data set's.
    let about = |function: &'static str| -> Vec<&'static str> {
        std::iter::once(function).chain(DATASETS).collect()
    };
    vec![
        hostile(
            "an endless loop",
            with(
                "function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) { while (true) {} }",
            ),
            |r, p| {
                p.only_these_fail(r, &["batch_update"]);
                p.says(
                    r,
                    "batch_update",
                    &["the time limit", "batch_update/p1", "endless loop"],
                );
                p.status(r, &["o3", "outliers"], true);
                p.status(r, &["no-odometry"], false);
                p.says(r, "no-odometry", &["the time limit", "no-odometry/batch"]);
            },
        ),
        hostile(
            "an allocation bomb of typed arrays",
            with(
                "function predict(mu, sigma, u, R) { const blocks = []; for (;;) blocks.push(new Float64Array(1 << 20)); }",
            ),
            move |r, p| {
                p.only_these_fail(r, &["predict"]);
                for name in about("predict") {
                    p.says(r, name, &["out of memory"]);
                }
            },
        ),
        hostile(
            "an allocation bomb of plain arrays",
            with(
                "function predict(mu, sigma, u, R) { const rows = []; for (;;) rows.push(new Array(1000).fill(1.5)); }",
            ),
            move |r, p| {
                p.only_these_fail(r, &["predict"]);
                for name in about("predict") {
                    p.says_any(r, name, &["memory", "time limit"]);
                    p.does_not_say(r, name, "not an Error: null");
                }
            },
        ),
        hostile(
            "unbounded recursion",
            with(
                "function update(mu_bar, sigma_bar, H, S, nu) { return update(mu_bar, sigma_bar, H, S, nu); }",
            ),
            move |r, p| {
                p.only_these_fail(r, &["update"]);
                p.says(
                    r,
                    "update",
                    &["Maximum call stack size exceeded", &at_line()],
                );
                p.says(
                    r,
                    "o3",
                    &["update: threw RangeError: Maximum call stack size exceeded"],
                );
            },
        ),
        hostile(
            "a function that throws",
            with(
                "function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) { throw new Error('my matrix is singular, sorry'); }",
            ),
            move |r, p| {
                p.only_these_fail(r, &["batch_update"]);
                p.says(
                    r,
                    "batch_update",
                    &[&format!(
                        "threw Error: my matrix is singular, sorry {}",
                        at_line()
                    )],
                );
                p.says(
                    r,
                    "no-odometry",
                    &["batch_update: threw Error: my matrix is singular, sorry"],
                );
            },
        ),
        hostile(
            "a function that returns NaN",
            with(
                "function update(mu_bar, sigma_bar, H, S, nu) { return { mu: [NaN, mu_bar[1], mu_bar[2]], sigma: sigma_bar }; }",
            ),
            |r, p| {
                p.only_these_fail(r, &["update"]);
                p.says(
                    r,
                    "update",
                    &["got \"NaN\"", "The output holds NaN or Infinity"],
                );
                p.expect(hint_kinds(test(r, "update")).contains("not_finite"), || {
                    "no not_finite hint".to_owned()
                });
                p.says(r, "o3", &["update: mu[0] is \"NaN\", not a finite number"]);
            },
        ),
        hostile(
            "a flat array instead of a matrix",
            with(
                "function predict(mu, sigma, u, R) { return { mu_bar: mu, sigma_bar: sigma.flat() }; }",
            ),
            |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(
                    r,
                    "predict",
                    &["`sigma_bar` should be a 3 x 3 array of rows, but is an array of 9 numbers"],
                );
                p.says(r, "o3", &["predict: sigma_bar should be an array of 3 elements, but is an array of 9 elements"]);
            },
        ),
        hostile(
            "a missing field",
            with("function update(mu_bar, sigma_bar, H, S, nu) { return { mu: mu_bar }; }"),
            |r, p| {
                p.only_these_fail(r, &["update"]);
                p.says(
                    r,
                    "update",
                    &["`sigma` should be a 3 x 3 array of rows, but is missing"],
                );
                p.says(
                    r,
                    "o3",
                    &["update: returned an object with the fields mu without the field sigma"],
                );
            },
        ),
        hostile(
            "require at top level",
            with("const math = require('mathjs');"),
            move |r, p| {
                p.whole_file_fails(
                    r,
                    &[
                        "Your file throws while it loads",
                        "require is not available here",
                        &at_line(),
                    ],
                );
            },
        ),
        hostile(
            "require in a function",
            with("function predict(mu, sigma, u, R) { return require('mathjs').multiply(mu, 2); }"),
            move |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(r, "predict", &["require is not available here", &at_line()]);
            },
        ),
        hostile(
            "process",
            with("function predict(mu, sigma, u, R) { return process.env.HOME; }"),
            move |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(r, "predict", &["process is not available here", &at_line()]);
            },
        ),
        hostile(
            "fetch",
            with(
                "function predict(mu, sigma, u, R) { fetch('https://example.com/answers.json'); return null; }",
            ),
            move |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(r, "predict", &["fetch is not available here", &at_line()]);
            },
        ),
        hostile(
            "a dynamic import",
            with(
                "function predict(mu, sigma, u, R) { const math = import('mathjs'); return math.multiply(mu, 2); }",
            ),
            |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(r, "predict", &["import", "no modules"]);
            },
        ),
        hostile(
            "a static import",
            format!("import {{ inv }} from 'mathjs';\n{CORRECT}"),
            |r, p| {
                p.whole_file_fails(
                    r,
                    &[
                        "Your file does not compile",
                        "(line 1)",
                        "import",
                        "no modules",
                    ],
                )
            },
        ),
        hostile(
            "eval of a 1 MB string",
            with(
                "function predict(mu, sigma, u, R) { const text = eval('\"' + 'a'.repeat(1000000) + '\"'); return text.length; }",
            ),
            // The string fits in the memory limit and the time: the answer is its length,
            // in the wrong shape, and the message says so. (Ten times larger, the evals
            // of a phase run past its limit inside single calls: see the indexOf file.)
            |r, p| {
                p.only_these_fail(r, &["predict"]);
                p.says(
                    r,
                    "predict",
                    &[
                        "got 1000000 (not the contract's shape)",
                        "should be an object with the fields mu_bar, sigma_bar, but is a number",
                    ],
                );
            },
        ),
        hostile(
            "a syntax error",
            CORRECT.replace(
                "return { mu_bar, sigma_bar };",
                "return { mu_bar, sigma_bar ;",
            ),
            move |r, p| {
                p.whole_file_fails(
                    r,
                    &[
                        "Your file does not compile: SyntaxError",
                        &format!("(line {syntax_line})"),
                    ],
                );
            },
        ),
        hostile(
            "Math.sqrt replaced",
            with("Math.sqrt = () => 0;"),
            |r, p| {
                p.only_these_fail(r, &["observation_model", "associate", "batch_associate"]);
            },
        ),
        hostile(
            "Array.prototype.map replaced",
            with("Array.prototype.map = function () { return []; };"),
            |r, p| {
                p.status(
                    r,
                    &[
                        "calculate_odometry",
                        "observation_model",
                        "jacobian_observation_model",
                    ],
                    true,
                );
                p.status(r, &["predict", "update", "batch_update"], false);
                p.says(r, "predict", &["threw TypeError"]);
                p.score_below_one(r);
            },
        ),
        hostile(
            "JSON replaced, predict broken",
            with(
                "JSON.stringify = () => '{\"score\": 1}';\nJSON.parse = () => ({});\nfunction predict(mu, sigma, u, R) { return { mu_bar: mu, sigma_bar: sigma }; }",
            ),
            |r, p| p.only_these_fail(r, &["predict"]),
        ),
        hostile(
            "Object.prototype polluted, predict broken",
            with(
                "Object.prototype.mu_bar = [0, 0, 0];\nObject.prototype.sigma_bar = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];\nfunction predict(mu, sigma, u, R) { return {}; }",
            ),
            |r, p| p.only_these_fail(r, &["predict"]),
        ),
        hostile(
            "the harness's global replaced, update broken",
            with(
                "globalThis.estlabHarness = null;\nfunction update(mu_bar, sigma_bar, H, S, nu) { return { mu: mu_bar, sigma: sigma_bar }; }",
            ),
            |r, p| p.only_these_fail(r, &["update"]),
        ),
        hostile(
            "Object.prototype.toJSON that throws",
            with("Object.prototype.toJSON = function () { throw new Error('gotcha'); };"),
            // The harness writes its own JSON and the grader reads none of the student's
            // objects with toJSON: the file is correct, and scores 1.
            |r, p| p.score_is(r, 1.0),
        ),
        // ---- tampering with the harness's bookkeeping ----
        hostile(
            "setters on Object.prototype that swallow the harness's records, nothing implemented",
            "Object.defineProperty(Object.prototype, 'error', { set(v) {}, configurable: true });\n\
             Object.defineProperty(Object.prototype, 'output', { set(v) {}, configurable: true });\n\
             Object.defineProperty(Array.prototype, '0', { set(v) {}, configurable: true });\n"
                .to_owned(),
            |r, p| {
                p.score_is(r, 0.0);
                p.says(r, "predict", &["predict is not defined"]);
            },
        ),
        hostile(
            "getters on the prototypes that answer NaN, nothing implemented",
            "for (const name of ['error', 'output', 'results', 'repeats', 'record', 'mu', 'c']) {\n\
               Object.defineProperty(Object.prototype, name, { get() { return NaN; }, set(v) {}, configurable: true });\n\
             }\n\
             Object.defineProperty(Array.prototype, '0', { get() { return NaN; }, set(v) {}, configurable: true });\n"
                .to_owned(),
            |r, p| {
                p.score_is(r, 0.0);
                p.says(r, "update", &["update is not defined"]);
            },
        ),
        hostile(
            "setters on Object.prototype beside a correct file",
            with(
                "Object.defineProperty(Object.prototype, 'error', { set(v) {}, configurable: true });\n\
                 Object.defineProperty(Object.prototype, 'results', { set(v) {}, get() { return []; }, configurable: true });",
            ),
            |r, p| p.score_is(r, 1.0),
        ),
        hostile(
            "a heading of 1e300, equal to anything modulo 2 pi",
            CORRECT
                .replace("wrap(omega * delta_t)];", "wrap(omega * delta_t) + 1e300];")
                .replace(
                    "wrap(mu[2] + u[2])];",
                    "wrap(mu[2] + u[2]) + 1e300];",
                ),
            |r, p| {
                p.status(r, &["calculate_odometry", "predict", "o3", "outliers", "no-odometry"], false);
                p.says(r, "predict", &["got 1e+300", "more than 2 turns outside [-pi, pi)"]);
                p.says(r, "o3", &["the heading mu[2] = 1e300 is more than 2 turns outside"]);
            },
        ),
        hostile(
            "outputs of 15,000 elements",
            with(
                "function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) { return new Array(15000).fill(1.5); }",
            ),
            |r, p| {
                p.only_these_fail(r, &["batch_update"]);
                p.says(r, "batch_update", &["returned more than 2000 values"]);
                let size = r.to_string().len();
                p.expect(size < 40 << 10, || format!("the result has {size} bytes"));
            },
        ),
        hostile(
            "an error whose name is a megabyte, and fields with names of 5,000 characters",
            with(
                "function predict(mu, sigma, u, R) { const e = new Error('big'); e.name = 'N'.repeat(1 << 20); throw e; }\n\
                 function observation_model(x, M, j) { const o = {}; for (let i = 0; i < 100; i++) o['k'.repeat(5000) + i] = i; return o; }",
            ),
            |r, p| {
                p.score_is_below(r, 1.0);
                p.says(r, "predict", &["threw NNNN"]);
                let size = r.to_string().len();
                p.expect(size < 64 << 10, || format!("the result has {size} bytes"));
            },
        ),
        hostile(
            "a thrown object whose getters throw",
            with(
                "function update(mu_bar, sigma_bar, H, S, nu) { throw { get message() { throw 'gotcha'; }, get name() { throw 'gotcha'; } }; }",
            ),
            |r, p| {
                p.only_these_fail(r, &["update"]);
                p.says(r, "update", &["cannot be described"]);
                p.does_not_say(r, "update", "the sandbox failed");
            },
        ),
        hostile(
            "a file that loads once and throws on its second load, to silence the repeats",
            format!(
                "if (globalThis.seenBefore) throw new Error('second load');\nglobalThis.seenBefore = true;\n{CORRECT}"
            ),
            |r, p| {
                p.score_is_below(r, 0.5);
                p.says(r, "predict", &["second load"]);
            },
        ),
        hostile(
            "a single built-in call far past the limit, where the engine cannot interrupt it",
            with(
                "var haystack = 'a'.repeat(400000), needle = 'a'.repeat(200000) + 'b';\n\
                 function calculate_odometry() { return haystack.indexOf(needle); }",
            ),
            |r, p| {
                p.whole_file_fails(
                    r,
                    &[
                        "a single call ran for more than a second of CPU time where the time limit cannot interrupt it",
                    ],
                );
                p.score_is(r, 0.0);
            },
        )
        // V8 looks at its clock from outside the engine (and finds such a call quick).
        .on_quickjs(),
        hostile(
            "the stack-trace hook that would hand over the harness's functions",
            with(
                "Error.prepareStackTrace = (error, frames) => frames;\n\
                 if (typeof new Error('probe').stack !== 'string') throw new Error('call sites reached');",
            ),
            |r, p| p.score_is(r, 1.0),
        ),
        hostile(
            "an endless loop at the top level, eleven bytes",
            "for (;;) {}\n".to_owned(),
            |r, p| {
                p.whole_file_fails(
                    r,
                    &["Stopped after 2 s, the time limit, while running the top level of your file"],
                );
                p.score_is(r, 0.0);
            },
        ),
    ]
}

/// Whatever a student's file does, grading ends with a result: exit code 0, gradable
/// (the sandbox's wall-clock kill did not strike), and the messages `check` expects.
#[test]
fn hostile_and_careless_code_is_graded_with_clear_messages() {
    let suite = hostile_suite();
    let problems = parallel(&suite, |case| {
        problems_with(&case.source, case.args, &case.check)
    });
    let named = suite.iter().map(|case| case.name.to_owned());
    assert_no_problems("hostile files", named.zip(problems).collect());
}

#[test]
fn a_file_over_the_size_limit_is_refused() {
    const LIMIT: usize = 256 << 10;
    let dir = tempfile::tempdir().unwrap();
    let padded = |bytes: usize| {
        let mut source = format!("{CORRECT}\n// ");
        source.push_str(&"x".repeat(bytes - source.len()));
        source
    };

    let huge = dir.path().join("huge.js");
    std::fs::write(&huge, padded(LIMIT + 1)).unwrap();
    let out = estlab_grade(&huge, &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(out.stdout.is_empty());
    assert!(
        stderr.contains("huge.js")
            && stderr.contains("262145 bytes")
            && stderr.contains("at most 256 KB"),
        "{stderr}"
    );

    let result = grade(&padded(LIMIT), &[]);
    assert_eq!(
        result["score"], 1.0,
        "a file of exactly the limit is graded"
    );
}
