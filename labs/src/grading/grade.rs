//! Grading: the student's outputs against the reference, test by test. Each function's
//! test earns its points in proportion to the cases it passes; each data-set test earns
//! its points when the run stays within the lab's bound.

use super::hints::{HintKind, describe, diagnose};
use super::outputs::{FunctionOutput, Outputs, RunOutput};
use super::plan::{FUNCTION_LIMIT_MS, Plan, RUN_LIMIT_MS, RunSpec, bound, mode_name};
use super::result::{Failure, GradeResult, RunFigures, Status, Test, Visibility};
use crate::cases::{Case, FUNCTIONS, Tolerance};
use crate::dataset::Kind;
use crate::ekf::{self, Belief, Decision, UpdateMode};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;

pub const LAB: &str = "ekf-localization";
/// Points of each function's test and of each data-set test.
pub const POINTS: f64 = 10.0;
/// Failing cases shown in detail per function.
const SHOWN_FAILURES: usize = 4;

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let mut tests: Vec<Test> = FUNCTIONS
        .iter()
        .map(|&function| {
            let output = outputs.functions.iter().find(|f| f.function == function);
            function_test(plan, function, output)
        })
        .collect();
    let failing: Vec<&str> = tests
        .iter()
        .filter(|t| t.status == Status::Failed)
        .map(|t| t.name.split(':').next().unwrap_or_default())
        .collect();
    let failing = failing.join(", ");
    for kind in Kind::ALL {
        tests.push(dataset_test(plan, outputs, kind, &failing));
    }
    let points: f64 = tests.iter().map(|t| t.points).sum();
    let max_points: f64 = tests.iter().map(|t| t.max_points).sum();
    GradeResult {
        lab: LAB.to_owned(),
        seed: plan.seed,
        gradable: true,
        reason: None,
        score: points / max_points,
        points,
        max_points,
        tests,
    }
}

fn function_test(plan: &Plan, function: &str, output: Option<&FunctionOutput>) -> Test {
    let cases: Vec<&Case> = plan.cases_of(function).collect();
    let name = format!("{function}: {} cases", cases.len());
    let Some(output) = output else {
        return failed(name, "not run".to_owned());
    };
    let mut failures = Vec::new();
    let mut passed = 0;
    for case in &cases {
        let result = output.results.iter().find(|r| r.id == case.id);
        match check(
            case,
            result.and_then(|r| r.output.as_ref()),
            result.and_then(|r| r.error.clone()),
        ) {
            None => passed += 1,
            Some(failure) => failures.push(failure),
        }
    }
    if output.results.is_empty() {
        // Nothing ran (the file does not load, or the phase was stopped): the error says
        // why, and a list of cases not run would say nothing more.
        failures.clear();
    }
    let mut lines = vec![format!("{passed} of {} cases pass.", cases.len())];
    let error = output.error.clone().or_else(|| {
        output
            .stopped
            .as_ref()
            .map(|s| s.message(FUNCTION_LIMIT_MS))
    });
    if let Some(error) = &error {
        lines.push(error.clone());
    }
    let impure = output.repeats.iter().any(|repeat| {
        let first = output.results.iter().find(|r| r.id == repeat.id);
        first.is_some_and(|first| first.output != repeat.output || first.error != repeat.error)
    });
    if impure {
        let hint = HintKind::StaleAssociation.hint();
        lines.push(format!("Hint: {}", hint.text));
        for failure in &mut failures {
            failure.hint = Some(hint.clone());
        }
    }
    for failure in failures.iter().take(SHOWN_FAILURES) {
        lines.push(failure_line(failure));
    }
    if failures.len() > SHOWN_FAILURES {
        lines.push(format!(
            "... and {} more failing cases.",
            failures.len() - SHOWN_FAILURES
        ));
    }
    let all = failures.is_empty() && error.is_none() && !impure;
    Test {
        name,
        points: if all {
            POINTS
        } else {
            POINTS * passed as f64 / cases.len().max(1) as f64
        },
        max_points: POINTS,
        status: if all { Status::Passed } else { Status::Failed },
        visibility: Visibility::Visible,
        message: lines.join("\n"),
        failures,
        run: None,
    }
}

