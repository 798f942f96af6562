//! An exercise's student files graded as the server grades them: through the real sandbox
//! (a worker process of `estlab` running the harness in QuickJS), with hidden cases and
//! hidden runs, on several seeds. What the tests of the odometry and the sensor-fusion
//! exercises (`odometry_mistakes.rs`, `fusion_mistakes.rs`) hold each one's files to:
//!
//! - the correct file scores 1;
//! - the starter scores 0, and every test says what is not implemented;
//! - every classic mistake of the exercise's catalogue (its `mistakes.json`: the correct
//!   file with one function broken) fails the test of the function it breaks, every
//!   failing case of it with the mistake's hint and no other, fails the tests of the
//!   functions that call it in the correct file (its `also`), passes the other functions'
//!   tests, and fails the runs it breaks while passing the others (save those it breaks
//!   only by chance, as the drawn run happens to show it).
//!
//! Gradings run in parallel, and the table-driven check collects every problem before
//! failing, so one run shows them all.

use super::{Replacement, made_in};
use estlab::sandbox::{Code, Sandbox};
use labs::grading::{self, GradeResult, Hidden, Status, Subject, Test};
use labs::{Exercise, Language};
use serde::Deserialize;
use serde_json::json;
use std::path::PathBuf;
use std::thread;

/// The seed of a student's variant, and the seed of its hidden cases and runs.
pub type Seeds = (u64, u64);

/// An exercise's student files: its correct file and its catalogue of classic mistakes
/// (the starter is the exercise's own).
pub struct Files {
    pub exercise: Exercise,
    /// The language the files are written in.
    pub language: Language,
    /// The student functions, in the contract's order.
    pub functions: &'static [&'static str],
    /// The runs of the exercise's loop a grading holds the functions to, by name.
    pub runs: &'static [&'static str],
    pub correct: &'static str,
    /// Where the catalogue is (for messages), and its text.
    pub catalogue: (&'static str, &'static str),
}

/// The tests of an exercise's student files: `$files` (a [`Files`]) graded on every seed
/// of `$seeds` (an array of [`Seeds`]), its catalogue holding `$at_least` mistakes or more.
#[allow(unused_macros)]
macro_rules! graded_as_the_server_grades {
    ($files:expr, $seeds:expr, $at_least:expr) => {
        #[test]
        fn the_correct_file_scores_1_with_hidden_cases() {
            $files.check_the_correct_file(&$seeds);
        }

        #[test]
        fn the_starter_scores_0_and_says_what_is_not_implemented() {
            $files.check_the_starter($seeds[0]);
        }

        #[test]
        fn every_mistake_fails_its_function_with_its_hint_and_the_runs_it_breaks() {
            $files.check_the_mistakes(&$seeds, $at_least);
        }
    };
}
#[allow(unused_imports)]
pub(crate) use graded_as_the_server_grades;

/// A classic mistake: the correct file with some text replaced.
#[derive(Deserialize)]
pub struct Mistake {
    pub name: String,
    /// The function it breaks.
    pub breaks: String,
    /// The hint it must get.
    pub hint: String,
    /// The functions that call the one it breaks in the correct file (as `ukf_predict`
    /// calls `sigma_points`), whose tests fail too, with whatever hint their cases give.
    #[serde(default)]
    also: Vec<String>,
    /// The runs it breaks (all when absent): a run does not reach every case a mistake
    /// shows in, and along a run a function that keeps state may give what it should.
    #[serde(default)]
    runs: Option<Vec<String>>,
    /// The runs it breaks only where the drawn run reaches what shows it (a reading across
    /// +-pi from the prediction, a pose in a corner of the square around the field of
    /// view): they may fail or pass, and when they fail they name the function.
    #[serde(default)]
    by_chance: Vec<String>,
    /// The cases (by their note) where the mistake may get no hint, because another
    /// mistake gives the very same answer there.
    #[serde(default)]
    pub unhinted: Vec<String>,
    replace: Vec<Replacement>,
}

impl Mistake {
    /// Whether the mistake breaks the run `name`.
    pub fn breaks_run(&self, name: &str) -> bool {
        self.runs
            .as_ref()
            .is_none_or(|runs| runs.iter().any(|run| run == name))
    }
}

impl Files {
    pub fn mistakes(&self) -> Vec<Mistake> {
        let (path, text) = self.catalogue;
        serde_json::from_str(text).unwrap_or_else(|e| panic!("{path}: {e}"))
    }

