//! Grading the EKF localization exercise: the tests of the functions (as every exercise's
//! are graded), and a test per kind of data set, which earns its points when the
//! student's filter loop stays within the lab's bound.

use super::hints::HintKind;
use super::job::FilterRecord;
use super::plan::{Plan, RUN_LIMIT_MS, RunSpec, bound, mode_name};
use crate::Exercise;
use crate::dataset::Kind;
use crate::ekf::{self, Belief, Decision, UpdateMode};
use crate::grading::{
    FunctionVerdicts, GradeResult, HEADING_TURNS, Mistake, Outputs, Reach, RunOutput, Subject,
    Test, describe, function_tests, heading_within_turns, infinity,
};
use nalgebra::{Matrix2, Matrix3, Vector3};
use serde::Deserialize;
use serde_json::Value;

/// Grades what the harness reported. Tests whose outputs are missing fail as not run.
pub fn grade(plan: &Plan, outputs: &Outputs) -> GradeResult {
    let (mut tests, functions) = function_tests(&plan.cases, &outputs.functions);
    for kind in Kind::ALL {
        tests.push(dataset_test(plan, outputs, kind, &functions));
    }
    GradeResult::graded(
        Exercise::EkfLocalization,
        plan.seed,
        plan.hidden.is_some(),
        tests,
    )
}

/// The test of a data set: the first run of its kind in the plan is held to the lab's
/// bound; any other (the sequential update without odometry) is shown for comparison.
fn dataset_test(plan: &Plan, outputs: &Outputs, kind: Kind, functions: &FunctionVerdicts) -> Test {
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
            "{} update over the {} {} s ({} readings): mean absolute error (x, y, theta) = ({:.5}, {:.5}, {:.5}); {} readings rejected.",
            mode_name(spec.mode),
            match spec.reach {
                Reach::Prefix => "first",
                Reach::Whole => "whole",
            },
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
    let mut verdict = if passed {
        format!("Passed: every mean absolute error is below the lab's bound of {bound}.")
    } else {
        format!("Failed: every mean absolute error must be below the lab's bound of {bound}.")
    };
    if !passed {
        verdict += &functions.explain();
    }
    let mut lines = vec![verdict];
    lines.push(match &graded_run {
        Ok(run) => describe_run(graded, run),
        Err(error) => format!("{}: {error}", graded.name),
    });
    if !passed {
        let init = outputs
            .runs
            .iter()
            .find(|r| r.name == graded.name)
            .and_then(|output| output.record::<FilterRecord>().ok()?.init);
        lines.extend(
            init.and_then(|init| tuning(kind.name(), &init).ok())
                .and_then(|tuning| settings_hint(kind, &tuning)),
        );
    }
    for spec in specs {
        lines.push(match &outcome(spec) {
            Ok(run) => format!("For comparison, the {}", describe_run(spec, run)),
            Err(error) => format!("For comparison, {}: {error}", spec.name),
        });
    }
    // The kind's runs (`o3/sequential`, `o3/batch`) are one subject, the data set's.
    let subject = Subject::Run(kind.name().to_owned());
    Test::all_or_nothing(subject, name, passed, lines.join("\n"))
}

/// The student's tuning from `init`.
struct Tuning {
    mu: Vector3<f64>,
    sigma: Matrix3<f64>,
    r: Matrix3<f64>,
    q: Matrix2<f64>,
    lambda_m: f64,
}

/// What `init` returned, field by field, each as it came: every one is checked below, with
/// a message naming it.
#[derive(Default, Deserialize)]
struct Init {
    #[serde(default)]
    mu: Value,
    #[serde(default)]
    sigma: Value,
    #[serde(default, rename = "R")]
    r: Value,
    #[serde(default, rename = "Q")]
    q: Value,
    #[serde(default, rename = "Lambda_M")]
    lambda_m: Value,
}