/// The failure of one case, or None when it passes.
fn check(case: &Case, got: Option<&Value>, error: Option<String>) -> Option<Failure> {
    let mut failure = Failure {
        case: case.id.clone(),
        note: case.note.clone(),
        args: serde_json::to_value(&case.call)
            .map(|v| v["args"].clone())
            .unwrap_or_default(),
        expected: case.expected.clone(),
        got: got.cloned(),
        error,
        mismatches: Vec::new(),
        hint: None,
    };
    let Some(got) = got else {
        failure.error.get_or_insert_with(|| "not run".to_owned());
        return Some(failure);
    };
    let mismatches = case.check(got, Tolerance::default());
    if mismatches.is_empty() {
        return None;
    }
    failure.hint = diagnose(&case.call, &case.expected, got, &mismatches);
    failure.mismatches = mismatches;
    Some(failure)
}

fn failure_line(failure: &Failure) -> String {
    let mut line = format!("{} ({}): ", failure.case, failure.note);
    if let Some(error) = &failure.error {
        line.push_str(error);
    } else {
        let shown: Vec<String> = failure
            .mismatches
            .iter()
            .take(3)
            .map(|m| {
                let place = if m.path.is_empty() { "output" } else { &m.path };
                format!("{place}: expected {}, got {}", m.expected, short(&m.got))
            })
            .collect();
        line.push_str(&shown.join("; "));
        if failure.mismatches.len() > 3 {
            line.push_str(&format!("; and {} more", failure.mismatches.len() - 3));
        }
    }
    if let Some(hint) = &failure.hint {
        line.push_str(&format!("\n  Hint: {}", hint.text));
    }
    line
}

/// A value for a message: numbers and short arrays as they are, anything larger in words.
fn short(value: &Value) -> String {
    let text = value.to_string();
    if text.len() <= 60 {
        text
    } else {
        describe(value)
    }
}

fn failed(name: String, message: String) -> Test {
    Test {
        name,
        points: 0.0,
        max_points: POINTS,
        status: Status::Failed,
        visibility: Visibility::Visible,
        message,
        failures: Vec::new(),
        run: None,
    }
}

/// The test of a data set: the first run of its kind in the plan is held to the lab's
/// bound; any other (the sequential update without odometry) is shown for comparison.
fn dataset_test(plan: &Plan, outputs: &Outputs, kind: Kind, failing: &str) -> Test {
    let mut specs = plan.runs.iter().filter(|r| r.kind == kind);
    let graded = specs.next().expect("the plan runs every kind of data set");
    let name = format!(
        "{} data set, {} update: {}",
        kind.name(),
        mode_name(graded.mode),
        match graded.mode {
            UpdateMode::Sequential => "calculate_odometry, predict, associate, update",
            UpdateMode::Batch => "calculate_odometry, predict, batch_associate, batch_update",
        }
    );
    let bound = bound(kind);
    let outcome = |spec: &RunSpec| {
        outputs
            .runs
            .iter()
            .find(|r| r.name == spec.name)
            .map_or_else(
                || Err("not run".to_owned()),
                |output| student_run(spec, output),
            )
    };
    let mae = |run: &ekf::Run| run.summary.mean_absolute_error;
    let describe_run = |spec: &RunSpec, run: &ekf::Run| {
        let e = mae(run);
        format!(
            "{} update over the first {} s ({} readings): mean absolute error (x, y, theta) = ({:.5}, {:.5}, {:.5}); {} readings rejected.",
            mode_name(spec.mode),
            spec.data
                .log
                .steps
                .last()
                .map_or(0.0, |step| step.t.round()),
            run.summary.readings,
            e.x,
            e.y,
            e.z,
            run.summary.rejected,
        )
    };
    let graded_run = outcome(graded);
    let passed = graded_run
        .as_ref()
        .is_ok_and(|run| mae(run).iter().all(|&e| e < bound));
    let mut lines = vec![if passed {
        format!("Passed: every mean absolute error is below the lab's bound of {bound}.")
    } else if failing.is_empty() {
        format!("Failed: every mean absolute error must be below the lab's bound of {bound}.")
    } else {
        format!(
            "Failed: every mean absolute error must be below the lab's bound of {bound}. These functions fail their own tests: {failing}."
        )
    }];
    lines.push(match &graded_run {
        Ok(run) => describe_run(graded, run),
        Err(error) => format!("{}: {error}", graded.name),
    });
    let mut errors = vec![graded_run.as_ref().map(mae).ok()];
    for spec in specs {
        let run = outcome(spec);
        lines.push(match &run {
            Ok(run) => format!("For comparison, the {}", describe_run(spec, run)),
            Err(error) => format!("For comparison, {}: {error}", spec.name),
        });
        errors.push(run.as_ref().map(mae).ok());
    }
    let figures = graded_run.as_ref().ok().map(|run| RunFigures {
        mean_absolute_error: errors.into_iter().flatten().map(Into::into).collect(),
        bound,
        rejected: run.summary.rejected,
        readings: run.summary.readings,
    });
    Test {
        name,
        points: if passed { POINTS } else { 0.0 },
        max_points: POINTS,
        status: if passed {
            Status::Passed
        } else {
            Status::Failed
        },
        visibility: Visibility::Visible,
        message: lines.join("\n"),
        failures: Vec::new(),
        run: figures,
    }
}