    /// The correct file with the mistake made, or which replaced text does not occur in it
    /// exactly once.
    pub fn source(&self, mistake: &Mistake) -> Result<String, String> {
        made_in(self.correct, &mistake.name, &mistake.replace)
    }

    /// Grades `source` in a worker process, as the server does.
    pub fn grade(&self, source: &str, (seed, hidden): Seeds) -> GradeResult {
        let sandbox = Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 1);
        let drawn = Hidden {
            cases: hidden,
            class: hidden,
        };
        let code = Code {
            language: self.language,
            text: source,
        };
        let result = sandbox.grade(self.exercise, code, seed, Some(drawn));
        assert!(result.gradable, "seed {seed}: {:?}", result.reason);
        result
    }

    /// The correct file scores 1 on every seed, with hidden cases, every function's test
    /// and every run's passed.
    pub fn check_the_correct_file(&self, seeds: &[Seeds]) {
        for (seeds, result) in seeds
            .iter()
            .zip(parallel(seeds, |&seeds| self.grade(self.correct, seeds)))
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
            assert_eq!(result.exercise, self.exercise);
            let subjects: Vec<&Subject> = result.tests.iter().map(|t| &t.subject).collect();
            let expected: Vec<Subject> = self
                .functions
                .iter()
                .map(|f| Subject::Function(f.to_string()))
                .chain(self.runs.iter().map(|r| Subject::Run(r.to_string())))
                .collect();
            assert_eq!(subjects, expected.iter().collect::<Vec<_>>());
            for run in self.runs {
                assert!(run_test(&result, run).message.starts_with("Passed"));
            }
            // A class challenge, where the exercise has one: the file's tuning() returns
            // the reference's default settings, so its figure is the reference's.
            if let Some(challenge) = &result.challenge {
                let figure = challenge
                    .figure
                    .unwrap_or_else(|| panic!("{seeds:?}: no figure: {}", challenge.message));
                assert!(
                    (figure - challenge.reference).abs() < 1e-6,
                    "{seeds:?}: {figure} against {}",
                    challenge.reference
                );
            }
        }
    }

    /// The starter scores 0: every function's test says the function threw "not
    /// implemented", and every run's that its loop stopped at the first function it
    /// called.
    pub fn check_the_starter(&self, seeds: Seeds) {
        let result = self.grade(self.exercise.declaration().starter(self.language), seeds);
        assert_eq!(result.score, 0.0);
        // What the starter's functions throw, as the harness names it.
        let thrown = match self.language {
            Language::JavaScript => "Error",
            Language::Python => "NotImplementedError",
            Language::Matlab => "error",
        };
        for function in self.functions {
            let test = function_test(&result, function);
            assert_eq!(test.points, 0.0, "{}", test.name);
            assert!(
                test.message
                    .contains(&format!("threw {thrown}: {function}: not implemented")),
                "{}: {}",
                test.name,
                test.message
            );
        }
        for run in self.runs {
            let test = run_test(&result, run);
            assert_eq!(test.status, Status::Failed);
            // The loop stops at its first call, whichever function it is: at its first
            // step, or before (as a loop that learns a noise first).
            assert!(
                (test.message.contains(&format!("{run}: at step "))
                    || test.message.contains(&format!("{run}: at the start, ")))
                    && self.functions.iter().any(|f| {
                        test.message
                            .contains(&format!(", {f}: threw {thrown}: {f}: not implemented"))
                    }),
                "{}",
                test.message
            );
        }
        // Over the class challenge's run the loop stops at the first function too, and
        // what the code threw there is not repeated: it could carry the run's data out.
        if let Some(challenge) = &result.challenge {
            assert_eq!(challenge.figure, None);
            assert!(
                challenge.message.contains("it threw")
                    && !challenge.message.contains("not implemented"),
                "{}",
                challenge.message
            );
        }
    }

    /// Every mistake of the catalogue (at least `at_least` of them, and one at least for
    /// every function) fails as it says on every seed: see the module's documentation.
    pub fn check_the_mistakes(&self, seeds: &[Seeds], at_least: usize) {
        let mistakes = self.mistakes();
        assert!(
            mistakes.len() >= at_least,
            "{}: {} mistakes",
            self.catalogue.0,
            mistakes.len()
        );
        for function in self.functions {
            assert!(
                mistakes.iter().any(|m| m.breaks == *function),
                "no mistake breaks {function}"
            );
        }
        self.check_a_sample_of_mistakes(seeds);
    }

    /// Every mistake of a catalogue that samples the classic mistakes (as the files of
    /// another language than JavaScript do: the hints read outputs, not code, so a sample
    /// shows they carry over) fails as it says on every seed.
    pub fn check_a_sample_of_mistakes(&self, seeds: &[Seeds]) {
        let mistakes = self.mistakes();
        let work: Vec<(&Mistake, Seeds)> = mistakes
            .iter()
            .flat_map(|m| seeds.iter().map(move |&seeds| (m, seeds)))
            .collect();
        let found: Vec<String> = parallel(&work, |(mistake, seeds)| self.problems(mistake, *seeds))
            .into_iter()
            .flatten()
            .collect();
        eprintln!(
            "{} mistakes graded on {} seeds each",
            mistakes.len(),
            seeds.len()
        );
        assert!(found.is_empty(), "{}", found.join("\n"));
    }

    /// What is wrong with the grading of `mistake` on one seed, if anything.
    fn problems(&self, mistake: &Mistake, seeds: Seeds) -> Vec<String> {
        let source = match self.source(mistake) {
            Ok(source) => source,
            Err(e) => return vec![e],
        };
        let result = self.grade(&source, seeds);
        let name = format!("{} on {seeds:?}", mistake.name);
        let mut problems = Vec::new();
        let hint: grading::HintKind = serde_json::from_value(json!(mistake.hint))
            .unwrap_or_else(|e| panic!("{}: no hint {:?}: {e}", mistake.name, mistake.hint));
        for function in self.functions {
            let test = function_test(&result, function);
            if mistake.also.iter().any(|f| f == function) {
                if test.status != Status::Failed {
                    problems.push(format!(
                        "{name}: passes {}, which calls {}",
                        test.name, mistake.breaks
                    ));
                }
                continue;
            }
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
        for run in self.runs {
            let test = run_test(&result, run);
            let failed = test.status == Status::Failed;
            if failed != mistake.breaks_run(run) && !mistake.by_chance.iter().any(|r| r == run) {
                problems.push(format!(
                    "{name}: the run {run} {}: {}",
                    if failed { "fails" } else { "passes" },
                    test.message
                ));
            }
            // The functions failing, in the contract's order.
            let failing: Vec<&str> = self
                .functions
                .iter()
                .copied()
                .filter(|f| *f == mistake.breaks || mistake.also.iter().any(|a| a == f))
                .collect();
            if failed
                && !test.message.contains(&format!(
                    "These functions fail their own tests: {}.",
                    failing.join(", ")
                ))
            {
                problems.push(format!(
                    "{name}: the run {run} does not name {}: {}",
                    mistake.breaks, test.message
                ));
            }
        }
        problems
    }
}

