//! `estlab odometry`, run as a user runs it: the printed figures are the reference
//! model's, every flag lands in its field, bad settings are named.

use crate::command;

use command::{estlab, stderr, stdout};
use labs::odometry::{
    Direction, MonteCarlo, MonteCarloParams, OdometryParams, Propagation, Shape, SystematicErrors,
    UmbmarkParams, monte_carlo, propagate, systematic, umbmark,
};

/// Every number of the line that starts with `label`, after the label.
fn numbers_on(text: &str, label: &str) -> Vec<f64> {
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix(label))
        .unwrap_or_else(|| panic!("no '{label}' in:\n{text}"));
    line.split(|c: char| !(c.is_ascii_digit() || ".-+e".contains(c)))
        .filter_map(|word| word.parse().ok())
        .collect()
}

/// `got` equals `want` within `tolerance(want)`: the printed precision.
fn assert_printed(got: &[f64], want: &[f64], tolerance: impl Fn(f64) -> f64, text: &str) {
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?} in:\n{text}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= tolerance(*w),
            "{got:?} vs {want:?} in:\n{text}"
        );
    }
}

/// Six decimals.
fn fixed(_: f64) -> f64 {
    5.1e-7
}

/// Seven significant digits.
fn scientific(w: f64) -> f64 {
    5.1e-7 * w.abs()
}

