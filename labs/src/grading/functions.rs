//! The tests of a student's functions, for any exercise: each function's test earns its
//! points in proportion to the cases it passes (with hidden cases, the smaller share of
//! the shown and the hidden ones), a case passing only when its answer matches the
//! reference and a fresh copy of the file gives the same answer again.

use super::compare::Tolerance;
use super::contract::Contract;
use super::hints::{Mistake, describe};
use super::outputs::FunctionOutput;
use super::result::{Failure, POINTS, Status, Subject, Test, Visibility};
use super::suite::{FUNCTION_LIMIT_MS, PlannedCase, Suite, cases_of};
use serde_json::Value;

/// Failing cases shown in detail per function.
const SHOWN_FAILURES: usize = 4;
/// Failing cases kept in the result in detail (arguments, expected and returned values),
/// which keeps a stored result within tens of kilobytes whatever the file returns.
const DETAILED_FAILURES: usize = 2;

/// The tests of every function of the contract, in its order, from what the harness
/// reported; a function without a report fails as not run.
pub fn function_tests<C: Contract>(
    cases: &[PlannedCase<C>],
    outputs: &[FunctionOutput],
) -> (Vec<Test>, FunctionVerdicts) {
    let tests: Vec<Test> = C::FUNCTIONS
        .iter()
        .map(|&function| {
            let output = outputs.iter().find(|f| f.function == function);
            function_test(cases, function, output)
        })
        .collect();
    // What a run's test says of the functions: those that fail their own tests, and those
    // whose tests have not run (the browser grades what has run so far).
    let ran = |function: &str| outputs.iter().any(|f| f.function == function);
    let names = |wanted: &dyn Fn(&str, &Test) -> bool| -> String {
        C::FUNCTIONS
            .iter()
            .zip(&tests)
            .filter(|(function, test)| wanted(function, test))
            .map(|(function, _)| *function)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let verdicts = FunctionVerdicts {
        failing: names(&|function, test| ran(function) && test.status == Status::Failed),
        not_run: names(&|function, _| !ran(function)),
    };
    (tests, verdicts)
}

/// The functions named in a failing run's message, comma-separated.
pub struct FunctionVerdicts {
    pub failing: String,
    pub not_run: String,
}

impl FunctionVerdicts {
    /// What a failing run adds about the functions it calls.
    pub fn explain(&self) -> String {
        let mut text = String::new();
        if !self.failing.is_empty() {
            text += &format!(" These functions fail their own tests: {}.", self.failing);
        }
        if !self.not_run.is_empty() {
            text += &format!(
                " The tests of these functions have not run yet: {}.",
                self.not_run
            );
        }
        text
    }
}

fn function_test<C: Contract>(
    cases: &[PlannedCase<C>],
    function: &str,
    output: Option<&FunctionOutput>,
) -> Test {
    let cases: Vec<&PlannedCase<C>> = cases_of(cases, function).collect();
    let name = format!("{function}: {} cases", cases.len());
    let subject = Subject::Function(function.to_owned());
    let Some(output) = output else {
        return Test::all_or_nothing(subject, name, false, "not run".to_owned());
    };
    let error = output.error.clone().or_else(|| {
        output
            .stopped
            .as_ref()
            .map(|s| s.message(FUNCTION_LIMIT_MS))
    });
    // Fails closed: a case passes only when its result matches the reference and its
    // repeat in a fresh copy of the file gives the same answer; anything missing fails.
    let mut failures = Vec::new();
    let mut tally = Tally::default();
    let (mut impure, mut unrepeated) = (false, false);
    for planned in &cases {
        let first = output.results.iter().find(|r| r.id == planned.case.id);
        let repeat = output.repeats.iter().find(|r| r.id == planned.case.id);
        let mut failure = check(
            planned,
            first.and_then(|r| r.output.as_ref()),
            first.and_then(|r| r.error.clone()),
        );
        if failure.is_none() {
            match repeat {
                None => {
                    unrepeated = true;
                    failure = check(planned, None, Some(NOT_REPEATED.to_owned()));
                }
                Some(repeat)
                    if first.is_some_and(|first| {
                        first.output != repeat.output || first.error != repeat.error
                    }) =>
                {
                    impure = true;
                    failure = check(planned, None, Some(ANSWERED_DIFFERENTLY.to_owned()));
                }
                Some(_) => {}
            }
        } else if repeat
            .is_some_and(|repeat| first.is_some_and(|first| first.output != repeat.output))
        {
            impure = true;
        }
        tally.count(planned.suite, failure.is_none());
        failures.extend(failure);
    }
    if output.results.is_empty() && error.is_some() {
        // Nothing ran (the file does not load, or the phase was stopped): the error says
        // why, and a list of cases not run would say nothing more.
        failures.clear();
    }
    let mut lines = vec![tally.summary()];
    if let Some(error) = &error {
        lines.push(error.clone());
    }
    if unrepeated && error.is_none() {
        lines.push(
            "Some calls were not repeated in a fresh copy of your file, so the report is incomplete: does your file change built-in objects?"
                .to_owned(),
        );
    }
    if impure {
        let hint = C::KEEPS_STATE.hint();
        lines.push(format!("Hint: {}", hint.text));
        for failure in &mut failures {
            failure.hint = Some(hint.clone());
        }
    }
    // Bounded before they are written into the message: a thrown text, a hint naming the
    // fields of a returned object, a large value, all within a few hundred characters.
    for failure in &mut failures {
        failure.bound();
    }
    // Hidden cases come last in a plan, so their lines close the list of failures.
    let mut hidden_detail = Vec::new();
    for failure in failures.iter().take(SHOWN_FAILURES) {
        let line = failure_line(failure);
        if failure.hidden {
            hidden_detail.push(line.clone());
        }
        lines.push(line);
    }
    if failures.len() > SHOWN_FAILURES {
        lines.push(format!(
            "... and {} more failing cases.",
            failures.len() - SHOWN_FAILURES
        ));
    }
    let all = failures.is_empty() && error.is_none();
    failures.truncate(DETAILED_FAILURES);
    Test {
        name,
        subject,
        points: if all { POINTS } else { POINTS * tally.share() },
        max_points: POINTS,
        status: if all { Status::Passed } else { Status::Failed },
        visibility: Visibility::Visible,
        message: lines.join("\n"),
        hidden_detail: hidden_detail.join("\n"),
        failures,
        hints: Vec::new(),
    }
}

/// What a case that passed says when its repeat in a fresh copy of the file is missing.
const NOT_REPEATED: &str =
    "not repeated in a fresh copy of your file, so its answer cannot be counted";
/// What a case that passed says when its repeat answered differently.
const ANSWERED_DIFFERENTLY: &str = "answered differently when called again in a fresh copy of your file (the calls in reverse order): the function keeps state between calls";

/// The cases of a function that pass, of those shown to the student (public and their
/// variant) and of the hidden ones.
#[derive(Default)]
struct Tally {
    shown: (usize, usize),
    hidden: (usize, usize),
}

impl Tally {
    fn count(&mut self, suite: Suite, passed: bool) {
        let (pass, all) = match suite {
            Suite::Public | Suite::Variant => &mut self.shown,
            Suite::Hidden => &mut self.hidden,
        };
        *pass += usize::from(passed);
        *all += 1;
    }

    /// The share of the points earned: the share of the cases passed, and with hidden
    /// cases the smaller share of the two kinds, so that answering the shown cases from a
    /// table earns nothing.
    fn share(&self) -> f64 {
        let rate = |(pass, all): (usize, usize)| pass as f64 / all.max(1) as f64;
        if self.hidden.1 == 0 {
            rate(self.shown)
        } else {
            rate(self.shown).min(rate(self.hidden))
        }
    }

    fn summary(&self) -> String {
        let (pass, all) = self.shown;
        if self.hidden.1 == 0 {
            return format!("{pass} of {all} cases pass.");
        }
        format!(
            "{pass} of {all} shown cases and {} of {} hidden cases pass (a function earns the smaller share of the two).",
            self.hidden.0, self.hidden.1
        )
    }
}

/// The failure of one case, or None when it passes.
fn check<C: Contract>(
    planned: &PlannedCase<C>,
    got: Option<&Value>,
    error: Option<String>,
) -> Option<Failure> {
    let case = &planned.case;
    let mut failure = Failure {
        case: case.id.clone(),
        note: case.note.clone(),
        hidden: planned.suite == Suite::Hidden,
        differing: 0,
        args: serde_json::to_value(&case.call)
            .map(|v| v["args"].clone())
            .unwrap_or_default(),
        expected: case.expected.clone(),
        got: got.cloned(),
        error,
        mismatches: Vec::new(),
        hint: None,
    };
    let Some(got) = got else {
        failure.error.get_or_insert_with(|| "not run".to_owned());
        return Some(failure.concealed());
    };
    let mismatches = case.check(got, Tolerance::default());
    if mismatches.is_empty() {
        return None;
    }
    // The case's expected output is the reference's answer (the lab's own fixtures agree
    // with it within the tolerance), which the hints read typed.
    failure.hint = case
        .call
        .reference()
        .ok()
        .and_then(|expected| case.call.diagnose(&expected, got, &mismatches));
    failure.mismatches = mismatches;
    Some(failure.concealed())
}

fn failure_line(failure: &Failure) -> String {
    let mut line = format!("{} ({}): ", failure.case, failure.note);
    if let Some(error) = &failure.error {
        line.push_str(error);
    } else if failure.hidden {
        line.push_str(&format!(
            "a hidden case: {} of its outputs differ (its values are not shown)",
            failure.differing
        ));
    } else {
        let shown: Vec<String> = failure
            .mismatches
            .iter()
            .take(3)
            .map(|m| {
                let place = if m.path.is_empty() { "output" } else { &m.path };
                format!(
                    "{place}: expected {}, got {}{}",
                    short(&m.expected),
                    short(&m.got),
                    m.problem.explanation()
                )
            })
            .collect();
        line.push_str(&shown.join("; "));
        if failure.mismatches.len() > 3 {
            line.push_str(&format!("; and {} more", failure.mismatches.len() - 3));
        }
    }
    if let Some(hint) = &failure.hint {
        line.push_str(&format!("\n  Hint: {}", hint.text));
    }
    line
}

/// A value for a message: numbers and short arrays as they are, anything larger in words.
fn short(value: &Value) -> String {
    let text = value.to_string();
    if text.len() <= 60 {
        text
    } else {
        describe(value)
    }
}