/// The test of `subject` in a result.
fn test_of<'a>(result: &'a GradeResult, subject: &Subject) -> &'a Test {
    result
        .tests
        .iter()
        .find(|t| t.subject == *subject)
        .unwrap_or_else(|| {
            let names: Vec<&str> = result.tests.iter().map(|t| t.name.as_str()).collect();
            panic!("no test of {subject:?} in {names:?}")
        })
}

/// What the test of `function` says, once it is known that it alone of the functions
/// failed, with the runs (which call it), and that the result is gradable: the student's
/// code, not the sandbox.
pub fn failing_alone(result: &GradeResult, function: &str) -> String {
    assert!(result.gradable, "not gradable: {:?}", result.reason);
    for test in &result.tests {
        let expected = match &test.subject {
            Subject::Function(name) if name != function => Status::Passed,
            _ => Status::Failed,
        };
        assert_eq!(test.status, expected, "{}: {}", test.name, test.message);
    }
    function_test(result, function).message.clone()
}

pub fn function_test<'a>(result: &'a GradeResult, function: &str) -> &'a Test {
    test_of(result, &Subject::Function(function.to_owned()))
}

pub fn run_test<'a>(result: &'a GradeResult, run: &str) -> &'a Test {
    test_of(result, &Subject::Run(run.to_owned()))
}

/// `work` on every item, the items split among as many threads as there are cores;
/// results in order.
pub fn parallel<T: Sync, R: Send>(items: &[T], work: impl Fn(&T) -> R + Sync) -> Vec<R> {
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
