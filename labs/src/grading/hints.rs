//! Hints: when a failing output is exactly what a classic mistake would give, the result
//! says which mistake. Each exercise names its own mistakes (and recognises them in its
//! contract's `diagnose`); the mistakes of any exercise's outputs are here, with what
//! every exercise's diagnosis uses.

use super::compare::{Mismatch, Problem};
use super::contract::Contract;
use super::infinity;
use crate::Exercise;
use crate::exercises::{Graded, Visit};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;
use std::sync::LazyLock;
use strum::VariantArray;
use ts_rs::TS;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Hint {
    pub kind: HintKind,
    pub text: String,
}

/// A classic mistake, of any exercise: stored by its name alone, which is unique across
/// the exercises (`wrong_shape`, `wheels_swapped`), and read back as the same mistake.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HintKind {
    name: &'static str,
    text: &'static str,
}

/// An exercise's classic mistakes (or the [`Common`] ones): each has a name, unique
/// across the exercises, and a text that explains it to the student.
pub trait Mistake: Copy + VariantArray + Into<&'static str> + 'static {
    fn text(self) -> &'static str;

    fn kind(self) -> HintKind {
        HintKind {
            name: self.into(),
            text: self.text(),
        }
    }

    fn hint(self) -> Hint {
        self.kind().hint()
    }
}

/// The mistakes an output of any exercise can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantArray)]
#[strum(serialize_all = "snake_case")]
pub enum Common {
    /// A matrix the contract says is symmetrised is not exactly symmetric.
    NotSymmetrised,
    WrongShape,
    NotFinite,
}

impl Mistake for Common {
    fn text(self) -> &'static str {
        match self {
            Common::NotSymmetrised => {
                "The covariance is not exactly symmetric: rounding lets its two triangles \
                 drift apart, and over a whole run the drift grows. Return (A + A^T) / 2, \
                 which is exactly symmetric."
            }
            Common::WrongShape => "The output does not have the contract's shape.",
            Common::NotFinite => {
                "The output holds NaN or Infinity: a division by zero, or arithmetic with \
                 an undefined value (an index past the end of an array?)."
            }
        }
    }
}

/// Every mistake of every exercise, the common ones first.
static EVERY: LazyLock<Vec<HintKind>> = LazyLock::new(|| {
    struct Mistakes;
    impl Visit for Mistakes {
        type Output = Vec<HintKind>;
        fn visit<G: Graded>(self) -> Vec<HintKind> {
            kinds::<<G::Call as Contract>::Mistake>()
        }
    }
    let mut every = kinds::<Common>();
    for exercise in Exercise::ALL {
        every.extend(exercise.visit(Mistakes));
    }
    every
});

impl HintKind {
    /// Every mistake of every exercise, the common ones first.
    pub fn every() -> &'static [HintKind] {
        &EVERY
    }

    /// Its name, as it is stored.
    pub fn name(self) -> &'static str {
        self.name
    }

    pub fn text(self) -> &'static str {
        self.text
    }

    pub fn hint(self) -> Hint {
        Hint {
            kind: self,
            text: self.text.to_owned(),
        }
    }
}

fn kinds<M: Mistake>() -> Vec<HintKind> {
    M::VARIANTS.iter().map(|m| m.kind()).collect()
}

impl Serialize for HintKind {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name)
    }
}

impl<'de> Deserialize<'de> for HintKind {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<HintKind, D::Error> {
        let name = String::deserialize(deserializer)?;
        HintKind::every()
            .iter()
            .copied()
            .find(|kind| kind.name == name)
            .ok_or_else(|| {
                serde::de::Error::custom(format!("no exercise has the mistake {name:?}"))
            })
    }
}

/// The hint of the one mistake among `kinds` (each listed as often as it explains the
/// output), or none when no mistake or more than one explains it.
pub fn the_only<M: Mistake + PartialEq>(kinds: impl IntoIterator<Item = M>) -> Option<Hint> {
    let mut kinds = kinds.into_iter();
    let first = kinds.next()?;
    kinds.all(|kind| kind == first).then(|| first.hint())
}

/// The hint an output's form gives before its numbers are looked at, if it gives one: NaN
/// or Infinity; the wrong shape (`transposed`, when the transpose of the output would be
/// right and the exercise has a hint for that, else what the shape should be); a wrapped
/// angle outside [-pi, pi) (`not_wrapped`); a covariance not exactly symmetric.
pub fn form_hint<C: Contract>(
    call: &C,
    expected: &C::Answer,
    got: &Value,
    mismatches: &[Mismatch],
    transposed: Option<HintKind>,
    not_wrapped: HintKind,
) -> Option<Hint> {
    let any = |problem| mismatches.iter().any(|m| m.problem == problem);
    if holds_non_finite(got) {
        return Some(Common::NotFinite.hint());
    }
    if any(Problem::WrongShape) {
        let right_transposed = || transpose(got).is_some_and(|t| call.answers(expected, &t));
        if let Some(kind) = transposed.filter(|_| right_transposed()) {
            return Some(kind.hint());
        }
        return mismatches
            .iter()
            .find(|m| m.problem == Problem::WrongShape)
            .map(|m| shape_hint(m, got));
    }
    if any(Problem::NotWrapped) {
        return Some(not_wrapped.hint());
    }
    if any(Problem::NotSymmetric) {
        return Some(Common::NotSymmetrised.hint());
    }
    None
}

