//! The student files of the odometry exercise the tests grade: the correct file, the
//! starter, and the classic mistakes of `tests/student/odometry/mistakes.json`, each made
//! in the correct file.

use super::{Replacement, made_in};
use labs::exercises::Graded;
use serde::Deserialize;

pub const CORRECT: &str = include_str!("../../../tests/student/odometry/correct.js");
pub const STARTER: &str = labs::exercises::odometry::Odometry::DECLARATION.starter;
const MISTAKES: &str = include_str!("../../../tests/student/odometry/mistakes.json");

/// The runs of the path loop a grading holds the student's functions to.
pub const PATHS: [&str; 2] = ["square", "figure-eight"];

/// A classic mistake: the correct file with some text replaced.
#[derive(Deserialize)]
pub struct Mistake {
    pub name: String,
    /// The function it breaks.
    pub breaks: String,
    /// The hint it must get.
    pub hint: String,
    /// The paths whose runs it breaks (all when absent): the square cannot tell which
    /// heading a step follows, the figure eight a wheel rolling backwards, and along a
    /// path a function that keeps the pose it returned, or a covariance not symmetrised,
    /// gives what it should.
    #[serde(default)]
    runs: Option<Vec<String>>,
    /// The cases (by their note) where the mistake may get no hint, because another
    /// mistake gives the very same answer there: on the spot (ds = 0) F_delta's columns
    /// swapped and its last row's signs flipped are one answer.
    #[serde(default)]
    pub unhinted: Vec<String>,
    replace: Vec<Replacement>,
}

impl Mistake {
    pub fn all() -> Vec<Mistake> {
        serde_json::from_str(MISTAKES).expect("tests/student/odometry/mistakes.json")
    }

    /// Whether the mistake breaks the run of `path`.
    pub fn breaks_path(&self, path: &str) -> bool {
        self.runs
            .as_ref()
            .is_none_or(|runs| runs.iter().any(|run| run == path))
    }

    /// The correct file with the mistake made, or which replaced text does not occur in it
    /// exactly once.
    pub fn source(&self) -> Result<String, String> {
        made_in(CORRECT, &self.name, &self.replace)
    }
}
