//! The result of a grading (`DESIGN.md`, "The result").

use super::compare::Mismatch;
use super::hints::{Hint, HintKind, describe};
use crate::Exercise;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use ts_rs::TS;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct GradeResult {
    /// The exercise graded (`lab` on the wire, as results have always named it).
    #[serde(rename = "lab")]
    pub exercise: Exercise,
    pub seed: u64,
    /// False when the sandbox itself failed (not the student's code): the submission is
    /// then neither passed nor failed, and `reason` says what happened.
    pub gradable: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Whether hidden cases were graded (on the server, which alone has the secret they
    /// are drawn from); without them the result covers the shown cases only.
    #[serde(default)]
    pub hidden_cases: bool,
    /// Points over max points, in [0, 1].
    pub score: f64,
    pub points: f64,
    pub max_points: f64,
    pub tests: Vec<Test>,
    /// The exercise's class challenge, where it has one and the grading ran it (on the
    /// server); it earns no points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub challenge: Option<Challenge>,
}

/// A class challenge's figure of one submission: the student's own filter, with the
/// settings they chose, over a run their class never sees (the same for every submission
/// of a course), lower the better. It ranks the class; it does not grade.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Challenge {
    /// What the figure measures, for a person: "the RMS position error averaged over 5
    /// held-out trials (1900 steps in all)".
    pub measure: String,
    /// The unit of the figures ("m").
    pub unit: String,
    /// The student's figure; none when the run gave none (`message` says why).
    pub figure: Option<f64>,
    /// How much the figure varies between the runs it is a mean of (their standard
    /// deviation), where it has a figure over several; none in results graded over one.
    #[serde(default)]
    pub spread: Option<f64>,
    /// The reference's figure over the same run, with its default settings.
    pub reference: f64,
    /// The settings used and the other figures of the run, or why it has no figure.
    pub message: String,
}

/// Points of each test: a function's, a run's.
pub const POINTS: f64 = 10.0;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Test {
    /// What a person reads: the function it tests and its count of cases (`predict: 12
    /// cases`), or the run and the functions the loop calls.
    pub name: String,
    /// What it tests, as the pages and the class's statistics tell tests apart.
    pub subject: Subject,
    pub points: f64,
    pub max_points: f64,
    pub status: Status,
    pub visibility: Visibility,
    pub message: String,
    /// The lines of `message` about failing hidden cases (which end its list of
    /// failures), for platforms that show them only after the due date.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub hidden_detail: String,
    /// The failing cases, in detail, for the browser's view.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub failures: Vec<Failure>,
    /// In the stored form: every classic mistake the failing cases point to, once each
    /// (the stored failures are fewer), for the class's statistics.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hints: Vec<HintKind>,
}

/// What a test tests: one of the student's functions, or the runs of the exercise's loop
/// that a name groups (`o3`, the EKF's runs of `o3/sequential` and `o3/batch`; `square`,
/// an odometry path). On the wire `{"kind": "function", "name": "predict"}`.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, TS)]
#[serde(tag = "kind", content = "name", rename_all = "snake_case")]
pub enum Subject {
    Function(String),
    Run(String),
}

impl Subject {
    /// The function's name, or the run's.
    pub fn name(&self) -> &str {
        match self {
            Subject::Function(name) | Subject::Run(name) => name,
        }
    }
}

