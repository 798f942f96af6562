//! The warm-up car: one run, or many seeds at once.

use super::{from_json, to_js};
use labs::car::{self, CarParams};
use wasm_bindgen::prelude::*;

/// The lab script's parameters, as JSON: the starting point of every experiment.
#[wasm_bindgen(js_name = carDefaults)]
pub fn car_defaults() -> String {
    serde_json::to_string(&CarParams::default()).expect("parameters serialise")
}

/// Simulates the car and runs its Kalman filter with `params` (JSON of `CarParams`;
/// missing fields take the lab's defaults).
#[wasm_bindgen(js_name = runCar)]
pub fn run_car(params: &str) -> Result<CarRun, JsError> {
    let params: CarParams = from_json("car parameters", params)?;
    Ok(CarRun {
        inner: car::run(&params).map_err(to_js)?,
    })
}

/// One run of the car, series by series.
#[wasm_bindgen]
pub struct CarRun {
    inner: car::CarRun,
}

impl CarRun {
    fn series(&self, f: impl Fn(&car::CarStep) -> f64) -> Vec<f64> {
        self.inner.steps.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl CarRun {
    pub fn t(&self) -> Vec<f64> {
        self.series(|s| s.t)
    }
    #[wasm_bindgen(js_name = truePosition)]
    pub fn true_position(&self) -> Vec<f64> {
        self.series(|s| s.truth.x)
    }
    #[wasm_bindgen(js_name = trueVelocity)]
    pub fn true_velocity(&self) -> Vec<f64> {
        self.series(|s| s.truth.y)
    }
    pub fn measurement(&self) -> Vec<f64> {
        self.series(|s| s.z)
    }
    pub fn position(&self) -> Vec<f64> {
        self.series(|s| s.mu.x)
    }
    pub fn velocity(&self) -> Vec<f64> {
        self.series(|s| s.mu.y)
    }
    /// The estimation error (estimate - truth) of the position.
    #[wasm_bindgen(js_name = positionError)]
    pub fn position_error(&self) -> Vec<f64> {
        self.series(|s| s.error().x)
    }
    /// The estimation error (estimate - truth) of the velocity.
    #[wasm_bindgen(js_name = velocityError)]
    pub fn velocity_error(&self) -> Vec<f64> {
        self.series(|s| s.error().y)
    }
    #[wasm_bindgen(js_name = positionStd)]
    pub fn position_std(&self) -> Vec<f64> {
        self.series(|s| s.std_dev()[0])
    }
    #[wasm_bindgen(js_name = velocityStd)]
    pub fn velocity_std(&self) -> Vec<f64> {
        self.series(|s| s.std_dev()[1])
    }
    #[wasm_bindgen(js_name = gainPosition)]
    pub fn gain_position(&self) -> Vec<f64> {
        self.series(|s| s.gain.x)
    }
    #[wasm_bindgen(js_name = gainVelocity)]
    pub fn gain_velocity(&self) -> Vec<f64> {
        self.series(|s| s.gain.y)
    }
    /// The standard deviations of the position and velocity errors over the second half.
    #[wasm_bindgen(js_name = errorStd)]
    pub fn error_std(&self) -> Vec<f64> {
        self.inner.error_std.to_vec()
    }
}

/// The car with `runs` seeds from `params.seed` on.
#[wasm_bindgen(js_name = carMonteCarlo)]
pub fn car_monte_carlo(params: &str, runs: u32) -> Result<CarMonteCarlo, JsError> {
    let params: CarParams = from_json("car parameters", params)?;
    Ok(CarMonteCarlo {
        inner: car::monte_carlo(&params, runs as usize).map_err(to_js)?,
    })
}

/// Many runs of the car: the actual spread of the error beside the filter's sigma.
#[wasm_bindgen]
pub struct CarMonteCarlo {
    inner: car::MonteCarlo,
}

impl CarMonteCarlo {
    fn column(rows: &[[f64; 2]], i: usize) -> Vec<f64> {
        rows.iter().map(|row| row[i]).collect()
    }
}

#[wasm_bindgen]
impl CarMonteCarlo {
    pub fn t(&self) -> Vec<f64> {
        self.inner.t.clone()
    }
    /// Mean error per step: 0 position, 1 velocity.
    #[wasm_bindgen(js_name = errorMean)]
    pub fn error_mean(&self, component: usize) -> Vec<f64> {
        Self::column(&self.inner.error_mean, component.min(1))
    }
    /// Sample standard deviation of the error per step: 0 position, 1 velocity.
    #[wasm_bindgen(js_name = errorStd)]
    pub fn error_std(&self, component: usize) -> Vec<f64> {
        Self::column(&self.inner.error_std, component.min(1))
    }
    /// The filter's own standard deviation per step: 0 position, 1 velocity.
    #[wasm_bindgen(js_name = filterStd)]
    pub fn filter_std(&self, component: usize) -> Vec<f64> {
        Self::column(&self.inner.filter_std, component.min(1))
    }
}
