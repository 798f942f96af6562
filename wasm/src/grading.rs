//! Grading in the browser: the same plan, the same comparison and the same result as on
//! the server, from the same seed. The student's code runs in a Web Worker, driven by
//! the harness with the job written here; its outputs come back to `grade`.

use super::ekf::{Dataset, EkfRun};
use super::{exercise, from_json, seed};
use labs::exercises::ekf_localization::{self, RunSpec};
use labs::grading::{self, Plan, Reports, RunOutput};
use wasm_bindgen::prelude::*;

/// The seed of a student's own variant within a course, as the server computes it.
#[wasm_bindgen(js_name = studentSeed)]
pub fn student_seed(course: &str, student: &str) -> f64 {
    grading::student_seed(course, student) as f64
}

/// Everything one grading of an exercise checks, made from a seed.
#[wasm_bindgen]
pub struct Grader {
    plan: Plan,
}

#[wasm_bindgen]
impl Grader {
    /// The grader of the exercise `lab` (by name) for the variant `seed_value`.
    #[wasm_bindgen(constructor)]
    pub fn new(lab: &str, seed_value: f64) -> Result<Grader, JsError> {
        Ok(Grader {
            plan: Plan::new(exercise(lab)?, seed(seed_value)?, None),
        })
    }

    /// What the harness needs (JSON): every call's arguments and every run's data.
    pub fn job(&self) -> String {
        serde_json::to_string(&self.plan.job()).expect("jobs serialise")
    }

    /// The result (JSON) for the harness's outputs (JSON: `{ functions, runs }`, each
    /// phase's report as the worker gave it); functions and runs missing from the outputs
    /// fail as not run, and a report that does not read fails its phase, as on the server.
    pub fn grade(&self, outputs: &str) -> Result<String, JsError> {
        let reports: Reports = from_json("outputs", outputs)?;
        let result = self.plan.grade(&reports.outputs());
        Ok(serde_json::to_string(&result).expect("results serialise"))
    }

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
        let run = match &self.plan {
            Plan::EkfLocalization(plan) => plan.run(name),
        };
        run.ok_or_else(|| JsError::new(&format!("no data-set run is called {name:?}")))
    }
}