/// The student's tuning from `init`.
struct Tuning {
    mu: Vector3<f64>,
    lambda_m: f64,
}

fn tuning(dataset: &str, init: &Value) -> Result<Tuning, String> {
    let dims = |field: &str| -> Option<(usize, usize)> {
        let rows = init.get(field)?.as_array()?;
        let cols = rows.first()?.as_array()?.len();
        rows.iter()
            .all(|r| {
                r.as_array()
                    .is_some_and(|r| r.len() == cols && r.iter().all(Value::is_number))
            })
            .then_some((rows.len(), cols))
    };
    if dims("R") == Some((2, 2)) && dims("Q") == Some((3, 3)) {
        return Err(format!(
            "init('{dataset}'): {}",
            HintKind::RQSwapped.hint().text
        ));
    }
    for (field, shape) in [("sigma", (3, 3)), ("R", (3, 3)), ("Q", (2, 2))] {
        if dims(field) != Some(shape) {
            return Err(format!(
                "init('{dataset}').{field} should be a {} x {} array of rows, but is {}.",
                shape.0,
                shape.1,
                describe(init.get(field).unwrap_or(&Value::Null))
            ));
        }
    }
    let mu: [f64; 3] = serde_json::from_value(init["mu"].clone()).map_err(|_| {
        format!(
            "init('{dataset}').mu should be an array of 3 numbers, but is {}.",
            describe(&init["mu"])
        )
    })?;
    let lambda_m = match &init["Lambda_M"] {
        Value::String(s) if s == "Infinity" => f64::INFINITY,
        value => value.as_f64().filter(|v| *v >= 0.0).ok_or_else(|| {
            format!(
                "init('{dataset}').Lambda_M should be a number >= 0 (or Infinity), but is {}.",
                describe(value)
            )
        })?,
    };
    Ok(Tuning {
        mu: Vector3::from(mu),
        lambda_m,
    })
}

/// The student's run as a whole `ekf::Run` (errors against the ground truth, summary,
/// odometry for plotting), or what went wrong with it.
pub fn student_run(spec: &RunSpec, output: &RunOutput) -> Result<ekf::Run, String> {
    let dataset = spec.kind.name();
    let error = output
        .error
        .clone()
        .or_else(|| output.stopped.as_ref().map(|s| s.message(RUN_LIMIT_MS)));
    let init = output.init.as_ref().ok_or_else(|| {
        error
            .clone()
            .unwrap_or_else(|| format!("init('{dataset}') returned nothing"))
    })?;
    let tuning = tuning(dataset, init)?;
    if let Some(error) = error {
        return Err(error);
    }
    let (steps, readings) = (spec.data.log.steps.len(), spec.data.log.readings());
    if output.mu.len() != steps || output.sigma.len() != steps {
        return Err(format!(
            "the run reported {} estimates for {steps} time steps",
            output.mu.len()
        ));
    }
    if output.c.len() != readings || output.outlier.len() != readings {
        return Err(format!(
            "the run reported {} associations for {readings} readings",
            output.c.len()
        ));
    }
    let beliefs: Vec<Belief> = output
        .mu
        .iter()
        .zip(&output.sigma)
        .map(|(mu, sigma)| Belief::new(Vector3::from(*mu), Matrix3::from_row_slice(sigma)))
        .collect();
    let decisions: Vec<Decision> = output
        .c
        .iter()
        .zip(&output.outlier)
        .map(|(&c, &outlier)| Decision {
            c,
            outlier,
            mahalanobis: f64::NAN,
        })
        .collect();
    let robot = spec.kind.lab_settings().robot;
    Ok(ekf::assemble(
        &spec.data,
        &robot,
        tuning.mu,
        tuning.lambda_m,
        &beliefs,
        &decisions,
    ))
}
