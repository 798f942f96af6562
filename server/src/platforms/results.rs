//! A result in the `results.json` of the platforms courses grade on: Gradescope's
//! autograder and PrairieLearn's external grader. Each type holds exactly the fields of
//! the platform's documented format that estlab writes, so a test can read a file back
//! and refuse any other.

use labs::Exercise;
use labs::grading::{Challenge, GradeResult, Status, Visibility};
use serde::{Deserialize, Serialize};

/// Gradescope's `results.json` (the autograder specification).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GradescopeResults {
    /// The total; absent when the submission was not gradable (Gradescope then adds up
    /// the tests, none, so the submission scores 0 and says why).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub score: Option<f64>,
    /// Shown above the tests.
    pub output: String,
    pub tests: Vec<GradescopeTest>,
    /// The class challenge's figure, on the assignment's leaderboard (where its settings
    /// turn the leaderboard on).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub leaderboard: Vec<LeaderboardEntry>,
    pub extra_data: GraderData,
}

/// A column of Gradescope's leaderboard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LeaderboardEntry {
    pub name: String,
    pub value: f64,
    /// "asc": lower is better.
    pub order: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GradescopeTest {
    pub name: String,
    pub score: f64,
    pub max_score: f64,
    pub status: Status,
    pub visibility: Visibility,
    pub output: String,
}

/// Which grader graded which variant, for the instructor looking at a result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraderData {
    /// The grader's version: estlab's release and a hash of what it grades.
    pub grader: String,
    /// None when the package could not be read, which says which exercise it grades.
    pub lab: Option<Exercise>,
    pub seed: u64,
    /// What drew the hidden cases with the grader's secret (`estlab grade --javascript
    /// quickjs --secret FILE --submission KEY` grades the same file the same way); none
    /// without hidden cases.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hidden_key: Option<i64>,
}

/// PrairieLearn's external grader `results.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrairieLearnResults {
    /// False: "invalid, not gradable", which costs the student no attempt.
    pub gradable: bool,
    /// In [0, 1].
    pub score: f64,
    pub message: String,
    /// Why the submission was not gradable.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format_errors: Option<String>,
    pub tests: Vec<PrairieLearnTest>,
    /// estlab's own: which grader graded which variant (PrairieLearn keeps any further
    /// field with the result).
    pub estlab: GraderData,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrairieLearnTest {
    pub name: String,
    pub points: f64,
    pub max_points: f64,
    pub message: String,
}

/// The class challenge as a test worth nothing: its name, and its figure beside the
/// reference's with the message.
fn challenge_test(challenge: &Challenge) -> (String, String) {
    let figure = challenge.figure.map_or("no figure".to_owned(), |f| {
        let spread = challenge
            .spread
            .map_or(String::new(), |s| format!(" ± {s:.4}"));
        format!("{f:.4}{spread} {}", challenge.unit)
    });
    (
        format!("Class challenge (no points): {}", challenge.measure),
        format!(
            "Your figure: {figure}; the reference filter's: {:.4} {}.\n{}",
            challenge.reference, challenge.unit, challenge.message
        ),
    )
}

/// What a test's output says in place of the failing hidden cases before the due date.
pub const HIDDEN_LATER: &str = "The failing hidden cases are described after the due date.";

/// The summary line with the variant and the grader that graded it.
fn signed(result: &GradeResult, grader: &str) -> String {
    format!(
        "{}\nVariant: seed {}. Graded by {grader}.",
        result.summary(),
        result.seed
    )
}

fn grader_data(result: &GradeResult, grader: &str, hidden_key: Option<i64>) -> GraderData {
    GraderData {
        grader: grader.to_owned(),
        lab: Some(result.exercise),
        seed: result.seed,
        hidden_key: hidden_key.filter(|_| result.hidden_cases),
    }
}

/// What a package that cannot be read says of itself, where a grader's data would be.
fn unreadable_grader() -> GraderData {
    GraderData {
        grader: "estlab".to_owned(),
        lab: None,
        seed: 0,
        hidden_key: None,
    }
}

