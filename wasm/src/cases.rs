//! Test cases of the student functions and their comparison, for grading in the browser.

use super::{from_json, seed};
use labs::cases::{self, Case, Tolerance};
use serde_json::Value;
use wasm_bindgen::prelude::*;

/// `per_function` generated cases of every student function, as a JSON array.
#[wasm_bindgen(js_name = generateCases)]
pub fn generate_cases(seed_value: f64, per_function: usize) -> Result<String, JsError> {
    let cases = cases::generate(seed(seed_value)?, per_function);
    Ok(serde_json::to_string(&cases).expect("cases serialise"))
}

/// Compares what a student function returned (`got`, JSON) with a case (JSON, as
/// `generateCases` wrote it); the mismatches as a JSON array, empty when all is well.
#[wasm_bindgen(js_name = checkCase)]
pub fn check_case(case: &str, got: &str) -> Result<String, JsError> {
    let case: Case = from_json("case", case)?;
    let got: Value = from_json("output", got)?;
    let mismatches = case.check(&got, Tolerance::default());
    Ok(serde_json::to_string(&mismatches).expect("mismatches serialise"))
}
