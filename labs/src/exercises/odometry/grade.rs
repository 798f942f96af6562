//! Grading the odometry exercise: the tests of the functions (as every exercise's are
//! graded), and a test per path, which earns its points when the student's functions,
//! strung together by the harness's path loop, give the reference's pose and covariance
//! after every step.

use super::contract::FUNCTIONS;
use super::job::PathRecord;
use super::plan::{PathSpec, Plan, RUN_LIMIT_MS};
use crate::Exercise;
use crate::grading::STEP_BY_STEP;
use crate::grading::{
    Beliefs, FunctionVerdicts, GradeResult, Outputs, RunOutput, Subject, Test, follows,
    function_tests,
};

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let (mut tests, functions) = function_tests(&plan.cases, &outputs.functions);
    for spec in &plan.runs {
        let output = outputs.runs.iter().find(|run| run.name == spec.name);
        tests.push(path_test(spec, output, &functions));
    }
    GradeResult::graded(Exercise::Odometry, plan.seed, plan.hidden.is_some(), tests)
}

/// The test of a path: passed when the run follows the reference at every step.
fn path_test(spec: &PathSpec, output: Option<&RunOutput>, functions: &FunctionVerdicts) -> Test {
    let steps = spec.steps();
    let outcome = output.map_or_else(|| Err("not run".to_owned()), |run| departure(spec, run));
    let passed = outcome.is_ok();
    let mut verdict = if passed {
        format!(
            "Passed: the pose and its covariance follow the reference at each of the {steps} steps."
        )
    } else {
        "Failed: the pose and its covariance must follow the reference at every step.".to_owned()
    };
    if !passed {
        verdict += &functions.explain();
    }
    let params = &spec.params;
    let mut lines = vec![
        verdict,
        format!(
            "The path: a {}, driven at {} m per step ({steps} steps), wheel base b = {} m, \
             k_r = {:.3e} m, k_l = {:.3e} m, from the pose {:?} known exactly (Sigma_p = 0). \
             Poses must match within {:e} (x and y in metres, the heading in radians, modulo \
             2 pi), covariances within {:e} of their largest element (or \
             {:e}).",
            params.shape.describe(),
            params.speed,
            params.wheel_base,
            params.k_r,
            params.k_l,
            spec.reference.path.start,
            STEP_BY_STEP.pose.absolute,
            STEP_BY_STEP.covariance_share,
            STEP_BY_STEP.covariance_floor,
        ),
    ];
    if let Err(departure) = outcome {
        lines.push(format!("{}: {departure}", spec.name));
    }
    Test::all_or_nothing(
        Subject::Run(spec.name.clone()),
        format!("{} path: {}", spec.name, FUNCTIONS.join(", ")),
        passed,
        lines.join("\n"),
    )
}

/// Where the student's run first departs from the reference (or what stopped it), or
/// nothing when it follows it throughout. The reference's poses and covariances start
/// with the start's; the run's with the first step's.
fn departure(spec: &PathSpec, output: &RunOutput) -> Result<(), String> {
    let record: PathRecord = output.completed(RUN_LIMIT_MS)?;
    let reference = &spec.reference;
    follows(
        ["p", "Sigma_p"],
        Beliefs {
            poses: &record.poses,
            covariances: &record.covariances,
        },
        Beliefs {
            poses: &reference.poses[1..],
            covariances: &reference.covariances[1..],
        },
        STEP_BY_STEP,
    )
}