fn tuning(dataset: &str, init: &Value) -> Result<Tuning, String> {
    let init: Init = match init {
        Value::Object(_) => Init::deserialize(init).unwrap_or_default(),
        _ => Init::default(),
    };
    if shape(&init.r) == Some((2, 2)) && shape(&init.q) == Some((3, 3)) {
        return Err(format!(
            "init('{dataset}'): {}",
            HintKind::RQSwapped.hint().text
        ));
    }
    for (field, value, expected) in [
        ("sigma", &init.sigma, (3, 3)),
        ("R", &init.r, (3, 3)),
        ("Q", &init.q, (2, 2)),
    ] {
        if shape(value) != Some(expected) {
            return Err(format!(
                "init('{dataset}').{field} should be a {} x {} array of rows, but is {}.",
                expected.0,
                expected.1,
                describe(value)
            ));
        }
    }
    let mu: [f64; 3] = serde_json::from_value(init.mu.clone()).map_err(|_| {
        format!(
            "init('{dataset}').mu should be an array of 3 numbers, but is {}.",
            describe(&init.mu)
        )
    })?;
    let lambda_m = infinity::read(&init.lambda_m)
        .filter(|v| *v >= 0.0)
        .ok_or_else(|| {
            format!(
                "init('{dataset}').Lambda_M should be a number >= 0 (or Infinity), but is {}.",
                describe(&init.lambda_m)
            )
        })?;
    // The shapes are checked: every element is a number.
    let element = |rows: &Value, i: usize, j: usize| rows[i][j].as_f64().unwrap_or(f64::NAN);
    Ok(Tuning {
        mu: Vector3::from(mu),
        sigma: Matrix3::from_fn(|i, j| element(&init.sigma, i, j)),
        r: Matrix3::from_fn(|i, j| element(&init.r, i, j)),
        q: Matrix2::from_fn(|i, j| element(&init.q, i, j)),
        lambda_m,
    })
}

/// The rows and columns of a matrix given as an array of rows of numbers; none for
/// anything else.
fn shape(value: &Value) -> Option<(usize, usize)> {
    let rows = value.as_array()?;
    let cols = rows.first()?.as_array()?.len();
    rows.iter()
        .all(|r| {
            r.as_array()
                .is_some_and(|r| r.len() == cols && r.iter().all(Value::is_number))
        })
        .then_some((rows.len(), cols))
}

/// The settings `init` returned that are not the lab's for this kind of data set, each
/// with its value and the lab's: what to look at first when a data-set run fails.
fn settings_hint(kind: Kind, tuning: &Tuning) -> Option<String> {
    let lab = kind.lab_settings();
    let same = |a: f64, b: f64| a == b || (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
    let same_all = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(&a, &b)| same(a, b));
    let mut differ = Vec::new();
    let mut note = |name: &str, yours: String, labs: String| {
        differ.push(format!("{name} is {yours}, the lab's is {labs}"));
    };
    if !same_all(tuning.r.as_slice(), lab.r.as_slice()) {
        note("R", matrix_text(&tuning.r), matrix_text(&lab.r));
    }
    if !same_all(tuning.q.as_slice(), lab.q.as_slice()) {
        note("Q", matrix_text(&tuning.q), matrix_text(&lab.q));
    }
    let lab_lambda = ekf::lambda_m(lab.delta_m);
    if !same(tuning.lambda_m, lab_lambda) {
        note(
            "Lambda_M",
            setting_number(tuning.lambda_m),
            format!(
                "{} (chi2inv({}, 2))",
                setting_number(lab_lambda),
                lab.delta_m
            ),
        );
    }
    if !same_all(tuning.mu.as_slice(), lab.mu0.as_slice()) {
        note("mu", matrix_text(&tuning.mu), matrix_text(&lab.mu0));
    }
    if !same_all(tuning.sigma.as_slice(), lab.sigma0.as_slice()) {
        note(
            "sigma",
            matrix_text(&tuning.sigma),
            matrix_text(&lab.sigma0),
        );
    }
    (!differ.is_empty()).then(|| {
        format!(
            "Hint: init('{}') does not return the lab's settings: {}.",
            kind.name(),
            differ.join("; ")
        )
    })
}

/// A setting for a message, to six significant digits: 0.04, not 0.04000000000000001.
fn setting_number(value: f64) -> String {
    let rounded: f64 = format!("{value:.5e}").parse().unwrap_or(value);
    format!("{rounded}")
}

