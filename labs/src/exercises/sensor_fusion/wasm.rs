//! The sensor-fusion workbench's views of a student's trial runs, as methods of the
//! browser's grader: the trial, the reference filter's run over it and the student's, in
//! the fusion page's types. Compiled into the wasm crate (`estlab-wasm`, whose build
//! script takes every exercise folder's `wasm.rs`), not into `labs`.

use crate::Grader;
use crate::from_json;
use crate::fusion::{FusionRun, FusionTrial};
use labs::exercises::sensor_fusion::{Plan, TrialRecord, TrialSpec, first_departure};
use labs::fusion::{Estimate, Use};
use labs::grading::RunOutput;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl Grader {
    /// The trial of a sensor-fusion run (by its name, `busy-room`): its times, truth and
    /// odometry.
    #[wasm_bindgen(js_name = fusionTrial)]
    pub fn fusion_trial(&self, name: &str) -> Result<FusionTrial, JsError> {
        Ok(self.trial(name)?.trial.clone().into())
    }

    /// The reference filter's run over a trial: its belief after every step, and what
    /// became of every reading.
    #[wasm_bindgen(js_name = referenceTrial)]
    pub fn reference_trial(&self, name: &str) -> Result<FusionRun, JsError> {
        let spec = self.trial(name)?;
        Ok(FusionRun::new(&spec.trial, spec.reference.clone()))
    }

    /// The student's run over a trial (the harness's output of one run, JSON): their
    /// belief after every step the run reported. The loop records beliefs only, so no
    /// step of it has a reading. An error when it reported none.
    #[wasm_bindgen(js_name = studentTrial)]
    pub fn student_trial(&self, output: &str) -> Result<FusionRun, JsError> {
        let (spec, record) = self.student_record(output)?;
        let estimates: Vec<Estimate> = record
            .poses
            .iter()
            .zip(&record.covariances)
            .take(spec.steps())
            .map(|(&pose, &sigma)| Estimate {
                pose,
                sigma,
                measurement: None,
                reading: Use::NoReading,
            })
            .collect();
        if estimates.is_empty() {
            return Err(JsError::new("the run reported no belief"));
        }
        Ok(FusionRun::new(&spec.trial, estimates))
    }

    /// The first step (counted from 1) at which the student's run (as for `studentTrial`)
    /// leaves the reference's beliefs by more than grading allows; none while it follows
    /// them as far as it got.
    #[wasm_bindgen(js_name = studentDeparture)]
    pub fn student_departure(&self, output: &str) -> Result<Option<usize>, JsError> {
        let (spec, record) = self.student_record(output)?;
        Ok(first_departure(spec, &record).map(|(step, _)| step))
    }
}

impl Grader {
    /// A sensor-fusion trial run of the plan.
    fn trial(&self, name: &str) -> Result<&TrialSpec, JsError> {
        let Some(plan) = self.plan().of::<Plan>() else {
            return Err(JsError::new("this exercise has no trial runs"));
        };
        plan.run(name)
            .ok_or_else(|| JsError::new(&format!("no trial run is called {name:?}")))
    }

    /// The trial of a student's run output (JSON), and what its loop recorded (nothing
    /// when the record does not read: the run's test says why).
    fn student_record(&self, output: &str) -> Result<(&TrialSpec, TrialRecord), JsError> {
        let output: RunOutput = from_json("run output", output)?;
        Ok((self.trial(&output.name)?, output.record().unwrap_or_default()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A run that reports the reference's own beliefs draws the reference's run and never
    /// departs; one stopped halfway draws as far as it got; one off at a step departs there.
    #[test]
    fn a_student_trial_is_the_beliefs_the_run_reported() {
        let grader = Grader::new("sensor-fusion", 7.0).unwrap_or_else(|_| panic!("the grader"));
        let spec = grader
            .trial("busy-room")
            .unwrap_or_else(|_| panic!("the busy room"));
        let steps = spec.steps();
        let reference = spec.reference_record();
        let output = |record: &TrialRecord| {
            json!({ "name": "busy-room", "record": { "loop": "fusion", "poses": record.poses, "covariances": record.covariances } })
                .to_string()
        };
        let bits = |values: Vec<f64>| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();

        let whole = grader
            .student_trial(&output(&reference))
            .unwrap_or_else(|_| panic!("the whole run"));
        let theirs = grader
            .reference_trial("busy-room")
            .unwrap_or_else(|_| panic!("the reference's run"));
        assert_eq!(whole.estimate(0).len(), steps);
        for component in 0..3 {
            assert_eq!(whole.estimate(component), theirs.estimate(component));
        }
        assert_eq!(bits(whole.ellipses(10, 3.0, 12)), bits(theirs.ellipses(10, 3.0, 12)));
        assert_eq!(whole.reading_use(), vec![0; steps]);
        assert_eq!(
            grader.student_departure(&output(&reference)).ok(),
            Some(None)
        );

        let mut half = reference.clone();
        half.poses.truncate(steps / 2);
        assert_eq!(
            grader
                .student_trial(&output(&half))
                .map(|run| run.std(2))
                .ok(),
            Some(theirs.std(2)[..steps / 2].to_vec())
        );

        let mut off = reference.clone();
        off.poses[41][1] += 1e-3;
        assert_eq!(grader.student_departure(&output(&off)).ok(), Some(Some(42)));
    }
}
