//! What every exercise's student contract gives the generic grader: its functions, and for
//! one call of one of them the arguments in the contract's order, the shape of the output,
//! the reference answer and the classic mistake a wrong answer points to. A [`Case`] is a
//! call with the output it must return.

use super::compare::{Mismatch, Shape, Tolerance, compare};
use super::hints::{Hint, Mistake};
use crate::{Error, Exercise};
use nalgebra::SMatrix;
use serde::de::{DeserializeOwned, Deserializer, IgnoredAny, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fmt::{self, Debug};

/// One call of one student function of an exercise, arguments named as in its contract.
/// Serialised as `{"function": name, "args": {...}}`.
pub trait Contract: Clone + Debug + PartialEq + Serialize + DeserializeOwned {
    /// The exercise whose functions these are.
    const EXERCISE: Exercise;
    /// The student functions, in the order the exercise introduces them.
    const FUNCTIONS: &'static [&'static str];
    /// What the functions return, typed: the reference's answer, which serialises as the
    /// contract's output (the JSON a student's function must return) and which the hints
    /// read.
    type Answer: Clone + Debug + PartialEq + Serialize;
    /// The exercise's classic mistakes.
    type Mistake: Mistake;
    /// The mistake of a function that answers a call differently in a fresh copy of the
    /// file (it keeps state between calls).
    const KEEPS_STATE: Self::Mistake;

    /// The function's name in the contract.
    fn function(&self) -> &'static str;

    /// The arguments in the contract's order, as the harness passes them: the call's
    /// fields as it serialises them (an infinity as [`super::infinity`] writes it), in the
    /// order they are declared in.
    fn arguments(&self) -> Vec<Value> {
        let text = serde_json::to_string(self).expect("calls serialise");
        let call: Serialised = serde_json::from_str(&text).expect("calls read back");
        call.args.0
    }

    /// The name of the output in the contract (the root of every path into it: `""` for an
    /// object of named fields) and its shape for this call.
    fn output_shape(&self) -> (&'static str, Shape);

    /// The reference answer.
    fn reference(&self) -> Result<Self::Answer, Error>;

    /// The reference answer as its output in the contract's shapes.
    fn reference_output(&self) -> Result<Value, Error> {
        self.reference().map(|answer| output(&answer))
    }

    /// Whether the output `got` is `answer`, within the default tolerance: what a hint
    /// asks of the answer a mistake gives.
    fn answers(&self, answer: &Self::Answer, got: &Value) -> bool {
        compare(
            &self.output_shape(),
            &output(answer),
            got,
            Tolerance::default(),
        )
        .is_empty()
    }

    /// The classic mistake that explains a failing output `got`, if one does; `expected`
    /// is the reference's answer.
    fn diagnose(
        &self,
        expected: &Self::Answer,
        got: &Value,
        mismatches: &[Mismatch],
    ) -> Option<Hint>;
}

/// An answer as the output a student's function returns.
fn output(answer: &impl Serialize) -> Value {
    serde_json::to_value(answer).expect("answers serialise")
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

/// A call as it serialises: `{"function": ..., "args": {...}}`.
#[derive(Deserialize)]
struct Serialised {
    args: InOrder,
}

/// The values of a JSON object's fields, in the order of the text.
struct InOrder(Vec<Value>);

impl<'de> Deserialize<'de> for InOrder {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Values;
        impl<'de> Visitor<'de> for Values {
            type Value = InOrder;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("the arguments of a call")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<InOrder, A::Error> {
                let mut values = Vec::new();
                while let Some((IgnoredAny, value)) = map.next_entry::<IgnoredAny, Value>()? {
                    values.push(value);
                }
                Ok(InOrder(values))
            }
        }
        deserializer.deserialize_map(Values)
    }
}

/// A matrix as the contracts write it, an array of rows.
pub fn rows<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>) -> [[f64; C]; R] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)]))
}

/// The matrix of an array of rows.
pub fn matrix_of<const R: usize, const C: usize>(a: &[[f64; C]; R]) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|i, j| a[i][j])
}
