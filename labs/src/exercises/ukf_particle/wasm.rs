//! The workbench's view of a student's run of the exercise on the UKF and the particle
//! filter, as a method of the browser's grader: the run's times and truth, the posts it
//! read, the reference filter's belief and the student's as far as their run reported,
//! and where the student's first departs. Compiled into the wasm crate (`estlab-wasm`,
//! whose build script takes every exercise folder's `wasm.rs`), not into `labs`.

use crate::Grader;
use crate::from_json;
use labs::exercises::ukf_particle::{FilterRecord, FilterSpec, Plan, RunFilter, first_departure};
use labs::grading::RunOutput;
use wasm_bindgen::prelude::*;

/// A run of a filter the student's functions make, beside the reference's.
#[wasm_bindgen]
pub struct FilterView {
    particle: bool,
    times: Vec<f64>,
    truth: Vec<[f64; 3]>,
    posts: Vec<f64>,
    reference: FilterRecord,
    student: FilterRecord,
    departure: Option<usize>,
}

/// The component `i` (0 to 2) of every pose.
fn component(poses: &[[f64; 3]], i: usize) -> Vec<f64> {
    poses.iter().map(|p| p[i.min(2)]).collect()
}

/// The square root of the diagonal element `i` of every covariance.
fn deviation(covariances: &[[[f64; 3]; 3]], i: usize) -> Vec<f64> {
    let i = i.min(2);
    covariances.iter().map(|s| s[i][i].sqrt()).collect()
}

#[wasm_bindgen]
impl FilterView {
    /// Whether the run is the particle filter's (else the UKF's).
    #[wasm_bindgen(getter)]
    pub fn particle(&self) -> bool {
        self.particle
    }
    /// The time of every step, seconds from the start.
    pub fn t(&self) -> Vec<f64> {
        self.times.clone()
    }
    pub fn truth(&self, component: usize) -> Vec<f64> {
        self::component(&self.truth, component)
    }
    /// Where the posts the run read stand: x, y pairs one after the other.
    pub fn posts(&self) -> Vec<f64> {
        self.posts.clone()
    }
    pub fn reference(&self, component: usize) -> Vec<f64> {
        self::component(&self.reference.poses, component)
    }
    /// The square root of the diagonal of the reference's Sigma.
    #[wasm_bindgen(js_name = referenceStd)]
    pub fn reference_std(&self, component: usize) -> Vec<f64> {
        deviation(&self.reference.covariances, component)
    }
    /// The student's belief, as far as their run reported.
    pub fn student(&self, component: usize) -> Vec<f64> {
        self::component(&self.student.poses, component)
    }
    #[wasm_bindgen(js_name = studentStd)]
    pub fn student_std(&self, component: usize) -> Vec<f64> {
        deviation(&self.student.covariances, component)
    }
    /// The step (counted from 1, the start) where the student's belief first leaves the
    /// reference's by more than grading allows; none while it follows it.
    #[wasm_bindgen(getter)]
    pub fn departure(&self) -> Option<usize> {
        self.departure
    }
}

#[wasm_bindgen]
impl Grader {
    /// The view of the student's run (the harness's output of one run, JSON) beside the
    /// reference's; an error when the run is not this exercise's or reported no belief.
    #[wasm_bindgen(js_name = filterRun)]
    pub fn filter_run(&self, output: &str) -> Result<FilterView, JsError> {
        let output: RunOutput = from_json("run output", output)?;
        let spec = self.filter_spec(&output.name)?;
        let mut student: FilterRecord = output.record().unwrap_or_default();
        let reported = student.poses.len().min(student.covariances.len()).min(spec.steps());
        if reported == 0 {
            return Err(JsError::new("the run reported no belief"));
        }
        student.poses.truncate(reported);
        student.covariances.truncate(reported);
        let mut posts: Vec<[f64; 2]> = spec
            .run
            .steps
            .iter()
            .flat_map(|s| s.readings.iter().map(|r| r.landmark))
            .collect();
        posts.sort_by(|a, b| a.partial_cmp(b).expect("posts stand at numbers"));
        posts.dedup();
        Ok(FilterView {
            particle: spec.run.filter == RunFilter::Particle,
            times: spec.times.clone(),
            truth: spec.truth.clone(),
            posts: posts.into_iter().flatten().collect(),
            reference: spec.reference.clone(),
            departure: first_departure(spec, &student).map(|(step, _)| step),
            student,
        })
    }
}

impl Grader {
    /// A run of the plan, by its name.
    fn filter_spec(&self, name: &str) -> Result<&FilterSpec, JsError> {
        let Some(plan) = self.plan().of::<Plan>() else {
            return Err(JsError::new("this exercise has no filter runs"));
        };
        plan.run(name)
            .ok_or_else(|| JsError::new(&format!("no filter run is called {name:?}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A run that reports the reference's own beliefs never departs; one off at a step
    /// departs there; one stopped halfway shows as far as it got.
    #[test]
    fn a_student_run_is_the_beliefs_it_reported() {
        let grader = Grader::new("ukf-particle", 7.0).unwrap_or_else(|_| panic!("the grader"));
        for name in ["ukf", "particle-filter"] {
            let spec = grader
                .filter_spec(name)
                .unwrap_or_else(|_| panic!("the run {name}"));
            let reference = spec.reference.clone();
            let output = |record: &FilterRecord| {
                json!({ "name": name, "record": { "loop": "mrclam", "poses": record.poses, "covariances": record.covariances } })
                    .to_string()
            };
            let whole = grader
                .filter_run(&output(&reference))
                .unwrap_or_else(|_| panic!("the whole run"));
            assert_eq!(whole.departure(), None);
            assert_eq!(whole.student(1), whole.reference(1));
            assert_eq!(whole.t().len(), spec.steps());
            assert_eq!(whole.particle(), name == "particle-filter");
            assert!(whole.posts().len() >= 2);

            let mut off = reference.clone();
            off.poses[41][0] += 1e-3;
            let view = grader.filter_run(&output(&off)).ok();
            assert_eq!(view.map(|v| v.departure()), Some(Some(42)));

            let mut half = reference.clone();
            half.poses.truncate(spec.steps() / 2);
            let view = grader.filter_run(&output(&half)).ok();
            assert_eq!(view.map(|v| v.student_std(2).len()), Some(spec.steps() / 2));
        }
    }
}
