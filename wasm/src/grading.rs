//! Grading in the browser: the same plan, the same comparison and the same result as on
//! the server, from the same seed. The student's code runs in a Web Worker, driven by
//! the harness with the job written here; its outputs come back to `grade`.

use super::ekf::{Dataset, EkfRun};
use super::odometry::OdometryPropagation;
use super::{exercise, from_json, seed};
use labs::exercises::ekf_localization::{self, RunSpec};
use labs::exercises::odometry::{self, PathRecord, PathSpec};
use labs::grading::{self, Plan, Reports, RunOutput};
use labs::odometry::{Path, Propagation};
use std::iter;
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

    /// The reference's poses and covariances along an odometry path run (by its name,
    /// `square`): the start, then after every step.
    #[wasm_bindgen(js_name = referencePath)]
    pub fn reference_path(&self, name: &str) -> Result<OdometryPropagation, JsError> {
        Ok(self.path(name)?.reference.clone().into())
    }

    /// The student's poses and covariances along an odometry path run (the harness's
    /// output of one run, JSON) as far as the run got: the start, known exactly as the
    /// loop takes it, then after every step the run reported.
    #[wasm_bindgen(js_name = studentPath)]
    pub fn student_path(&self, output: &str) -> Result<OdometryPropagation, JsError> {
        let output: RunOutput = from_json("run output", output)?;
        let reference = &self.path(&output.name)?.reference;
        let record: PathRecord = output.record().unwrap_or_default();
        let steps = record
            .poses
            .len()
            .min(record.covariances.len())
            .min(reference.path.steps());
        let propagation = Propagation {
            path: Path {
                start: reference.path.start,
                increments: reference.path.increments[..steps].to_vec(),
            },
            poses: iter::once(reference.poses[0])
                .chain(record.poses[..steps].iter().copied())
                .collect(),
            covariances: iter::once(reference.covariances[0])
                .chain(record.covariances[..steps].iter().copied())
                .collect(),
        };
        Ok(propagation.into())
    }
}

impl Grader {
    /// An EKF data-set run of the plan.
    fn spec(&self, name: &str) -> Result<&RunSpec, JsError> {
        let Some(plan) = self.plan.of::<ekf_localization::Plan>() else {
            return Err(JsError::new("this exercise has no data-set runs"));
        };
        plan.run(name)
            .ok_or_else(|| JsError::new(&format!("no data-set run is called {name:?}")))
    }

    /// An odometry path run of the plan.
    fn path(&self, name: &str) -> Result<&PathSpec, JsError> {
        let Some(plan) = self.plan.of::<odometry::Plan>() else {
            return Err(JsError::new("this exercise has no path runs"));
        };
        plan.run(name)
            .ok_or_else(|| JsError::new(&format!("no path run is called {name:?}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A run that reports the reference's own poses and covariances draws the reference's
    /// path; one stopped halfway draws as far as it got.
    #[test]
    fn a_student_path_is_the_start_and_the_steps_the_run_reported() {
        let grader = Grader::new("odometry", 7.0).unwrap_or_else(|_| panic!("the grader"));
        let reference = grader
            .reference_path("square")
            .unwrap_or_else(|_| panic!("the square"));
        let steps = reference.steps();
        let x = reference.pose(0);
        let y = reference.pose(1);
        let theta = reference.pose(2);
        let sigma = |k: usize| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| std::array::from_fn(|j| reference.covariance(i, j)[k]))
        };
        let output = |reported: usize| {
            json!({
                "name": "square",
                "record": {
                    "loop": "path",
                    "poses": (1..=reported).map(|k| [x[k], y[k], theta[k]]).collect::<Vec<_>>(),
                    "covariances": (1..=reported).map(sigma).collect::<Vec<_>>(),
                },
            })
            .to_string()
        };
        let whole = grader
            .student_path(&output(steps))
            .unwrap_or_else(|_| panic!("the whole run"));
        assert_eq!(whole.steps(), steps);
        assert_eq!(whole.pose(0), x);
        assert_eq!(
            whole
                .ellipses(10, 3.0, 12)
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>(),
            reference
                .ellipses(10, 3.0, 12)
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>(),
        );
        let half = grader
            .student_path(&output(steps / 2))
            .unwrap_or_else(|_| panic!("half a run"));
        assert_eq!(half.steps(), steps / 2);
        assert_eq!(half.pose(1), y[..=steps / 2]);
        assert_eq!(
            half.final_pose(),
            [x[steps / 2], y[steps / 2], theta[steps / 2]]
        );
    }
}
