//! Grading the exercise: the tests of the functions (as every exercise's are graded), and
//! a test per run, which earns its points when the student's functions, strung together by
//! the harness's loop into a UKF or a particle filter, give the reference filter's belief
//! at the start and after every step.

use super::job::{FilterRecord, RunFilter};
use super::plan::{FilterSpec, PARTICLE_FUNCTIONS, PARTICLES, Plan, RUN_LIMIT_MS, UKF_FUNCTIONS};
use crate::Exercise;
use crate::grading::STEP_BY_STEP;
use crate::grading::{
    self, Beliefs, FunctionVerdicts, GradeResult, Mismatch, Outputs, RunOutput, Subject, Test,
    follows, function_tests,
};

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let (mut tests, functions) = function_tests(&plan.cases, &outputs.functions);
    for spec in &plan.runs {
        let output = outputs.runs.iter().find(|run| run.name == spec.name);
        tests.push(run_test(spec, output, &functions));
    }
    GradeResult::graded(
        Exercise::UkfParticle,
        plan.seed,
        plan.hidden.is_some(),
        tests,
    )
}

/// The test of a run: passed when the run follows the reference at every step.
fn run_test(spec: &FilterSpec, output: Option<&RunOutput>, functions: &FunctionVerdicts) -> Test {
    let steps = spec.steps();
    let outcome = output.map_or_else(|| Err("not run".to_owned()), |run| departure(spec, run));
    let passed = outcome.is_ok();
    let filter = match spec.run.filter {
        RunFilter::Ukf => "the reference UKF's",
        RunFilter::Particle => "the reference particle filter's",
    };
    let mut verdict = if passed {
        format!(
            "Passed: the belief follows {filter} at the start and each of the {} steps.",
            steps - 1
        )
    } else {
        format!("Failed: the belief must follow {filter} at every step.")
    };
    if !passed {
        verdict += &functions.explain();
    }
    let learned = format!(
        "Q learned from {} residuals and the alphas from {} commands.",
        spec.run.residuals.len(),
        spec.run.commanded.len()
    );
    let what = match spec.run.filter {
        RunFilter::Ukf => format!(
            "The run: a UKF over {} steps of {} s of a generated robot, {} readings of \
             posts, the gate at {:.4} (chi2inv(0.999, 2)), {learned}",
            steps - 1,
            spec.run.dt,
            readings(spec),
            spec.run.gate,
        ),
        RunFilter::Particle => format!(
            "The run: a particle filter of {PARTICLES} particles over {} steps of {} s of a \
             generated robot, {} readings of posts, every random number given, {learned}",
            steps - 1,
            spec.run.dt,
            readings(spec),
        ),
    };
    let mut lines = vec![
        verdict,
        format!(
            "{what} Poses must match within {:e} (x and y in metres, the heading in radians, \
             modulo 2 pi), covariances within {:e} of their largest element (or \
             {:e}).",
            STEP_BY_STEP.pose.absolute,
            STEP_BY_STEP.covariance_share,
            STEP_BY_STEP.covariance_floor,
        ),
    ];
    if let Err(departure) = outcome {
        lines.push(format!("{}: {departure}", spec.name));
    }
    let functions = match spec.run.filter {
        RunFilter::Ukf => UKF_FUNCTIONS.as_slice(),
        RunFilter::Particle => PARTICLE_FUNCTIONS.as_slice(),
    };
    Test::all_or_nothing(
        Subject::Run(spec.name.clone()),
        format!("{} run: {}", spec.name, functions.join(", ")),
        passed,
        lines.join("\n"),
    )
}

fn readings(spec: &FilterSpec) -> usize {
    spec.run.steps.iter().map(|s| s.readings.len()).sum()
}

/// Where the student's run first departs from the reference (or what stopped it), or
/// nothing when it follows it throughout.
fn departure(spec: &FilterSpec, output: &RunOutput) -> Result<(), String> {
    let record: FilterRecord = output.completed(RUN_LIMIT_MS)?;
    follows(
        NAMES,
        beliefs(&record),
        beliefs(&spec.reference),
        STEP_BY_STEP,
    )
}

/// The first step (counted from 1, the start) at which the beliefs `record` holds leave
/// the reference's, with the first element that differs there; none while they follow it
/// as far as they go.
pub fn first_departure(spec: &FilterSpec, record: &FilterRecord) -> Option<(usize, Mismatch)> {
    grading::first_departure(
        NAMES,
        beliefs(record),
        beliefs(&spec.reference),
        STEP_BY_STEP,
    )
}

/// What the belief's parts are called in messages.
const NAMES: [&str; 2] = ["mu", "sigma"];

fn beliefs(record: &FilterRecord) -> Beliefs<'_> {
    Beliefs {
        poses: &record.poses,
        covariances: &record.covariances,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cloud resampled to copies of one particle while the robot stands still has a
    /// covariance of rounding alone (about 1e-30), which another order of the same sums
    /// gives otherwise: that passes, a real difference does not.
    #[test]
    fn a_collapsed_cloud_is_held_to_the_floor() {
        let collapsed = |spec: &FilterSpec| {
            spec.reference
                .covariances
                .iter()
                .position(|s| s.iter().flatten().all(|v| v.abs() < 1e-20))
        };
        // A few seeds in a hundred collapse their cloud.
        let (plan, k) = (1..=400)
            .map(|seed| Plan::new(seed, None))
            .find_map(|plan| {
                let k = collapsed(plan.run("particle-filter")?)?;
                Some((plan, k))
            })
            .expect("a seed whose cloud collapses");
        let spec = plan
            .run("particle-filter")
            .expect("the particle filter's run");
        let mut record = spec.reference.clone();
        record.covariances[k][0][1] += 3e-25;
        record.covariances[k][1][0] += 3e-25;
        assert_eq!(first_departure(spec, &record).map(|(step, _)| step), None);
        record.covariances[k][0][1] += 1e-9;
        assert_eq!(
            first_departure(spec, &record).map(|(step, _)| step),
            Some(k + 1)
        );
    }
}
