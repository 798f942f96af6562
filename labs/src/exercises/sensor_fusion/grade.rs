//! Grading the sensor-fusion exercise: the tests of the functions (as every exercise's
//! are graded), and a test per trial, which earns its points when the student's
//! functions, strung together by the harness's fusion loop, give the reference filter's
//! belief after every step.

use super::contract::FUNCTIONS;
use super::job::TrialRecord;
use super::plan::{Plan, RUN_LIMIT_MS, TrialSpec};
use crate::Exercise;
use crate::grading::{
    self, BeliefTolerance, Beliefs, FunctionVerdicts, GradeResult, Mismatch, Outputs, RunOutput,
    Subject, Test, Tolerance, follows, function_tests,
};

/// How close the beliefs along a trial must be: x and y in metres, the heading in radians
/// (modulo 2 pi). The student's arithmetic may round otherwise than the reference's; the
/// filter forgets such differences rather than growing them.
pub const POSE_TOLERANCE: Tolerance = Tolerance {
    absolute: 1e-6,
    relative: 0.0,
};
/// How close the covariances must be, as a share of the largest element of the
/// reference's covariance at that step.
pub const COVARIANCE_TOLERANCE: f64 = 1e-6;

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let (mut tests, functions) = function_tests(&plan.cases, &outputs.functions);
    for spec in &plan.runs {
        let output = outputs.runs.iter().find(|run| run.name == spec.name);
        tests.push(trial_test(spec, output, &functions));
    }
    GradeResult::graded(
        Exercise::SensorFusion,
        plan.seed,
        plan.hidden.is_some(),
        tests,
    )
}

/// The test of a trial: passed when the run follows the reference at every step.
fn trial_test(spec: &TrialSpec, output: Option<&RunOutput>, functions: &FunctionVerdicts) -> Test {
    let steps = spec.steps();
    let outcome = output.map_or_else(|| Err("not run".to_owned()), |run| departure(spec, run));
    let passed = outcome.is_ok();
    let mut verdict = if passed {
        format!("Passed: the belief follows the reference filter's at each of the {steps} steps.")
    } else {
        "Failed: the belief must follow the reference filter's at every step.".to_owned()
    };
    if !passed {
        verdict += &functions.explain();
    }
    let s = &spec.settings;
    let mut lines = vec![
        verdict,
        format!(
            "The trial: {steps} steps of 0.28 s, k_xy = {}, k_theta = {}, c_xy = {}, a field \
             of view of {} m and a gate of {:.4} (chi2inv(0.999, 3)), from the odometry's \
             first pose with standard deviations {:?}. Poses must match within {:e} (x and y \
             in metres, the heading in radians, modulo 2 pi), covariances within {:e} of \
             their largest element.",
            s.process_xy,
            s.process_theta,
            s.noise.c_xy,
            s.field_of_view,
            s.gate_threshold(),
            s.start_sigma,
            POSE_TOLERANCE.absolute,
            COVARIANCE_TOLERANCE,
        ),
    ];
    if let Err(departure) = outcome {
        lines.push(format!("{}: {departure}", spec.name));
    }
    Test::all_or_nothing(
        Subject::Run(spec.name.clone()),
        format!("{} trial: {}", spec.name, FUNCTIONS.join(", ")),
        passed,
        lines.join("\n"),
    )
}

/// Where the student's run first departs from the reference (or what stopped it), or
/// nothing when it follows it throughout.
fn departure(spec: &TrialSpec, output: &RunOutput) -> Result<(), String> {
    let record: TrialRecord = output.completed(RUN_LIMIT_MS)?;
    let reference = spec.reference_record();
    follows(NAMES, beliefs(&record), beliefs(&reference), TOLERANCE)
}

/// The first step (counted from 1) at which the beliefs `record` holds leave the
/// reference's, with the first element that differs there; none while they follow it as
/// far as they go.
pub fn first_departure(spec: &TrialSpec, record: &TrialRecord) -> Option<(usize, Mismatch)> {
    let reference = spec.reference_record();
    grading::first_departure(NAMES, beliefs(record), beliefs(&reference), TOLERANCE)
}

/// What the belief's parts are called in messages.
const NAMES: [&str; 2] = ["mu", "sigma"];

const TOLERANCE: BeliefTolerance = BeliefTolerance {
    pose: POSE_TOLERANCE,
    covariance_share: COVARIANCE_TOLERANCE,
};

fn beliefs(record: &TrialRecord) -> Beliefs<'_> {
    Beliefs {
        poses: &record.poses,
        covariances: &record.covariances,
    }
}
