//! The odometry exercise's grading from the reference's side: the reference's own answers
//! pass every case and every path of many seeds; every case's expected output is what
//! `labs::odometry` gives for its arguments; the cases are the same for a seed and differ
//! between seeds; and a path that departs from the reference, stops, or does not run fails
//! with a message that says where and why. (The student files, correct and with classic
//! mistakes, are graded through the real sandbox in `server/tests/odometry_mistakes.rs`.)

use labs::Exercise;
use labs::exercises::odometry::{
    Call, Case, FUNCTIONS, PATH_FUNCTIONS, PathRecord, Plan, generate,
};
use labs::grading::STEP_BY_STEP;
use labs::grading::{
    self, CallResult, Cause, Contract, ExercisePlan, FunctionOutput, Outputs, RunOutput, Status,
    Stopped, Test,
};
use serde_json::{Value, json};
use std::f64::consts::PI;

/// The seeds every property is checked on.
const SEEDS: u64 = 50;
/// Cases of each function per seed, as a grading draws them.
const PER_FUNCTION: usize = grading::CASES_PER_FUNCTION;

/// A hidden seed for `seed`, as the server would draw one.
fn hidden(seed: u64) -> u64 {
    seed.wrapping_mul(0x9E37_79B9) ^ 0x5EED
}

/// What the harness reports when every call answers the case's expected output (again
/// alike in the fresh copy) and every run follows the reference.
fn reference_outputs(plan: &Plan) -> Outputs {
    let functions = FUNCTIONS
        .iter()
        .map(|&function| {
            let results: Vec<CallResult> = plan
                .cases
                .iter()
                .filter(|planned| planned.case.call.function() == function)
                .map(|planned| CallResult {
                    id: planned.case.id.clone(),
                    output: Some(planned.case.expected.clone()),
                    error: None,
                })
                .collect();
            FunctionOutput {
                function: function.to_owned(),
                error: None,
                stopped: None,
                repeats: results.iter().rev().cloned().collect(),
                results,
            }
        })
        .collect();
    let runs = plan
        .runs
        .iter()
        .map(|spec| RunOutput {
            name: spec.name.clone(),
            error: None,
            stopped: None,
            recorded: Some(json!(PathRecord {
                poses: spec.reference.poses[1..].to_vec(),
                covariances: spec.reference.covariances[1..].to_vec(),
            })),
        })
        .collect();
    Outputs { functions, runs }
}

fn test<'a>(tests: &'a [Test], prefix: &str) -> &'a Test {
    tests
        .iter()
        .find(|t| t.name.starts_with(prefix))
        .unwrap_or_else(|| panic!("no test {prefix}"))
}

#[test]
fn the_reference_answers_pass_every_case_and_path_of_every_seed() {
    for seed in 1..=SEEDS {
        for hidden in [None, Some(hidden(seed))] {
            let drawn = hidden.map(|cases| grading::Hidden { cases, class: 1 });
            let plan = grading::Plan::new(Exercise::Odometry, seed, drawn);
            assert_eq!(plan.exercise(), Exercise::Odometry);
            let own = Plan::new(seed, hidden);
            let result = plan.grade(&reference_outputs(&own));
            let failed: Vec<String> = result
                .tests
                .iter()
                .filter(|t| t.status != Status::Passed)
                .map(|t| format!("{}: {}", t.name, t.message))
                .collect();
            assert!(
                failed.is_empty(),
                "seed {seed}, hidden {hidden:?}:\n{}",
                failed.join("\n")
            );
            assert_eq!(result.score, 1.0);
            // A test per function and per path.
            assert_eq!(result.tests.len(), FUNCTIONS.len() + 2);
            assert_eq!(result.exercise, Exercise::Odometry);
        }
    }
}

