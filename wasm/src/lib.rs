//! The browser's view of `labs`: conversion at the boundary only. Settings come in as
//! JSON (they are small); bulk results go out as typed arrays (`Vec<f64>` becomes a
//! `Float64Array`), one per series, so that a re-run costs what the filter costs.
//! Errors become JavaScript `Error`s carrying `labs`' message.

mod car;
mod cases;
mod ekf;
mod fusion;
mod grading;
mod mrclam;
mod odometry;

/// Each exercise's views of its runs, from its folder (`build.rs`).
mod exercises {
    include!(concat!(env!("OUT_DIR"), "/exercises.rs"));
}

pub use car::{CarMonteCarlo, CarRun, car_defaults, car_monte_carlo, run_car};
pub use cases::{check_case, generate_cases};
pub use ekf::{Dataset, EkfRun, lambda_m};
pub use fusion::{FusionRun, FusionTrial, fusion_defaults, fusion_gate_threshold};
pub use grading::{Grader, student_seed};
pub use mrclam::{MrclamFilterRun, MrclamRobot, mrclam_defaults};
pub use odometry::{
    OdometryMonteCarlo, OdometryPropagation, OdometrySystematic, OdometryUmbmark,
    odometry_defaults, odometry_monte_carlo, odometry_systematic, odometry_umbmark,
    propagate_odometry,
};

use wasm_bindgen::JsError;

/// JSON text into a `labs` type, or an error naming what was wrong with it.
fn from_json<T: serde::de::DeserializeOwned>(what: &str, json: &str) -> Result<T, JsError> {
    serde_json::from_str(json).map_err(|e| JsError::new(&format!("{what}: {e}")))
}

fn to_js(error: labs::Error) -> JsError {
    JsError::new(&error.to_string())
}

/// An exercise by name, or the error naming the known ones.
fn exercise(name: &str) -> Result<labs::Exercise, JsError> {
    name.parse()
        .map_err(|e: labs::UnknownExercise| JsError::new(&e.to_string()))
}

/// A seed from JavaScript, whose numbers are doubles: a whole number in [0, 2^53].
fn seed(value: f64) -> Result<u64, JsError> {
    if value >= 0.0 && value.fract() == 0.0 && value <= 9_007_199_254_740_992.0 {
        Ok(value as u64)
    } else {
        Err(JsError::new(&format!(
            "seed: {value} is not a whole number from 0 to 2^53"
        )))
    }
}