/// A submission the package could not grade, and why, for a person.
fn not_gradable(reason: &str) -> String {
    format!("Not gradable: {reason}\nVariant: seed 0. Graded by estlab.")
}

impl GradescopeResults {
    /// Gradescope's `results.json`: points per test and the message as its output. The
    /// details of failing hidden cases move out of a test's output into a test of their
    /// own, worth nothing and shown after the due date; their count stays in the test's
    /// first line, as estlab's own server shows it.
    pub fn of(result: &GradeResult, grader: &str, hidden_key: Option<i64>) -> GradescopeResults {
        let mut tests = Vec::new();
        for t in &result.tests {
            let output = if t.hidden_detail.is_empty() {
                t.message.clone()
            } else {
                t.message.replacen(&t.hidden_detail, HIDDEN_LATER, 1)
            };
            tests.push(GradescopeTest {
                name: t.name.clone(),
                score: t.points,
                max_score: t.max_points,
                status: t.status,
                visibility: t.visibility,
                output,
            });
            if !t.hidden_detail.is_empty() {
                tests.push(GradescopeTest {
                    name: format!("{}: the failing hidden cases", t.name),
                    score: 0.0,
                    max_score: 0.0,
                    status: Status::Failed,
                    visibility: Visibility::AfterDueDate,
                    output: t.hidden_detail.clone(),
                });
            }
        }
        let mut leaderboard = Vec::new();
        if let Some(challenge) = &result.challenge {
            let (name, output) = challenge_test(challenge);
            tests.push(GradescopeTest {
                name,
                score: 0.0,
                max_score: 0.0,
                status: if challenge.figure.is_some() {
                    Status::Passed
                } else {
                    Status::Failed
                },
                visibility: Visibility::Visible,
                output,
            });
            leaderboard.extend(challenge.figure.map(|value| LeaderboardEntry {
                name: format!("Class challenge ({})", challenge.unit),
                value,
                order: "asc".to_owned(),
            }));
        }
        GradescopeResults {
            score: result.gradable.then_some(result.points),
            output: signed(result, grader),
            tests,
            leaderboard,
            extra_data: grader_data(result, grader, hidden_key),
        }
    }

    /// The results of a package that could not grade the submission (worth nothing).
    pub fn unreadable(reason: &str) -> GradescopeResults {
        GradescopeResults {
            score: None,
            output: not_gradable(reason),
            tests: Vec::new(),
            leaderboard: Vec::new(),
            extra_data: unreadable_grader(),
        }
    }
}

impl PrairieLearnResults {
    /// PrairieLearn's external grader `results.json`: score in [0, 1], points per test.
    pub fn of(result: &GradeResult, grader: &str, hidden_key: Option<i64>) -> PrairieLearnResults {
        PrairieLearnResults {
            gradable: result.gradable,
            score: result.score,
            message: signed(result, grader),
            format_errors: result.reason.clone().filter(|_| !result.gradable),
            tests: result
                .tests
                .iter()
                .map(|t| PrairieLearnTest {
                    name: t.name.clone(),
                    points: t.points,
                    max_points: t.max_points,
                    message: t.message.clone(),
                })
                .chain(result.challenge.as_ref().map(|challenge| {
                    let (name, message) = challenge_test(challenge);
                    PrairieLearnTest {
                        name,
                        points: 0.0,
                        max_points: 0.0,
                        message,
                    }
                }))
                .collect(),
            estlab: grader_data(result, grader, hidden_key),
        }
    }

    /// The results of a package that could not grade the submission (not gradable, which
    /// costs no attempt).
    pub fn unreadable(reason: &str) -> PrairieLearnResults {
        PrairieLearnResults {
            gradable: false,
            score: 0.0,
            message: not_gradable(reason),
            format_errors: Some(reason.to_owned()),
            tests: Vec::new(),
            estlab: unreadable_grader(),
        }
    }
}
