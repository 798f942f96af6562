//! Test cases of an exercise's student functions and their comparison, for grading in the
//! browser.

use super::{exercise, from_json, seed};
use labs::Exercise;
use labs::exercises::{ekf_localization, odometry};
use labs::grading::{Case, Contract, Generator, Tolerance};
use serde_json::Value;
use wasm_bindgen::prelude::*;

/// `per_function` generated cases of every student function of the exercise `lab`, as a
/// JSON array.
#[wasm_bindgen(js_name = generateCases)]
pub fn generate_cases(lab: &str, seed_value: f64, per_function: usize) -> Result<String, JsError> {
    let seed = seed(seed_value)?;
    Ok(match exercise(lab)? {
        Exercise::EkfLocalization => cases(ekf_localization::generate, seed, per_function),
        Exercise::Odometry => cases(odometry::generate, seed, per_function),
    })
}

/// Compares what a student function of the exercise `lab` returned (`got`, JSON) with a
/// case (JSON, as `generateCases` wrote it); the mismatches as a JSON array, empty when
/// all is well.
#[wasm_bindgen(js_name = checkCase)]
pub fn check_case(lab: &str, case: &str, got: &str) -> Result<String, JsError> {
    let got: Value = from_json("output", got)?;
    match exercise(lab)? {
        Exercise::EkfLocalization => check::<ekf_localization::Call>(case, &got),
        Exercise::Odometry => check::<odometry::Call>(case, &got),
    }
}

fn cases<C: Contract>(generate: Generator<C>, seed: u64, per_function: usize) -> String {
    serde_json::to_string(&generate(seed, per_function)).expect("cases serialise")
}

fn check<C: Contract>(case: &str, got: &Value) -> Result<String, JsError> {
    let case: Case<C> = from_json("case", case)?;
    let mismatches = case.check(got, Tolerance::default());
    Ok(serde_json::to_string(&mismatches).expect("mismatches serialise"))
}