impl Test {
    /// A test of `subject` that earns all its points when it passed and none otherwise.
    pub fn all_or_nothing(subject: Subject, name: String, passed: bool, message: String) -> Test {
        Test {
            name,
            subject,
            points: if passed { POINTS } else { 0.0 },
            max_points: POINTS,
            status: if passed {
                Status::Passed
            } else {
                Status::Failed
            },
            visibility: Visibility::Visible,
            message,
            hidden_detail: String::new(),
            failures: Vec::new(),
            hints: Vec::new(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Passed,
    Failed,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "snake_case")]
pub enum Visibility {
    Visible,
    Hidden,
    AfterDueDate,
}

/// One failing case: what was asked, what came back, how it differs, and why it may. A
/// hidden case keeps only its id, its note, what it threw, how many outputs differ and the
/// hint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Failure {
    pub case: String,
    pub note: String,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub hidden: bool,
    /// How many elements of the output differ, when not all of them are listed in
    /// `mismatches` (a hidden case lists none); 0 when they are.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub differing: usize,
    /// The arguments, named as in the contract.
    pub args: Value,
    pub expected: Value,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub got: Option<Value>,
    /// What the call threw.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mismatches: Vec<Mismatch>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hint: Option<Hint>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// A returned value kept in a failure when its JSON has at most this many bytes; a larger
/// one is described in words ("an array of 15000 numbers").
const KEPT_VALUE: usize = 1 << 10;
/// A differing element's values kept when their JSON has at most this many bytes.
const KEPT_ELEMENT: usize = 120;
/// Differing elements kept in a failure; the rest are counted in `differing`.
const KEPT_MISMATCHES: usize = 12;
/// Characters kept of a message the student's code wrote (what it threw), or of a hint
/// that names what it returned.
const KEPT_TEXT: usize = 500;
/// Characters kept of a test's message.
const KEPT_MESSAGE: usize = 4000;

impl Failure {
    /// A hidden case's failure without what would reveal the case.
    pub fn concealed(self) -> Failure {
        if !self.hidden {
            return self;
        }
        Failure {
            args: Value::Null,
            expected: Value::Null,
            got: None,
            differing: self.mismatches.len(),
            mismatches: Vec::new(),
            ..self
        }
    }

    /// The failure within a few kilobytes, whatever the student's code returned: a large
    /// value in words, the first differing elements and a count of the rest.
    pub fn bound(&mut self) {
        let small = |value: &Value| value.to_string().len() <= KEPT_VALUE;
        if let Some(got) = self.got.as_mut().filter(|got| !small(got)) {
            *got = Value::String(describe(got));
        }
        if self.mismatches.len() > KEPT_MISMATCHES {
            self.differing = self.mismatches.len();
            self.mismatches.truncate(KEPT_MISMATCHES);
        }
        // A mismatch of the whole output (a wrong shape) would repeat it: in words.
        let brief = |value: &Value| value.to_string().len() <= KEPT_ELEMENT;
        for mismatch in &mut self.mismatches {
            for value in [&mut mismatch.expected, &mut mismatch.got] {
                if !brief(value) {
                    *value = Value::String(describe(value));
                }
            }
        }
        if let Some(error) = self.error.as_mut() {
            *error = clip(error, KEPT_TEXT);
        }
        if let Some(hint) = self.hint.as_mut() {
            hint.text = clip(&hint.text, KEPT_TEXT);
        }
    }
}

/// At most `n` characters of a text, marked when cut.
pub fn clip(text: &str, n: usize) -> String {
    match text.char_indices().nth(n) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text.to_owned(),
    }
}

/// Failing cases a stored result keeps in detail per test, and differing elements per case.
const STORED_FAILURES: usize = 1;
const STORED_MISMATCHES: usize = 4;

impl GradeResult {
    /// The result as the server keeps and serves it, a few kilobytes whatever the file
    /// returned: every test's message, and one failing case per test in detail without
    /// its arguments and expected output (known to the grader, not the student's) and with
    /// its first few differing elements.
    pub fn stored(mut self) -> GradeResult {
        for test in &mut self.tests {
            for kind in test
                .failures
                .iter()
                .filter_map(|f| f.hint.as_ref().map(|h| h.kind))
            {
                if !test.hints.contains(&kind) {
                    test.hints.push(kind);
                }
            }
            test.failures.truncate(STORED_FAILURES);
            for failure in &mut test.failures {
                failure.args = Value::Null;
                failure.expected = Value::Null;
                if failure.mismatches.len() > STORED_MISMATCHES {
                    failure.differing = failure.differing.max(failure.mismatches.len());
                    failure.mismatches.truncate(STORED_MISMATCHES);
                }
            }
        }
        self
    }

    /// The result of a grading's tests: every message within bounds, the points summed.
    pub fn graded(
        exercise: Exercise,
        seed: u64,
        hidden_cases: bool,
        mut tests: Vec<Test>,
    ) -> GradeResult {
        for test in &mut tests {
            test.message = clip(&test.message, KEPT_MESSAGE);
        }
        let points: f64 = tests.iter().map(|t| t.points).sum();
        let max_points: f64 = tests.iter().map(|t| t.max_points).sum();
        GradeResult {
            exercise,
            seed,
            gradable: true,
            reason: None,
            hidden_cases,
            score: points / max_points,
            points,
            max_points,
            tests,
            challenge: None,
        }
    }

    /// The result of a grading the sandbox could not carry out.
    pub fn not_gradable(exercise: Exercise, seed: u64, reason: impl Into<String>) -> GradeResult {
        GradeResult {
            exercise,
            seed,
            gradable: false,
            reason: Some(reason.into()),
            hidden_cases: false,
            score: 0.0,
            points: 0.0,
            max_points: 0.0,
            tests: Vec::new(),
            challenge: None,
        }
    }

    pub fn test(&self, name_contains: &str) -> Option<&Test> {
        self.tests.iter().find(|t| t.name.contains(name_contains))
    }

    /// What a result graded without hidden cases leaves out, for a person reading it.
    pub fn shown_only(exercise: Exercise) -> String {
        let unseen = exercise.declaration().runs.noun;
        format!(
            "Graded on the shown cases only: the server also grades hidden cases drawn from its secret, and {unseen} you have not seen."
        )
    }

    /// One line for the student: the score, or why there is none.
    pub fn summary(&self) -> String {
        match &self.reason {
            Some(reason) if !self.gradable => format!("Not gradable: {reason}"),
            _ => format!(
                "{} of {} points ({:.0}%), {} of {} tests passed",
                round(self.points),
                round(self.max_points),
                100.0 * self.score,
                self.tests
                    .iter()
                    .filter(|t| t.status == Status::Passed)
                    .count(),
                self.tests.len()
            ),
        }
    }
}

/// Points to two decimals, as a person reads them.
pub fn round(points: f64) -> f64 {
    (points * 100.0).round() / 100.0
}
