//! What every exercise's student contract gives the generic grader: its functions, and for
//! one call of one of them the arguments in the contract's order, the shape of the output,
//! the reference answer and the classic mistake a wrong answer points to. A [`Case`] is a
//! call with the output it must return.

use super::compare::{Mismatch, Shape, Tolerance, compare};
use super::hints::{Hint, HintKind};
use crate::{Error, Exercise};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fmt::Debug;

/// One call of one student function of an exercise, arguments named as in its contract.
/// Serialised as `{"function": name, "args": {...}}`.
pub trait Contract: Clone + Debug + PartialEq + Serialize + DeserializeOwned {
    /// The exercise whose functions these are.
    const EXERCISE: Exercise;
    /// The student functions, in the order the exercise introduces them.
    const FUNCTIONS: &'static [&'static str];
    /// The hint for a function that answers a call differently in a fresh copy of the
    /// file (it keeps state between calls).
    const KEEPS_STATE: HintKind;

    /// The function's name in the contract.
    fn function(&self) -> &'static str;

    /// The arguments in the contract's order, as the harness passes them (an infinity as
    /// [`super::infinity`] writes it).
    fn arguments(&self) -> Vec<Value>;

    /// The name of the output in the contract (the root of every path into it: `""` for an
    /// object of named fields) and its shape for this call.
    fn output_shape(&self) -> (&'static str, Shape);

    /// The reference answer, in the contract's shapes.
    fn reference(&self) -> Result<Value, Error>;

    /// The classic mistake that explains a failing output, if one does.
    fn diagnose(&self, expected: &Value, got: &Value, mismatches: &[Mismatch]) -> Option<Hint>;
}

/// One test case: a call of a student function and the output it must return.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "C: Contract")]
pub struct Case<C> {
    /// Unique within its suite: `predict/17`.
    pub id: String,
    /// What the case is about: "a landmark behind the robot".
    pub note: String,
    #[serde(flatten)]
    pub call: C,
    pub expected: Value,
}

impl<C: Contract> Case<C> {
    /// Every element of `got` that differs from the expected output.
    pub fn check(&self, got: &Value, tolerance: Tolerance) -> Vec<Mismatch> {
        compare(&self.call.output_shape(), &self.expected, got, tolerance)
    }
}