#[test]
fn odometry_prints_the_reference_with_every_flag() {
    // Each flag set to a value of its own, so that one landing in the wrong field shows.
    let flags = [
        "odometry",
        "--shape",
        "circle",
        "--size",
        "1.5",
        "--direction",
        "cw",
        "--speed",
        "0.04",
        "--wheel-base",
        "0.3",
        "--k-r",
        "2e-5",
        "--k-l",
        "3e-5",
        "--sigma0",
        "1e-4,2e-4,3e-3",
        "--monte-carlo",
        "3000",
        "--seed",
        "11",
        "--e-d",
        "1.004",
        "--e-b",
        "0.99",
        "--umbmark",
        "2.5",
        "--runs",
        "7",
    ];
    let params = OdometryParams {
        shape: Shape::Circle {
            radius: 1.5,
            direction: Direction::Clockwise,
        },
        speed: 0.04,
        wheel_base: 0.3,
        k_r: 2e-5,
        k_l: 3e-5,
        sigma0: [[1e-4, 0.0, 0.0], [0.0, 2e-4, 0.0], [0.0, 0.0, 3e-3]],
    };
    let mc_params = MonteCarloParams {
        robots: 3000,
        seed: 11,
        cloud_every: 0,
    };
    let errors = SystematicErrors {
        e_d: 1.004,
        e_b: 0.99,
    };
    let test = UmbmarkParams {
        side: 2.5,
        runs: 7,
        seed: 11,
    };
    let propagation = propagate(&params).unwrap();
    let mc = monte_carlo(&params, &mc_params).unwrap();
    let run = systematic(&params, &errors).unwrap();
    let benchmark = umbmark(&params, &errors, &test).unwrap();

    let out = estlab(&[&flags[..], &["--json"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let printed: OdometryParams = serde_json::from_value(json["params"].clone()).unwrap();
    assert_eq!(printed, params);
    let printed: Propagation = serde_json::from_value(json["propagation"].clone()).unwrap();
    assert_eq!(printed, propagation);
    let printed: MonteCarlo = serde_json::from_value(json["monte_carlo"].clone()).unwrap();
    assert_eq!(printed, mc);
    assert_eq!(json["systematic"]["run"], serde_json::json!(run));
    assert_eq!(json["systematic"]["errors"], serde_json::json!(errors));
    assert_eq!(json["umbmark"]["test"], serde_json::json!(test));
    assert_eq!(json["umbmark"]["result"], serde_json::json!(benchmark));

    let out = estlab(&flags);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.starts_with(&format!(
            "odometry: circle of radius 1.5 m, clockwise, {} steps of at most 0.04 m, wheel base 0.3 m\n\
             wheel noise: k_r = 2e-5 m, k_l = 3e-5 m; start covariance diag(1e-4, 2e-4, 3e-3)\n",
            propagation.path.steps()
        )),
        "{text}"
    );
    let pose = propagation.final_pose();
    let sigma = propagation.final_covariance();
    assert_printed(
        &numbers_on(&text, "final pose (x, y, theta): "),
        &pose,
        fixed,
        &text,
    );
    let std = [0, 1, 2].map(|i| sigma[i][i].sqrt());
    assert_printed(
        &numbers_on(&text, "final std (x, y, theta): "),
        &std,
        fixed,
        &text,
    );
    for (name, row) in ["x", "y", "theta"].iter().zip(&sigma) {
        let label = format!("final covariance, row {name}: ");
        assert_printed(&numbers_on(&text, &label), row, scientific, &text);
    }
    assert!(
        text.contains("\nmonte carlo: 3000 robots, seed 11\n"),
        "{text}"
    );
    assert_printed(
        &numbers_on(&text, "sample mean (x, y, theta): "),
        &mc.sample_mean,
        fixed,
        &text,
    );
    for (name, row) in ["x", "y", "theta"].iter().zip(&mc.sample_covariance) {
        let label = format!("sample covariance, row {name}: ");
        assert_printed(&numbers_on(&text, &label), row, scientific, &text);
    }
    let share = mc.inside_3_sigma.unwrap();
    assert_printed(
        &numbers_on(&text, "inside the 3-sigma ellipse: "),
        &[100.0 * share, 100.0 * mc.gaussian_inside_3_sigma],
        |_| 0.0051,
        &text,
    );
    assert!(text.contains("\nsystematic errors: E_d = 1.004, E_b = 0.99\n"));
    assert_printed(
        &numbers_on(&text, "true final pose (x, y, theta): "),
        run.truth.last().unwrap(),
        fixed,
        &text,
    );
    assert_printed(
        &numbers_on(&text, "error, true - odometry (x, y, theta): "),
        &run.final_error,
        fixed,
        &text,
    );
    assert!(text.contains(
        "\nUMBmark: square of side 2.5 m, 7 runs each way, E_d = 1.004, E_b = 0.99, seed 11\n"
    ));
    for (label, direction) in [
        ("clockwise: ", &benchmark.clockwise),
        ("counter-clockwise: ", &benchmark.counter_clockwise),
    ] {
        assert_printed(
            &numbers_on(&text, label),
            &[direction.centre[0], direction.centre[1], direction.r],
            fixed,
            &text,
        );
    }
    assert_printed(
        &numbers_on(&text, "E_max,syst = "),
        &[benchmark.e_max_syst],
        fixed,
        &text,
    );
}

/// The defaults, pinned: the 4 m square closes, and its covariance is what the model gives
/// (sigma 43 cm in x and y, 9.6 degrees of heading after 16 m and four quarter turns).
#[test]
fn the_default_square_and_a_drawn_polyline() {
    let out = estlab(&["odometry"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.starts_with(
        "odometry: square of side 4 m, counter-clockwise, 344 steps of at most 0.05 m, wheel base 0.35 m\n\
         wheel noise: k_r = 1e-4 m, k_l = 1e-4 m; start covariance diag(0, 0, 0)\n"
    ), "{text}");
    assert_printed(
        &numbers_on(&text, "final pose (x, y, theta): "),
        &[0.0, 0.0, 0.0],
        fixed,
        &text,
    );
    assert_printed(
        &numbers_on(&text, "final std (x, y, theta): "),
        &[0.434668, 0.434668, 0.167086],
        |_| 0.0,
        &text,
    );
    assert!(!text.contains("monte carlo"), "{text}");

    // --points alone makes a polyline; it ends at its last point facing along its last leg.
    let out = estlab(&["odometry", "--points", "-1,0; 2,0; 2,1.5", "--speed", "0.1"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.starts_with("odometry: polyline of 3 points, "),
        "{text}"
    );
    assert_printed(
        &numbers_on(&text, "final pose (x, y, theta): "),
        &[2.0, 1.5, std::f64::consts::FRAC_PI_2],
        fixed,
        &text,
    );
}

#[test]
fn bad_settings_are_named() {
    let fails = |args: &[&str], code: i32, message: &str| {
        let out = estlab(&[&["odometry"], args].concat());
        assert_eq!(out.status.code(), Some(code), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(message),
            "{args:?}: {} should say {message}",
            stderr(&out)
        );
    };
    // Flags that would be ignored are refused instead.
    fails(
        &["--shape", "line", "--direction", "cw"],
        1,
        "estlab: --direction: only a circle or a square goes round one way or the other\n",
    );
    fails(
        &["--points", "0,0;1,0", "--size", "2"],
        1,
        "estlab: --size: a polyline's size is its points (--points)\n",
    );
    fails(&["--runs", "3"], 2, "--umbmark");
    fails(
        &["--wheel-base", "0"],
        1,
        "estlab: wheel_base: must lie in [0.001, 1000] metres, got 0\n",
    );
    fails(
        &["--k-l=-1e-4"],
        1,
        "estlab: k_l: must lie in [0, 1] metres, got -0.0001\n",
    );
    fails(
        &["--speed", "NaN"],
        1,
        "estlab: speed: must lie in (0, 1e6] metres per step, got NaN\n",
    );
    fails(
        &["--shape", "line", "--size=-2"],
        1,
        "estlab: shape.length: must lie in (0, 1e6] metres, got -2\n",
    );
    fails(
        &["--monte-carlo", "1"],
        1,
        "estlab: robots: must lie in 2..=100000, got 1\n",
    );
    fails(
        &["--e-b", "3"],
        1,
        "estlab: e_b: must lie in [0.5, 2], got 3\n",
    );
    fails(
        &["--umbmark", "--runs", "0"],
        1,
        "estlab: runs: must lie in 1..=100, got 0\n",
    );
    fails(
        &["--points", "1,1"],
        1,
        "estlab: shape.points: needs at least 2 distinct points, got 1 of 1 given\n",
    );
    fails(
        &["--shape", "line", "--points", "0,0;1,1"],
        1,
        "estlab: --points: only a polyline has points (--shape polyline)\n",
    );
    fails(
        &["--sigma0", "1,2"],
        2,
        "expected 3 comma-separated numbers, got 2",
    );
    fails(&["--shape", "triangle"], 2, "invalid value 'triangle'");
}
