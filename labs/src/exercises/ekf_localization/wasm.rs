//! The EKF localization workbench's views of a student's data-set runs, as methods of
//! the browser's grader. Compiled into the wasm crate (`estlab-wasm`, whose build script
//! takes every exercise folder's `wasm.rs`), not into `labs`.

use crate::Grader;
use crate::ekf::{Dataset, EkfRun};
use crate::from_json;
use labs::exercises::ekf_localization::{self, Plan, RunSpec};
use labs::grading::RunOutput;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl Grader {
    /// The seed an EKF data-set run's data set was simulated from (before it was cut to the graded
    /// readings), for a link to the whole data set.
    #[wasm_bindgen(js_name = dataSeed)]
    pub fn data_seed(&self, name: &str) -> Result<f64, JsError> {
        Ok(self.spec(name)?.data_seed as f64)
    }

    /// The data set of an EKF data-set run (by its name, `o3/sequential`), for the map.
    pub fn dataset(&self, name: &str) -> Result<Dataset, JsError> {
        let spec = self.spec(name)?;
        Ok(Dataset::of_kind(spec.data.clone(), spec.kind))
    }

    /// The student's EKF data-set run (the harness's output of one run, JSON) as a whole
    /// run with its errors against the ground truth, for the plots.
    #[wasm_bindgen(js_name = studentRun)]
    pub fn student_run(&self, output: &str) -> Result<EkfRun, JsError> {
        let output: RunOutput = from_json("run output", output)?;
        let spec = self.spec(&output.name)?;
        ekf_localization::student_run(spec, &output)
            .map(EkfRun::from)
            .map_err(|e| JsError::new(&e))
    }
}

impl Grader {
    /// An EKF data-set run of the plan.
    fn spec(&self, name: &str) -> Result<&RunSpec, JsError> {
        let Some(plan) = self.plan().of::<Plan>() else {
            return Err(JsError::new("this exercise has no data-set runs"));
        };
        plan.run(name)
            .ok_or_else(|| JsError::new(&format!("no data-set run is called {name:?}")))
    }
}