/// The answer to a call worked out here by hand from the contract's formulas, apart from
/// `labs::odometry`: the step, its Jacobians by central differences of the step, the
/// wheel noise and the propagation, each element compared within `close`.
fn by_hand(call: &Call) -> Vec<f64> {
    // p' = p + [ds cos(theta + dtheta/2), ds sin(theta + dtheta/2), dtheta], theta wrapped.
    let step = |p: [f64; 3], r: f64, l: f64, b: f64| {
        let (ds, dtheta) = ((r + l) / 2.0, (r - l) / b);
        let phi = p[2] + dtheta / 2.0;
        let theta = (p[2] + dtheta + PI).rem_euclid(2.0 * PI) - PI;
        [p[0] + ds * phi.cos(), p[1] + ds * phi.sin(), theta]
    };
    // d p' / d v by central differences, the heading's difference unwrapped.
    let derivative = |f: &dyn Fn(f64) -> [f64; 3]| {
        let h = 1e-6;
        let (plus, minus) = (f(h), f(-h));
        (0..3)
            .map(|i| {
                let mut d = plus[i] - minus[i];
                if i == 2 {
                    d = (d + PI).rem_euclid(2.0 * PI) - PI;
                }
                d / (2.0 * h)
            })
            .collect::<Vec<f64>>()
    };
    let columns = |columns: Vec<Vec<f64>>| -> Vec<f64> {
        (0..3)
            .flat_map(|i| columns.iter().map(move |c| c[i]))
            .collect()
    };
    match call {
        Call::OdometryStep { p, ds_r, ds_l, b } => step(*p, *ds_r, *ds_l, *b).to_vec(),
        Call::PoseJacobian { p, ds_r, ds_l, b } => columns(
            (0..3)
                .map(|j| {
                    derivative(&|h| {
                        let mut q = *p;
                        q[j] += h;
                        step(q, *ds_r, *ds_l, *b)
                    })
                })
                .collect(),
        ),
        Call::IncrementJacobian { p, ds_r, ds_l, b } => columns(vec![
            derivative(&|h| step(*p, ds_r + h, *ds_l, *b)),
            derivative(&|h| step(*p, *ds_r, ds_l + h, *b)),
        ]),
        Call::WheelNoise {
            ds_r,
            ds_l,
            k_r,
            k_l,
        } => vec![k_r * ds_r.abs(), 0.0, 0.0, k_l * ds_l.abs()],
        Call::Propagate {
            sigma_p,
            f_p,
            f_delta,
            sigma_delta,
        } => {
            // F_p Sigma_p F_p^T + F_delta Sigma_delta F_delta^T, element by element.
            let element = |i: usize, j: usize| {
                let mut sum = 0.0;
                for a in 0..3 {
                    for c in 0..3 {
                        sum += f_p[i][a] * sigma_p[a][c] * f_p[j][c];
                    }
                }
                for a in 0..2 {
                    for c in 0..2 {
                        sum += f_delta[i][a] * sigma_delta[a][c] * f_delta[j][c];
                    }
                }
                sum
            };
            (0..3)
                .flat_map(|i| (0..3).map(move |j| element(i, j)))
                .collect()
        }
    }
}

/// Every element of a case's expected output, in order.
fn elements(value: &Value) -> Vec<f64> {
    match value {
        Value::Array(items) => items.iter().flat_map(elements).collect(),
        value => vec![value.as_f64().expect("a number")],
    }
}

#[test]
fn every_case_expects_what_the_formulas_give_and_its_covariances_are_symmetric() {
    for seed in 1..=SEEDS {
        for case in generate(seed, PER_FUNCTION) {
            let (expected, by_hand) = (elements(&case.expected), by_hand(&case.call));
            assert_eq!(expected.len(), by_hand.len(), "seed {seed}, {}", case.id);
            for (e, h) in expected.iter().zip(&by_hand) {
                // Central differences of a step are good to about 1e-6 of its size.
                let close = 1e-5 * (1.0 + e.abs());
                assert!(
                    (e - h).abs() <= close,
                    "seed {seed}, {}: {expected:?} by hand {by_hand:?}",
                    case.id
                );
            }
            // The reference passes its own comparison: a wrapped heading, an exactly
            // symmetric covariance.
            assert!(
                case.check(&case.expected, grading::Tolerance::default())
                    .is_empty(),
                "seed {seed}, {}",
                case.id
            );
            if let Call::Propagate { sigma_p, .. } = &case.call {
                let mirrored: [[f64; 3]; 3] =
                    std::array::from_fn(|i| std::array::from_fn(|j| sigma_p[j][i]));
                assert_eq!(&mirrored, sigma_p, "seed {seed}, {}", case.id);
            }
        }
    }
}