/// Whether the output holds a number JSON cannot (the harness writes them as strings).
pub fn holds_non_finite(value: &Value) -> bool {
    match value {
        Value::String(s) => infinity::is_non_finite(s),
        Value::Array(items) => items.iter().any(holds_non_finite),
        Value::Object(fields) => fields.values().any(holds_non_finite),
        _ => false,
    }
}

/// What is wrong with an output of the wrong shape, in words: what the element should be,
/// what it is, and for an object with a missing field, the fields it has.
fn shape_hint(mismatch: &Mismatch, got: &Value) -> Hint {
    let place = if mismatch.path.is_empty() {
        "The output".to_owned()
    } else {
        format!("`{}`", mismatch.path)
    };
    let mut text = format!(
        "{place} should be {}, but is {}.",
        describe(&mismatch.expected),
        describe(&mismatch.got)
    );
    if let (Value::Null, Some(fields)) = (&mismatch.got, got.as_object()) {
        let names: Vec<&str> = fields.keys().map(String::as_str).collect();
        text.push_str(&if names.is_empty() {
            " The returned object has no fields; field names are those of the contract.".to_owned()
        } else {
            format!(
                " The returned object has the fields {}; field names are those of the contract.",
                names.join(", ")
            )
        });
    }
    Hint {
        kind: Common::WrongShape.kind(),
        text,
    }
}

/// A value's shape in words: "a 3 x 3 array of rows", "an object with fields mu, sigma".
pub fn describe(value: &Value) -> String {
    match value {
        Value::Null => "missing".to_owned(),
        Value::Bool(_) => "true or false".to_owned(),
        Value::Number(_) => "a number".to_owned(),
        Value::String(s) if infinity::is_non_finite(s) || s == "undefined" => s.clone(),
        Value::String(_) => "a string".to_owned(),
        Value::Array(items) => {
            let n = items.len();
            if n > 0 && items.iter().all(Value::is_number) {
                format!("an array of {n} numbers")
            } else if let Some(cols) = items.first().and_then(Value::as_array).map(Vec::len) {
                if items
                    .iter()
                    .all(|row| row.as_array().is_some_and(|r| r.len() == cols))
                {
                    format!("a {n} x {cols} array of rows")
                } else {
                    format!("an array of {n} rows of different lengths")
                }
            } else {
                format!("an array of {n} elements")
            }
        }
        Value::Object(fields) => {
            let names: Vec<&str> = fields.keys().map(String::as_str).collect();
            format!("an object with the fields {}", names.join(", "))
        }
    }
}

/// A matrix (an array of rows) transposed; None for anything else.
pub fn transpose(value: &Value) -> Option<Value> {
    let rows: Vec<&Vec<Value>> = value
        .as_array()?
        .iter()
        .map(Value::as_array)
        .collect::<Option<_>>()?;
    let cols = rows.first()?.len();
    if rows.iter().any(|r| r.len() != cols) {
        return None;
    }
    Some(Value::Array(
        (0..cols)
            .map(|j| Value::Array(rows.iter().map(|r| r[j].clone()).collect()))
            .collect(),
    ))
}

/// Whether two numbers are each other's negatives (to rounding).
pub fn negated(expected: &Value, got: &Value) -> bool {
    match (expected.as_f64(), got.as_f64()) {
        (Some(e), Some(g)) => (e + g).abs() <= 1e-9 * (1.0 + e.abs()),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// Every exercise's hints are stored by name alone: each name is unique across the
    /// exercises and reads back as the same hint, with a text.
    #[test]
    fn every_hint_has_a_name_of_its_own_and_reads_back_as_itself() {
        let mut names = BTreeSet::new();
        let every = HintKind::every();
        assert!(every.len() > Common::VARIANTS.len());
        for &kind in every {
            let stored = serde_json::to_value(kind).unwrap();
            assert!(names.insert(stored.to_string()), "{stored} twice");
            let read: HintKind = serde_json::from_value(stored.clone()).unwrap();
            assert_eq!(read, kind, "{stored}");
            assert!(!kind.text().is_empty());
        }
        let unknown = serde_json::from_value::<HintKind>(serde_json::json!("no_such_mistake"));
        assert!(unknown.is_err());
    }
}
