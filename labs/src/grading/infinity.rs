//! Infinities in the JSON that passes between the grader and the harness: JSON has no
//! number for them, so an infinite argument (`Lambda_M` when no reading is rejected) is
//! written as the string "Infinity", and the harness turns it back into a number. What the
//! harness reports uses the same strings for every number JSON cannot hold ("NaN",
//! "Infinity", "-Infinity"); this module is the one place the grader writes and reads them.

use serde::{Deserialize, Deserializer, Serializer, de::Error};
use serde_json::{Value, json};

/// How JSON carries positive infinity here.
pub const INFINITY: &str = "Infinity";
/// How the harness reports the other numbers JSON has none for.
pub const MINUS_INFINITY: &str = "-Infinity";
pub const NOT_A_NUMBER: &str = "NaN";

/// Whether a text the harness reported stands for a number JSON cannot hold.
pub fn is_non_finite(text: &str) -> bool {
    [INFINITY, MINUS_INFINITY, NOT_A_NUMBER].contains(&text)
}

/// The value as an argument: a number, or [`INFINITY`].
pub fn value(number: f64) -> Value {
    if number.is_infinite() && number > 0.0 {
        json!(INFINITY)
    } else {
        json!(number)
    }
}

/// A number, or positive infinity written as [`INFINITY`].
pub fn read(value: &Value) -> Option<f64> {
    match value {
        Value::String(text) if text == INFINITY => Some(f64::INFINITY),
        value => value.as_f64(),
    }
}

/// `#[serde(with = "infinity")]`: serialises as [`value`] does.
pub fn serialize<S: Serializer>(number: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    if number.is_infinite() && *number > 0.0 {
        serializer.serialize_str(INFINITY)
    } else {
        serializer.serialize_f64(*number)
    }
}

/// `#[serde(with = "infinity")]`: reads what [`serialize`] writes.
pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    let value = Value::deserialize(deserializer)?;
    read(&value)
        .ok_or_else(|| D::Error::custom(format!("{value} is neither a number nor \"{INFINITY}\"")))
}
