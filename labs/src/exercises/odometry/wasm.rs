//! The odometry workbench's views of a student's path runs, as methods of the browser's
//! grader. Compiled into the wasm crate (`estlab-wasm`, whose build script takes every
//! exercise folder's `wasm.rs`), not into `labs`.

use crate::Grader;
use crate::from_json;
use crate::odometry::OdometryPropagation;
use labs::exercises::odometry::{PathRecord, PathSpec, Plan};
use labs::grading::RunOutput;
use labs::odometry::{Path, Propagation};
use std::iter;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl Grader {
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
    /// An odometry path run of the plan.
    fn path(&self, name: &str) -> Result<&PathSpec, JsError> {
        let Some(plan) = self.plan().of::<Plan>() else {
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