#[test]
fn cases_and_paths_are_the_same_for_a_seed_and_differ_between_seeds() {
    let arguments = |cases: &[Case]| -> Vec<Value> {
        cases
            .iter()
            .map(|c| serde_json::to_value(&c.call).unwrap())
            .collect()
    };
    for seed in 1..=SEEDS {
        let cases = generate(seed, PER_FUNCTION);
        assert_eq!(cases, generate(seed, PER_FUNCTION), "seed {seed}");
        assert_eq!(cases.len(), FUNCTIONS.len() * PER_FUNCTION);
        let other = generate(seed + 1, PER_FUNCTION);
        for (a, b) in cases.iter().zip(&other) {
            assert_eq!((&a.id, &a.note), (&b.id, &b.note));
            assert_ne!(a.call, b.call, "seeds {seed} and {}: {}", seed + 1, a.id);
        }
        assert_ne!(arguments(&cases), arguments(&other));
        let (plan, again) = (Plan::new(seed, None), Plan::new(seed, None));
        assert_eq!(plan.job(), again.job(), "seed {seed}");
        assert_ne!(plan.job().runs, Plan::new(seed + 1, None).job().runs);
        // The hidden seed draws the paths on the server.
        assert_eq!(
            Plan::new(seed, Some(77)).job().runs,
            Plan::new(seed + 1, Some(77)).job().runs
        );
    }
    // The public suite is every student's.
    let public = |seed| -> Vec<Value> {
        grading::planned_cases(generate, seed, None)
            .into_iter()
            .filter(|planned| planned.suite == grading::Suite::Public)
            .map(|planned| serde_json::to_value(planned.case).unwrap())
            .collect()
    };
    assert_eq!(public(1), public(2));
    assert_eq!(public(1).len(), FUNCTIONS.len() * PER_FUNCTION);
}

#[test]
fn the_job_carries_the_wheels_of_each_path_and_nothing_of_the_reference() {
    let plan = Plan::new(5, None);
    let job = serde_json::to_value(plan.job()).unwrap();
    let runs = job["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for (run, spec) in runs.iter().zip(&plan.runs) {
        assert_eq!(run["loop"], "path");
        assert_eq!(run["name"], spec.name);
        assert_eq!(run["functions"], json!(PATH_FUNCTIONS));
        assert_eq!(run["start"], json!([0.0, 0.0, 0.0]));
        assert_eq!(run["steps"].as_array().unwrap().len(), spec.steps());
        assert_eq!(run["b"], json!(spec.params.wheel_base));
        let fields: Vec<&str> = run
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(
            fields.len(),
            9,
            "loop, name, functions, start, b, k_r, k_l, steps, limit_ms: {fields:?}"
        );
    }
    // The calls carry arguments only.
    let text = job.to_string();
    assert!(!text.contains("expected") && !text.contains("covariances"));
}

/// The reference outputs of `plan` with `change` made to what the square's run recorded.
fn graded_with_record(plan: &Plan, change: impl FnOnce(&mut PathRecord)) -> Test {
    graded_with(plan, |run| {
        let mut record: PathRecord = run.record().expect("the run recorded its path");
        change(&mut record);
        run.recorded = Some(serde_json::to_value(record).unwrap());
    })
}

/// The reference outputs of `plan` with `change` made to the square's run.
fn graded_with(plan: &Plan, change: impl FnOnce(&mut RunOutput)) -> Test {
    let mut outputs = reference_outputs(plan);
    change(&mut outputs.runs[0]);
    let result = labs::exercises::odometry::grade(plan, &outputs);
    test(&result.tests, "square path:").clone()
}