/// A matrix for a message: `diag(a, b)` when it is diagonal, rows otherwise.
fn matrix_text<R: nalgebra::Dim, C: nalgebra::Dim, S: nalgebra::RawStorage<f64, R, C>>(
    a: &nalgebra::Matrix<f64, R, C, S>,
) -> String {
    let (rows, cols) = a.shape();
    let join = |values: Vec<f64>| {
        values
            .iter()
            .map(|&v| setting_number(v))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if cols == 1 {
        return format!("[{}]", join(a.iter().copied().collect()));
    }
    let diagonal = (0..rows).all(|i| (0..cols).all(|j| i == j || a[(i, j)] == 0.0));
    if diagonal && rows == cols {
        format!("diag({})", join((0..rows).map(|i| a[(i, i)]).collect()))
    } else {
        let text: Vec<String> = (0..rows)
            .map(|i| format!("[{}]", join((0..cols).map(|j| a[(i, j)]).collect())))
            .collect();
        format!("[{}]", text.join(", "))
    }
}

/// The student's run as a whole `ekf::Run` (errors against the ground truth, summary,
/// odometry for plotting), or what went wrong with it.
pub fn student_run(spec: &RunSpec, output: &RunOutput) -> Result<ekf::Run, String> {
    let dataset = spec.kind.name();
    let (record, unreadable) = match output.record::<FilterRecord>() {
        Ok(record) => (record, None),
        Err(unreadable) => (FilterRecord::default(), Some(unreadable)),
    };
    let error = unreadable
        .or_else(|| output.error.clone())
        .or_else(|| output.stopped.as_ref().map(|s| s.message(RUN_LIMIT_MS)));
    let output = &record;
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
    // Far outside [-pi, pi) a heading's error wraps to anything (exactly 0 at 1e300).
    if let Some((k, mu)) = output
        .mu
        .iter()
        .enumerate()
        .find(|(_, mu)| !heading_within_turns(mu[2]))
    {
        return Err(format!(
            "at time step {}, the heading mu[2] = {:e} is more than {HEADING_TURNS} turns outside [-pi, pi), where its error means nothing: wrap it",
            k + 1,
            mu[2]
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

#[cfg(test)]
mod tests {
    use super::super::contract::{Call, FUNCTIONS};
    use super::*;
    use crate::grading::{
        CallResult, Failure, FunctionOutput, POINTS, PhaseOutput, PlannedCase, Status, Suite,
        cases_of,
    };

    /// What a function's phase reports when every case gets `answer(case)`, each call
    /// repeated alike.
    fn answered(
        plan: &Plan,
        function: &str,
        answer: impl Fn(&PlannedCase<Call>) -> Option<Value>,
    ) -> FunctionOutput {
        let results: Vec<CallResult> = cases_of(&plan.cases, function)
            .filter_map(|planned| {
                answer(planned).map(|output| CallResult {
                    id: planned.case.id.clone(),
                    output: Some(output),
                    error: None,
                })
            })
            .collect();
        FunctionOutput {
            function: function.to_owned(),
            error: None,
            stopped: None,
            repeats: results.clone(),
            results,
        }
    }

    fn function_result(plan: &Plan, output: FunctionOutput) -> Test {
        let function = output.function.clone();
        let outputs = Outputs {
            functions: vec![output],
            runs: Vec::new(),
        };
        let result = grade(plan, &outputs);
        assert!(result.gradable);
        result.test(&format!("{function}:")).unwrap().clone()
    }

    #[test]
    fn the_reference_answers_pass_and_a_phase_without_results_fails() {
        let plan = Plan::new(1, None);
        let right = function_result(
            &plan,
            answered(&plan, "predict", |p| Some(p.case.expected.clone())),
        );
        assert_eq!((right.status, right.points), (Status::Passed, POINTS));

        // What a setter on Object.prototype made of the bookkeeping before: no results,
        // no error. Every case has failed.
        let silent = function_result(&plan, answered(&plan, "predict", |_| None));
        assert_eq!((silent.status, silent.points), (Status::Failed, 0.0));
        assert!(
            silent.message.starts_with("0 of 12 cases pass."),
            "{}",
            silent.message
        );
        assert!(silent.message.contains("not run"), "{}", silent.message);
    }

    #[test]
    fn an_unreadable_report_fails_its_phase_and_the_submission_stays_gradable() {
        let plan = Plan::new(1, None);
        for report in [
            "{\"function\": \"predict\", \"results\": NaN}",
            "[]",
            "{\"function\": \"update\"}",
        ] {
            let test = function_result(&plan, FunctionOutput::from_report("predict", report));
            assert_eq!(test.points, 0.0, "{report}");
            assert!(
                test.message.contains("unreadable"),
                "{report}: {}",
                test.message
            );
        }
    }

    /// A run whose record the student's code spoiled (a field of the wrong type) fails
    /// its test with the reason, whatever else the run reported.
    #[test]
    fn an_unreadable_record_fails_its_run() {
        let plan = Plan::new(1, None);
        let name = &plan.runs[0].name;
        let report = format!(
            "{{\"name\": {name:?}, \"error\": \"at time step 3, predict: threw\", \"record\": {{\"mu\": \"x\"}}}}"
        );
        let outputs = Outputs {
            functions: Vec::new(),
            runs: vec![RunOutput::from_report(name, &report)],
        };
        let result = grade(&plan, &outputs);
        let test = result.test(plan.runs[0].kind.name()).unwrap();
        assert_eq!(test.points, 0.0);
        assert!(
            test.message.contains(&format!(
                "{name}: The test harness's report of this phase is unreadable"
            )),
            "{}",
            test.message
        );
    }

    #[test]
    fn hidden_cases_reveal_nothing_and_a_table_of_the_shown_cases_earns_nothing() {
        let plan = Plan::new(1, Some(77));
        assert_eq!(cases_of(&plan.cases, "update").count(), 18);
        // A lookup table: the shown cases answered, the hidden ones with a guess.
        let table = function_result(
            &plan,
            answered(&plan, "update", |p| match p.suite {
                Suite::Hidden => Some(
                    serde_json::json!({ "mu": [0, 0, 0], "sigma": [[1, 0, 0], [0, 1, 0], [0, 0, 1]] }),
                ),
                _ => Some(p.case.expected.clone()),
            }),
        );
        assert_eq!(table.points, 0.0, "{}", table.message);
        assert!(
            table
                .message
                .starts_with("12 of 12 shown cases and 0 of 6 hidden cases pass"),
            "{}",
            table.message
        );
        let hidden: Vec<&Failure> = table.failures.iter().filter(|f| f.hidden).collect();
        assert!(!hidden.is_empty());
        for failure in hidden {
            assert!(failure.case.starts_with("update/h"));
            assert_eq!(
                (&failure.args, &failure.expected),
                (&Value::Null, &Value::Null)
            );
            assert!(failure.got.is_none() && failure.mismatches.is_empty());
            assert!(failure.differing > 0);
        }
        assert!(table.message.contains("a hidden case"), "{}", table.message);
    }

    #[test]
    fn a_huge_output_is_stored_in_words() {
        let plan = Plan::new(1, None);
        let huge = serde_json::json!(vec![1.5; 15_000]);
        let test = function_result(
            &plan,
            answered(&plan, "observation_model", |_| Some(huge.clone())),
        );
        let stored = serde_json::to_string(&test).unwrap();
        assert!(stored.len() < 8 << 10, "{} bytes", stored.len());
        assert!(stored.contains("an array of 15000 numbers"), "{stored}");
        assert_eq!(test.failures.len(), 2, "failures kept in detail");
    }

    #[test]
    fn the_data_set_tests_tell_functions_that_fail_from_functions_not_run_yet() {
        let plan = Plan::new(1, None);
        // One function's tests run (and fail), the data sets and the other functions not.
        let outputs = Outputs {
            functions: vec![answered(&plan, "predict", |_| Some(Value::Null))],
            runs: Vec::new(),
        };
        let result = grade(&plan, &outputs);
        let o3 = result.test("o3 data set").unwrap();
        assert!(
            o3.message
                .contains("These functions fail their own tests: predict."),
            "{}",
            o3.message
        );
        assert!(
            o3.message.contains(
                "have not run yet: calculate_odometry, observation_model, jacobian_observation_model, associate, batch_associate, update, batch_update."
            ),
            "{}",
            o3.message
        );
    }

    #[test]
    fn a_stored_result_is_a_few_kilobytes_however_wrong_the_file() {
        // Every function answers every case with the right shapes and wrong numbers.
        let plan = Plan::new(1, None);
        let wrong = |value: &Value| -> Value {
            fn nudge(value: &Value) -> Value {
                match value {
                    Value::Number(x) => serde_json::json!(x.as_f64().unwrap_or(0.0) * 1.01 + 1e-3),
                    Value::Bool(b) => Value::Bool(!b),
                    Value::Array(items) => Value::Array(items.iter().map(nudge).collect()),
                    Value::Object(fields) => {
                        Value::Object(fields.iter().map(|(k, v)| (k.clone(), nudge(v))).collect())
                    }
                    other => other.clone(),
                }
            }
            nudge(value)
        };
        let outputs = Outputs {
            functions: FUNCTIONS
                .iter()
                .map(|function| answered(&plan, function, |p| Some(wrong(&p.case.expected))))
                .collect(),
            runs: Vec::new(),
        };
        let result = grade(&plan, &outputs);
        assert_eq!(result.points, 0.0);
        let full = serde_json::to_string(&result).unwrap().len();
        let stored = result.stored();
        let size = serde_json::to_string(&stored).unwrap().len();
        assert!(size < 20 << 10, "{size} bytes stored (of {full})");
        for test in &stored.tests {
            assert!(test.failures.len() <= 1);
            for failure in &test.failures {
                assert_eq!(
                    (&failure.args, &failure.expected),
                    (&Value::Null, &Value::Null)
                );
                assert!(failure.mismatches.len() <= 4);
                // All differing elements are listed, or their count is kept.
                assert!(failure.differing == 0 || failure.differing > failure.mismatches.len());
            }
        }
    }
}
