//! The result of a grading (format in `DESIGN.md`) and its exports to the Gradescope and
//! PrairieLearn `results.json` formats.

use super::hints::Hint;
use crate::cases::Mismatch;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GradeResult {
    pub lab: String,
    pub seed: u64,
    /// False when the sandbox itself failed (not the student's code): the submission is
    /// then neither passed nor failed, and `reason` says what happened.
    pub gradable: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Points over max points, in [0, 1].
    pub score: f64,
    pub points: f64,
    pub max_points: f64,
    pub tests: Vec<Test>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Test {
    /// Contains the name of the function it tests: `predict`, or the functions of the
    /// filter loop for a data-set run.
    pub name: String,
    pub points: f64,
    pub max_points: f64,
    pub status: Status,
    pub visibility: Visibility,
    pub message: String,
    /// The failing cases, in detail, for the browser's view.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub failures: Vec<Failure>,
    /// A data-set run's figures, for the browser's view.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunFigures>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Passed,
    Failed,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Visibility {
    Visible,
    Hidden,
    AfterDueDate,
}

/// One failing case: what was asked, what came back, how it differs, and why it may.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    pub case: String,
    pub note: String,
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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunFigures {
    /// Mean absolute error in x, y and theta, one entry per run of the test.
    pub mean_absolute_error: Vec<[f64; 3]>,
    pub bound: f64,
    pub rejected: usize,
    pub readings: usize,
}

impl GradeResult {
    /// The result of a grading the sandbox could not carry out.
    pub fn not_gradable(lab: &str, seed: u64, reason: impl Into<String>) -> GradeResult {
        GradeResult {
            lab: lab.to_owned(),
            seed,
            gradable: false,
            reason: Some(reason.into()),
            score: 0.0,
            points: 0.0,
            max_points: 0.0,
            tests: Vec::new(),
        }
    }

    pub fn test(&self, name_contains: &str) -> Option<&Test> {
        self.tests.iter().find(|t| t.name.contains(name_contains))
    }

    /// Gradescope's `results.json` (autograder specification): points per test, the
    /// message as each test's output. A submission that was not gradable carries the
    /// reason and no score, so that it costs the student nothing.
    pub fn gradescope(&self) -> Value {
        let tests: Vec<Value> = self
            .tests
            .iter()
            .map(|t| {
                json!({
                    "name": t.name,
                    "score": t.points,
                    "max_score": t.max_points,
                    "status": t.status,
                    "visibility": t.visibility,
                    "output": t.message,
                })
            })
            .collect();
        if self.gradable {
            json!({ "score": self.points, "output": self.summary(), "tests": tests })
        } else {
            json!({ "output": self.summary(), "tests": tests })
        }
    }

    /// PrairieLearn's external grader `results.json`: score in [0, 1], points per test.
    pub fn prairielearn(&self) -> Value {
        let tests: Vec<Value> = self
            .tests
            .iter()
            .map(|t| {
                json!({
                    "name": t.name,
                    "points": t.points,
                    "max_points": t.max_points,
                    "message": t.message,
                })
            })
            .collect();
        json!({
            "gradable": self.gradable,
            "score": self.score,
            "message": self.summary(),
            "tests": tests,
        })
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
