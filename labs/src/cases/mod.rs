//! Test cases of the student functions: generated from a seed, or the original EL2320
//! fixtures; each holds a call and the reference output, and serialises to JSON.

mod compare;
mod contract;
mod el2320;
mod generate;

pub use compare::{
    HEADING_TURNS, Kind, Mismatch, Problem, Shape, Tolerance, compare, heading_within_turns,
    output_shape,
};
pub(crate) use contract::rows;
pub use contract::{Call, FUNCTIONS, reference};
pub use el2320::{FIXTURE_FILES, load_fixtures};
pub use generate::generate;

use serde::{Deserialize, Serialize};
use serde_json::Value;

/// One test case: a call of a student function and the output it must return.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Case {
    /// Unique within its suite: `predict/17`.
    pub id: String,
    /// What the case is about: "a landmark behind the robot".
    pub note: String,
    #[serde(flatten)]
    pub call: Call,
    pub expected: Value,
}

impl Case {
    /// Every element of `got` that differs from the expected output.
    pub fn check(&self, got: &Value, tolerance: Tolerance) -> Vec<Mismatch> {
        compare(&output_shape(&self.call), &self.expected, got, tolerance)
    }
}
