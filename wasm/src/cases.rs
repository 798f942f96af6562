//! Test cases of an exercise's student functions and their comparison, for grading in the
//! browser.

use super::{exercise, from_json, seed};
use labs::exercises::{Graded, Visit};
use labs::grading::{Case, Tolerance};
use serde_json::Value;
use wasm_bindgen::prelude::*;

/// `per_function` generated cases of every student function of the exercise `lab`, as a
/// JSON array.
#[wasm_bindgen(js_name = generateCases)]
pub fn generate_cases(lab: &str, seed_value: f64, per_function: usize) -> Result<String, JsError> {
    let seed = seed(seed_value)?;
    Ok(exercise(lab)?.generated_cases(seed, per_function))
}

/// Compares what a student function of the exercise `lab` returned (`got`, JSON) with a
/// case (JSON, as `generateCases` wrote it); the mismatches as a JSON array, empty when
/// all is well.
#[wasm_bindgen(js_name = checkCase)]
pub fn check_case(lab: &str, case: &str, got: &str) -> Result<String, JsError> {
    let got: Value = from_json("output", got)?;
    exercise(lab)?.visit(Checked { case, got: &got })
}

/// A case of an exercise (JSON) checked against what the student's function returned.
struct Checked<'a> {
    case: &'a str,
    got: &'a Value,
}

impl Visit for Checked<'_> {
    type Output = Result<String, JsError>;
    fn visit<G: Graded>(self) -> Result<String, JsError> {
        let case: Case<G::Call> = from_json("case", self.case)?;
        let mismatches = case.check(self.got, Tolerance::default());
        Ok(serde_json::to_string(&mismatches).expect("mismatches serialise"))
    }
}