#[test]
fn a_path_that_departs_fails_at_the_step_and_the_element_where_it_does() {
    let plan = Plan::new(3, None);
    let steps = plan.runs[0].steps();
    let passed = graded_with(&plan, |_| {});
    assert_eq!((passed.status, passed.points), (Status::Passed, 10.0));
    assert!(
        passed
            .name
            .ends_with("odometry_step, pose_jacobian, increment_jacobian, wheel_noise, propagate"),
        "{}",
        passed.name
    );
    assert!(
        passed
            .message
            .contains(&format!("each of the {steps} steps")),
        "{}",
        passed.message
    );

    // A covariance element off by 1e-5 of the largest at step 17.
    let off = graded_with_record(&plan, |path| {
        let largest = path.covariances[16]
            .iter()
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        path.covariances[16][0][2] += 10.0 * STEP_BY_STEP.covariance_share * largest;
    });
    assert_eq!((off.status, off.points), (Status::Failed, 0.0));
    assert!(
        off.message.contains(&format!("from step 17 of {steps} on"))
            && off.message.contains("Sigma_p[0][2]"),
        "{}",
        off.message
    );
    // Within the tolerance it passes.
    let close = graded_with_record(&plan, |path| {
        let largest = path.covariances[16]
            .iter()
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        path.covariances[16][0][2] += 0.1 * STEP_BY_STEP.covariance_share * largest;
        path.poses[40][0] += 1e-8;
    });
    assert_eq!(close.status, Status::Passed, "{}", close.message);

    // The heading is compared modulo 2 pi, x and y within 1e-6 m.
    let turned = graded_with_record(&plan, |path| path.poses[5][2] += std::f64::consts::TAU);
    assert_eq!(turned.status, Status::Passed, "{}", turned.message);
    let moved = graded_with_record(&plan, |path| path.poses[100][1] += 1e-5);
    assert!(
        moved.message.contains("from step 101 of") && moved.message.contains("p[1]"),
        "{}",
        moved.message
    );

    // A run that reports too little, that threw, or that was stopped.
    let short = graded_with_record(&plan, |path| {
        path.poses.pop();
    });
    assert!(
        short.message.contains(&format!("for {steps} steps")),
        "{}",
        short.message
    );
    // A record the student's code spoiled fails the path with the reason.
    let spoiled = graded_with(&plan, |run| run.recorded = Some(json!({ "poses": "x" })));
    assert_eq!(spoiled.points, 0.0);
    assert!(
        spoiled
            .message
            .contains("square: The test harness's report of this phase is unreadable"),
        "{}",
        spoiled.message
    );
    let threw = graded_with(&plan, |run| {
        run.error = Some("at step 3, propagate: threw Error: not implemented".to_owned());
    });
    assert!(
        threw.message.contains("at step 3, propagate"),
        "{}",
        threw.message
    );
    let stopped = graded_with(&plan, |run| {
        run.stopped = Some(Stopped {
            during: "square: step 201".to_owned(),
            cause: Cause::Time,
            limit_ms: None,
        });
    });
    assert!(
        stopped.message.contains("Stopped after 5 s"),
        "{}",
        stopped.message
    );
    assert_eq!(stopped.points, 0.0);
}

#[test]
fn a_path_test_names_the_functions_that_fail_or_have_not_run() {
    let plan = Plan::new(4, None);
    let mut outputs = reference_outputs(&plan);
    // wheel_noise fails its cases, propagate has not run, and no path has run.
    for result in &mut outputs.functions[3].results {
        result.output = Some(json!([[1, 0], [0, 1]]));
    }
    outputs.functions.remove(4);
    outputs.runs.clear();
    let result = labs::exercises::odometry::grade(&plan, &outputs);
    for name in ["square path:", "figure-eight path:"] {
        let path = test(&result.tests, name);
        assert_eq!(path.status, Status::Failed);
        assert!(path.message.contains("not run"), "{}", path.message);
        assert!(
            path.message
                .contains("These functions fail their own tests: wheel_noise."),
            "{}",
            path.message
        );
        assert!(
            path.message.contains("have not run yet: propagate."),
            "{}",
            path.message
        );
    }
}
