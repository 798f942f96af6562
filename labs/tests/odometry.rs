//! The odometry exercise's reference model, against what can be worked out by hand and
//! against simulation: Jacobians against central finite differences, the straight line's
//! covariance in closed form, closed shapes that close, the propagated covariance against
//! a large Monte Carlo run (and the banana where the linearisation fails), symmetric
//! positive semi-definite covariances and wrapped headings on every path, and the
//! UMBmark's two systematic errors telling themselves apart.

use labs::odometry::{
    Direction, Increment, MonteCarlo, MonteCarloParams, OdometryParams, Path, Shape,
    SystematicErrors, UmbmarkParams, from_rows, increment_jacobian, monte_carlo, pose_jacobian,
    propagate, step, systematic, umbmark,
};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use std::f64::consts::{PI, TAU};

const STEP: f64 = 1e-6;

fn wrapped(angle: f64) -> bool {
    (-PI..PI).contains(&angle)
}

fn pose() -> impl Strategy<Value = Vector3<f64>> {
    (-10.0..10.0, -10.0..10.0, -PI..PI).prop_map(|(x, y, t)| Vector3::new(x, y, t))
}

fn direction() -> impl Strategy<Value = Direction> {
    prop_oneof![
        Just(Direction::Clockwise),
        Just(Direction::CounterClockwise)
    ]
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (0.2..5.0).prop_map(|length| Shape::Line { length }),
        (0.2..3.0, direction()).prop_map(|(radius, direction)| Shape::Circle { radius, direction }),
        (0.2..4.0, direction()).prop_map(|(side, direction)| Shape::Square { side, direction }),
        (0.2..2.0).prop_map(|radius| Shape::FigureEight { radius }),
        proptest::collection::vec((-3.0..3.0, -3.0..3.0), 2..8).prop_map(|points| {
            Shape::Polyline {
                points: points.into_iter().map(|(x, y)| [x, y]).collect(),
            }
        }),
    ]
}

/// A covariance L L' with entries of about 10^`exponent`, exactly symmetric.
fn covariance(exponents: std::ops::Range<f64>) -> impl Strategy<Value = [[f64; 3]; 3]> {
    (proptest::collection::vec(-1.0..1.0, 6), exponents).prop_map(|(v, exponent)| {
        let l = Matrix3::new(v[0], 0.0, 0.0, v[1], v[2], 0.0, v[3], v[4], v[5])
            * 10f64.powf(exponent / 2.0);
        let s = l * l.transpose();
        let s = (s + s.transpose()) * 0.5;
        std::array::from_fn(|i| std::array::from_fn(|j| s[(i, j)]))
    })
}

fn params() -> impl Strategy<Value = OdometryParams> {
    (
        shape(),
        0.02..0.3,
        0.1..1.0,
        0.0..1e-2,
        0.0..1e-2,
        covariance(-8.0..0.0),
    )
        .prop_map(
            |(shape, speed, wheel_base, k_r, k_l, sigma0)| OdometryParams {
                shape,
                speed,
                wheel_base,
                k_r,
                k_l,
                sigma0,
            },
        )
}

fn assert_symmetric_positive_semidefinite(rows: &[[f64; 3]; 3], what: &str) {
    let sigma = from_rows(rows);
    assert_eq!(sigma, sigma.transpose(), "{what}: not symmetric");
    let eigenvalues = sigma.symmetric_eigenvalues();
    let scale = sigma.abs().max();
    assert!(
        eigenvalues.iter().all(|&e| e >= -1e-12 * scale),
        "{what}: eigenvalues {eigenvalues:?}"
    );
}

/// Every covariance of the propagation symmetric positive semi-definite, every pose
/// finite with its heading wrapped; the path ends where the poses do.
fn check_propagation(params: &OdometryParams, what: &str) {
    let result = propagate(params).unwrap();
    assert_eq!(result.poses.len(), result.path.steps() + 1, "{what}");
    assert_eq!(result.covariances.len(), result.path.steps() + 1, "{what}");
    for (k, (pose, sigma)) in result.poses.iter().zip(&result.covariances).enumerate() {
        let what = format!("{what}, step {k}");
        assert!(pose.iter().all(|v| v.is_finite()), "{what}: {pose:?}");
        assert!(wrapped(pose[2]), "{what}: theta = {}", pose[2]);
        assert_symmetric_positive_semidefinite(sigma, &what);
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x0d0_e7e5),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    })]

    /// F_p = d step / d p, the heading difference wrapped.
    #[test]
    fn pose_jacobian_matches_finite_differences(
        p in pose(), right in -0.5..0.5, left in -0.5..0.5, b in 0.1..1.0,
    ) {
        let increment = Increment::new(right, left);
        let f = pose_jacobian(&p, increment, b);
        for k in 0..3 {
            let (mut plus, mut minus) = (p, p);
            plus[k] += STEP;
            minus[k] -= STEP;
            let (a, c) = (step(&plus, increment, b), step(&minus, increment, b));
            let numeric = Vector3::new(a.x - c.x, a.y - c.y, labs::angle::wrap(a.z - c.z)) / (2.0 * STEP);
            for i in 0..3 {
                prop_assert!((numeric[i] - f[(i, k)]).abs() < 1e-7 * (1.0 + f[(i, k)].abs()),
                    "F_p[{i}][{k}] = {} but finite differences give {}", f[(i, k)], numeric[i]);
            }
        }
    }

    /// F_delta = d step / d (ds_r, ds_l), the heading difference wrapped.
    #[test]
    fn increment_jacobian_matches_finite_differences(
        p in pose(), right in -0.5..0.5, left in -0.5..0.5, b in 0.1..1.0,
    ) {
        let f = increment_jacobian(&p, Increment::new(right, left), b);
        for k in 0..2 {
            let nudge = |h: f64| if k == 0 { Increment::new(right + h, left) } else { Increment::new(right, left + h) };
            let (a, c) = (step(&p, nudge(STEP), b), step(&p, nudge(-STEP), b));
            let numeric = Vector3::new(a.x - c.x, a.y - c.y, labs::angle::wrap(a.z - c.z)) / (2.0 * STEP);
            for i in 0..3 {
                prop_assert!((numeric[i] - f[(i, k)]).abs() < 1e-7 * (1.0 + f[(i, k)].abs()),
                    "F_delta[{i}][{k}] = {} but finite differences give {}", f[(i, k)], numeric[i]);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x0d0_e7e6),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    })]

    /// Random shapes, speeds, wheel bases, wheel noises and initial covariances: every
    /// covariance along the path symmetric positive semi-definite, every heading wrapped.
    #[test]
    fn random_paths_keep_covariances_positive_semidefinite(params in params()) {
        check_propagation(&params, &format!("{params:?}"));
    }
}

#[test]
fn every_shape_keeps_covariances_positive_semidefinite_and_headings_wrapped() {
    let sigma0 = [[1e-3, 2e-4, 0.0], [2e-4, 1e-3, 1e-4], [0.0, 1e-4, 0.1]];
    for direction in [Direction::Clockwise, Direction::CounterClockwise] {
        for shape in [
            Shape::Line { length: 4.0 },
            Shape::Circle {
                radius: 2.0,
                direction,
            },
            Shape::Square {
                side: 4.0,
                direction,
            },
            Shape::FigureEight { radius: 1.5 },
            Shape::Polyline {
                points: vec![
                    [0.0, 0.0],
                    [3.0, 1.0],
                    [-2.0, 2.0],
                    [-2.0, -3.0],
                    [1.0, 0.5],
                ],
            },
        ] {
            for sigma0 in [[[0.0; 3]; 3], sigma0] {
                let params = OdometryParams {
                    shape: shape.clone(),
                    sigma0,
                    ..OdometryParams::default()
                };
                check_propagation(&params, &format!("{shape:?}, sigma0 {sigma0:?}"));
            }
        }
    }
}

/// On a straight line along +x, from a known start, in n equal steps d = L/n with
/// k_r = k_l = k, every step's F_p = [1 0 0; 0 1 d; 0 0 1] and F_delta Sigma_delta F_delta'
/// = k d [1/2 0 0; 0 d^2/(2b^2) d/b^2; 0 d/b^2 2/b^2]. The recursion sums in closed form:
///
/// var x = k L / 2,  var theta = 2 k L / b^2,  cov(y, theta) = k L^2 / b^2,
/// var y = k d^3 sum_{j=1..n} 2 (j - 1/2)^2 / b^2 = k L (4 L^2 - d^2) / (6 b^2),
///
/// and x is uncorrelated with y and theta: along the path the variance grows like the
/// distance, across it like the distance cubed.
#[test]
fn a_straight_line_grows_its_covariance_as_worked_out_by_hand() {
    let (k, b, d, n) = (1e-3, 0.4, 0.1, 30);
    let params = OdometryParams {
        shape: Shape::Line {
            length: d * n as f64,
        },
        speed: d,
        wheel_base: b,
        k_r: k,
        k_l: k,
        sigma0: [[0.0; 3]; 3],
    };
    let result = propagate(&params).unwrap();
    assert_eq!(result.path.steps(), n);
    for (m, sigma) in result.covariances.iter().enumerate() {
        let l = m as f64 * d;
        let expected = [
            [k * l / 2.0, 0.0, 0.0],
            [
                0.0,
                k * l * (4.0 * l * l - d * d) / (6.0 * b * b),
                k * l * l / (b * b),
            ],
            [0.0, k * l * l / (b * b), 2.0 * k * l / (b * b)],
        ];
        for i in 0..3 {
            for j in 0..3 {
                let (got, want) = (sigma[i][j], expected[i][j]);
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1e-9),
                    "step {m}, Sigma[{i}][{j}] = {got}, by hand {want}"
                );
            }
        }
        assert_eq!(result.poses[m][1], 0.0);
        assert!((result.poses[m][0] - l).abs() < 1e-12);
    }
    // At 3 m: sigma_x = 3.9 cm along the path, sigma_y = 34 cm across it.
    let last = result.final_covariance();
    assert!((last[0][0].sqrt() - 0.0387).abs() < 1e-4 && (last[1][1].sqrt() - 0.3354).abs() < 1e-4);
}

fn assert_close(got: &[f64], want: &[f64], tolerance: f64, what: &str) {
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tolerance, "{what}: {got:?} vs {want:?}");
    }
}

#[test]
fn closed_shapes_return_to_their_start() {
    for direction in [Direction::Clockwise, Direction::CounterClockwise] {
        for (shape, speed) in [
            (
                Shape::Circle {
                    radius: 2.0,
                    direction,
                },
                0.05,
            ),
            (
                Shape::Circle {
                    radius: 0.05,
                    direction,
                },
                1.0,
            ),
            (
                Shape::Square {
                    side: 4.0,
                    direction,
                },
                0.05,
            ),
            (
                Shape::Square {
                    side: 1.3,
                    direction,
                },
                0.07,
            ),
            (Shape::FigureEight { radius: 1.5 }, 0.03),
        ] {
            let params = OdometryParams {
                shape: shape.clone(),
                speed,
                ..OdometryParams::default()
            };
            let result = propagate(&params).unwrap();
            let end = result.final_pose();
            assert_close(&end, &[0.0; 3], 1e-9, &format!("{shape:?}"));
            // ... and went somewhere on the way.
            let far = result
                .poses
                .iter()
                .map(|p| p[0].hypot(p[1]))
                .fold(0.0, f64::max);
            assert!(far > 0.09, "{shape:?}");
        }
    }
    // A counter-clockwise circle goes round (0, r), a clockwise one round (0, -r); the
    // figure eight does both.
    let top = |shape| {
        let poses = propagate(&OdometryParams {
            shape,
            ..OdometryParams::default()
        })
        .unwrap()
        .poses;
        let ys = poses.iter().map(|p| p[1]);
        (
            ys.clone().fold(f64::MAX, f64::min),
            ys.fold(f64::MIN, f64::max),
        )
    };
    let (low, high) = top(Shape::Circle {
        radius: 1.0,
        direction: Direction::CounterClockwise,
    });
    assert!(
        low.abs() < 1e-12 && (high - 2.0).abs() < 1e-2,
        "{low} {high}"
    );
    let (low, high) = top(Shape::Circle {
        radius: 1.0,
        direction: Direction::Clockwise,
    });
    assert!(
        (low + 2.0).abs() < 1e-2 && high.abs() < 1e-12,
        "{low} {high}"
    );
    let (low, high) = top(Shape::FigureEight { radius: 1.0 });
    assert!(
        (low + 2.0).abs() < 1e-2 && (high - 2.0).abs() < 1e-2,
        "{low} {high}"
    );
}

#[test]
fn a_polyline_visits_its_points() {
    let points = vec![
        [1.0, -1.0],
        [4.0, 3.0],
        [4.0, 3.0],
        [-2.0, 3.0],
        [0.5, -2.5],
    ];
    let params = OdometryParams {
        shape: Shape::Polyline {
            points: points.clone(),
        },
        speed: 0.1,
        ..OdometryParams::default()
    };
    let result = propagate(&params).unwrap();
    assert_close(&result.poses[0][..2], &points[0], 0.0, "start");
    for point in &points[1..] {
        let nearest = result
            .poses
            .iter()
            .map(|p| (p[0] - point[0]).hypot(p[1] - point[1]))
            .fold(f64::MAX, f64::min);
        assert!(nearest < 1e-9, "{point:?}: nearest {nearest}");
    }
    assert_close(&result.final_pose()[..2], &[0.5, -2.5], 1e-9, "end");
    // Facing the last leg's direction.
    let heading = (-5.5f64).atan2(2.5);
    assert!((result.final_pose()[2] - heading).abs() < 1e-9);
}

/// The largest |sample - propagated| of the covariance's elements in standard errors: a
/// sample covariance of N Gaussian draws has Var(S_ij) = (P_ij^2 + P_ii P_jj) / (N - 1).
fn covariance_gap_in_standard_errors(mc: &MonteCarlo, propagated: &[[f64; 3]; 3]) -> f64 {
    let n = mc.robots as f64;
    let p = propagated;
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let standard_error = ((p[i][j] * p[i][j] + p[i][i] * p[j][j]) / (n - 1.0)).sqrt();
            worst = worst.max((mc.sample_covariance[i][j] - p[i][j]).abs() / standard_error);
        }
    }
    worst
}

/// With little noise the linearisation holds: over 20,000 robots the sample covariance of
/// the final poses equals the propagated one within 4 standard errors in every element,
/// the sample mean is the nominal pose within 4 standard errors, and the share inside the
/// 3-sigma ellipse is the Gaussian's 98.89 % within 4 binomial standard errors. The same
/// comparison against a covariance propagated with 30 % more wheel noise fails: the test
/// can tell.
#[test]
fn the_propagated_covariance_is_the_spread_of_a_large_monte_carlo_run() {
    let params = OdometryParams {
        shape: Shape::Square {
            side: 2.0,
            direction: Direction::CounterClockwise,
        },
        speed: 0.05,
        wheel_base: 0.35,
        k_r: 1e-6,
        k_l: 2e-6,
        sigma0: [[1e-5, 2e-6, 0.0], [2e-6, 1e-5, 0.0], [0.0, 0.0, 1e-5]],
    };
    let mc = monte_carlo(
        &params,
        &MonteCarloParams {
            robots: 20_000,
            seed: 7,
            cloud_every: 0,
        },
    )
    .unwrap();
    assert_eq!(mc.steps, 184);
    assert_eq!(mc.final_poses.len(), 20_000);
    let gap = covariance_gap_in_standard_errors(&mc, &mc.covariance);
    assert!(gap < 4.0, "{gap} standard errors: {mc:?}");
    let n = mc.robots as f64;
    for i in 0..3 {
        let standard_error = (mc.covariance[i][i] / n).sqrt();
        let gap = labs::angle::wrap(mc.sample_mean[i] - mc.nominal[i]);
        assert!(
            gap.abs() < 4.0 * standard_error,
            "mean[{i}]: {gap} vs {standard_error}"
        );
    }
    let share = mc.inside_3_sigma.unwrap();
    let standard_error =
        (mc.gaussian_inside_3_sigma * (1.0 - mc.gaussian_inside_3_sigma) / n).sqrt();
    assert!((mc.gaussian_inside_3_sigma - 0.988_891).abs() < 1e-6);
    assert!(
        (share - mc.gaussian_inside_3_sigma).abs() < 4.0 * standard_error,
        "{share}"
    );

    let noisier = propagate(&OdometryParams {
        k_r: 1.3 * params.k_r,
        k_l: 1.3 * params.k_l,
        ..params.clone()
    })
    .unwrap()
    .final_covariance();
    assert!(covariance_gap_in_standard_errors(&mc, &noisier) > 4.0);
}

/// A heading known to +-0.5 rad (1 sigma) at the start of a 5 m line, and no other noise
/// (bar 1 cm of position): each robot drives straight along its own heading, so its end
/// is (L cos theta, L sin theta) plus the start's offset, a banana. For theta ~ N(0, s^2),
/// E[cos theta] = e^(-s^2/2) and var(sin theta) = (1 - e^(-2 s^2)) / 2: the cloud's mean
/// falls short of the nominal end, its spread across is less than the propagated
/// L^2 s^2, and far fewer than 98.9 % of the robots lie inside the propagated 3-sigma
/// ellipse, which is thin along x and misses the banana's ends.
#[test]
fn a_large_initial_heading_variance_bends_the_cloud_into_a_banana() {
    let (l, s2, position) = (5.0, 0.25, 1e-4);
    let params = OdometryParams {
        shape: Shape::Line { length: l },
        k_r: 0.0,
        k_l: 0.0,
        sigma0: [[position, 0.0, 0.0], [0.0, position, 0.0], [0.0, 0.0, s2]],
        ..OdometryParams::default()
    };
    let mc = monte_carlo(
        &params,
        &MonteCarloParams {
            robots: 20_000,
            seed: 3,
            cloud_every: 25,
        },
    )
    .unwrap();
    let n = mc.robots as f64;
    let xs: Vec<f64> = mc.final_poses.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = mc.final_poses.iter().map(|p| p[1]).collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
    let moment = |v: &[f64], m: f64, k: i32| v.iter().map(|x| (x - m).powi(k)).sum::<f64>() / n;

    let want_x = l * (-s2 / 2.0f64).exp();
    let (mean_x, var_x) = (mean(&xs), moment(&xs, mean(&xs), 2));
    assert!(
        (mean_x - want_x).abs() < 4.0 * (var_x / n).sqrt(),
        "{mean_x} vs {want_x}"
    );
    assert!(
        mc.nominal[0] - mean_x > 0.5,
        "the mean falls short of the nominal end"
    );

    let want_var_y = position + l * l * (1.0 - (-2.0 * s2).exp()) / 2.0;
    let (mean_y, var_y) = (mean(&ys), moment(&ys, 0.0, 2));
    let standard_error = ((moment(&ys, 0.0, 4) - var_y * var_y) / n).sqrt();
    assert!(mean_y.abs() < 4.0 * (var_y / n).sqrt());
    assert!(
        (var_y - want_var_y).abs() < 4.0 * standard_error,
        "{var_y} vs {want_var_y}"
    );
    let propagated_var_y = mc.covariance[1][1];
    assert!((propagated_var_y - (position + l * l * s2)).abs() < 1e-9);
    assert!(var_y < 0.85 * propagated_var_y);

    let share = mc.inside_3_sigma.unwrap();
    assert!(share < 0.3, "{share} inside the 3-sigma ellipse");

    // The clouds: steps 0, 25, ..., 100 (the path's end), the last one the final poses.
    let steps: Vec<usize> = mc.clouds.iter().map(|c| c.step).collect();
    assert_eq!(steps, [0, 25, 50, 75, 100]);
    assert_eq!(mc.clouds[4].poses, mc.final_poses);
    // At the start: the drawn initial poses, heading spread s.
    let headings: Vec<f64> = mc.clouds[0].poses.iter().map(|p| p[2]).collect();
    let var_theta = moment(&headings, mean(&headings), 2);
    assert!((var_theta - s2).abs() < 0.02, "{var_theta}");
}

#[test]
fn monte_carlo_runs_are_seeded_and_each_robot_keeps_its_path() {
    let params = OdometryParams::default();
    let run = |robots, seed| {
        monte_carlo(
            &params,
            &MonteCarloParams {
                robots,
                seed,
                cloud_every: 0,
            },
        )
        .unwrap()
    };
    let (small, large) = (run(50, 9), run(200, 9));
    assert_eq!(small, run(50, 9));
    assert_eq!(small.final_poses[..], large.final_poses[..50]);
    assert_ne!(small.final_poses, run(50, 10).final_poses);
    // Without any noise every robot is the nominal one, and there is no ellipse.
    let exact = monte_carlo(
        &OdometryParams {
            k_r: 0.0,
            k_l: 0.0,
            ..params.clone()
        },
        &MonteCarloParams::default(),
    )
    .unwrap();
    assert!(exact.final_poses.iter().all(|p| *p == exact.nominal));
    assert_eq!(exact.inside_3_sigma, None);
    assert_eq!(exact.sample_covariance, [[0.0; 3]; 3]);
}

#[test]
fn headings_are_wrapped_everywhere() {
    // Circles pass theta = pi; a large heading variance draws starts far round.
    let params = OdometryParams {
        shape: Shape::FigureEight { radius: 1.0 },
        sigma0: [[0.0; 3], [0.0; 3], [0.0, 0.0, 4.0]],
        k_r: 1e-3,
        k_l: 1e-3,
        ..OdometryParams::default()
    };
    let mc = monte_carlo(
        &params,
        &MonteCarloParams {
            robots: 200,
            seed: 1,
            cloud_every: 7,
        },
    )
    .unwrap();
    let poses = mc
        .clouds
        .iter()
        .flat_map(|c| &c.poses)
        .chain(&mc.final_poses)
        .chain([&mc.sample_mean]);
    let mut count = 0;
    for pose in poses {
        assert!(wrapped(pose[2]), "{pose:?}");
        count += 1;
    }
    assert!(count > 200 * 20);
    let run = systematic(
        &params,
        &SystematicErrors {
            e_d: 1.05,
            e_b: 0.9,
        },
    )
    .unwrap();
    assert!(run.odometry.iter().chain(&run.truth).all(|p| wrapped(p[2])));
    assert!(wrapped(run.final_error[2]));
    let test = umbmark(
        &params,
        &SystematicErrors {
            e_d: 1.05,
            e_b: 0.9,
        },
        &UmbmarkParams::default(),
    )
    .unwrap();
    for direction in [&test.clockwise, &test.counter_clockwise] {
        assert!(direction.odometry.iter().all(|p| wrapped(p[2])));
        assert!(direction.truths.iter().flatten().all(|p| wrapped(p[2])));
        assert!(direction.errors.iter().all(|p| wrapped(p[2])));
    }
}

fn noiseless() -> OdometryParams {
    OdometryParams {
        k_r: 0.0,
        k_l: 0.0,
        ..OdometryParams::default()
    }
}

fn umbmark_of(e_d: f64, e_b: f64) -> labs::odometry::Umbmark {
    umbmark(
        &noiseless(),
        &SystematicErrors { e_d, e_b },
        &UmbmarkParams::default(),
    )
    .unwrap()
}

#[test]
fn without_systematic_errors_the_umbmark_square_closes_both_ways() {
    let test = umbmark_of(1.0, 1.0);
    for direction in [&test.clockwise, &test.counter_clockwise] {
        assert_eq!(direction.errors.len(), 5);
        for error in &direction.errors {
            assert_close(error, &[0.0; 3], 1e-12, "return error");
        }
        assert_eq!(direction.truths[0], direction.odometry);
    }
    assert!(test.e_max_syst < 1e-12);
}

/// E_b != 1 alone: every turn is 1/E_b of what the odometry believes, whichever way, so
/// the counter-clockwise square's heading ends off by 4 (pi/2)(1/E_b - 1) and the
/// clockwise one's by as much the other way; the clockwise square is the mirror image of
/// the counter-clockwise one in the x axis, and so are their return errors.
#[test]
fn a_wrong_wheel_base_gives_mirror_image_errors_of_opposite_rotation() {
    for e_b in [1.02, 0.97] {
        let test = umbmark_of(1.0, e_b);
        let (cw, ccw) = (test.clockwise.errors[0], test.counter_clockwise.errors[0]);
        let heading = TAU * (1.0 / e_b - 1.0);
        assert!((ccw[2] - heading).abs() < 1e-12, "{ccw:?} vs {heading}");
        assert!((cw[2] + heading).abs() < 1e-12, "{cw:?} vs {heading}");
        assert_close(&cw, &[ccw[0], -ccw[1], -ccw[2]], 1e-12, "mirror");
        assert!(test.counter_clockwise.r > 0.1, "{ccw:?}");
        assert!((test.clockwise.r - test.counter_clockwise.r).abs() < 1e-12);
        assert_eq!(
            test.e_max_syst,
            test.clockwise.r.max(test.counter_clockwise.r)
        );
    }
}

/// E_d != 1 alone: on a straight leg of L the robot turns by L (c_r - c_l) / b while the
/// odometry believes it goes straight, the same way in both directions; turns on the spot
/// are right (c_r + c_l = 2). So both squares end with the heading off by the same
/// 4 L (c_r - c_l) / b, and their position errors are not mirror images.
#[test]
fn unequal_wheels_bend_both_squares_the_same_way() {
    let (l, b) = (4.0, noiseless().wheel_base);
    for e_d in [1.01, 0.995] {
        let test = umbmark_of(e_d, 1.0);
        let (c_r, c_l) = SystematicErrors { e_d, e_b: 1.0 }.wheel_factors();
        assert!((c_r + c_l - 2.0).abs() < 1e-15 && (c_r / c_l - e_d).abs() < 1e-15);
        let heading = 4.0 * l * (c_r - c_l) / b;
        let (cw, ccw) = (test.clockwise.errors[0], test.counter_clockwise.errors[0]);
        assert!((cw[2] - heading).abs() < 1e-12, "{cw:?} vs {heading}");
        assert!((ccw[2] - heading).abs() < 1e-12, "{ccw:?} vs {heading}");
        assert!(
            (cw[1] + ccw[1]).abs() > 0.1,
            "not mirror images: {cw:?} {ccw:?}"
        );
        assert!(test.clockwise.r > 0.1 && test.counter_clockwise.r > 0.1);
    }
}

/// Why UMBmark drives both ways: with E_d chosen so that the legs' bending makes up for a
/// too large wheel base on counter-clockwise turns (the real wheel base E_b b bends the
/// legs too), 4 L (c_r - c_l) / (E_b b) = 2 pi (1 - 1/E_b), every leg and its turn
/// together turn by exactly a quarter turn, so the four make a closed figure: the
/// counter-clockwise square returns exactly to its start and the odometry looks perfect,
/// while the clockwise one, where the two errors add, misses by 36 cm. With E_d the other
/// way round the roles swap.
#[test]
fn the_two_errors_can_cancel_one_way_round_but_not_both() {
    let (l, b, e_b) = (4.0, noiseless().wheel_base, 1.01);
    // c_r - c_l = 2 (E_d - 1) / (E_d + 1) = g  <=>  E_d = (2 + g) / (2 - g).
    let g = TAU * (e_b - 1.0) * b / (4.0 * l);
    let e_d = (2.0 + g) / (2.0 - g);
    let test = umbmark_of(e_d, e_b);
    assert!(test.counter_clockwise.errors[0][2].abs() < 1e-12);
    assert!(
        test.counter_clockwise.r < 1e-12,
        "{:?}",
        test.counter_clockwise.errors
    );
    assert!(test.clockwise.r > 0.3, "{:?}", test.clockwise.errors);
    assert_eq!(test.e_max_syst, test.clockwise.r);
    let swapped = umbmark_of(1.0 / e_d, e_b);
    assert!(swapped.clockwise.r < 1e-12 && swapped.counter_clockwise.r > 0.3);
}

/// With wheel slip too, the runs of a direction scatter round the systematic error: the
/// centre of gravity of 100 runs lies near the noiseless return error, while each run
/// differs from the others.
#[test]
fn with_slip_the_runs_cluster_round_the_systematic_error() {
    let errors = SystematicErrors {
        e_d: 1.002,
        e_b: 1.01,
    };
    let systematic_only = umbmark(&noiseless(), &errors, &UmbmarkParams::default()).unwrap();
    let test = umbmark(
        &OdometryParams::default(),
        &errors,
        &UmbmarkParams {
            runs: 100,
            ..UmbmarkParams::default()
        },
    )
    .unwrap();
    for (noisy, exact) in [
        (&test.clockwise, &systematic_only.clockwise),
        (&test.counter_clockwise, &systematic_only.counter_clockwise),
    ] {
        let spread = noisy
            .errors
            .iter()
            .map(|e| (e[0] - noisy.centre[0]).hypot(e[1] - noisy.centre[1]))
            .sum::<f64>()
            / 100.0;
        assert!(spread > 0.01, "{spread}");
        let gap = (noisy.centre[0] - exact.centre[0]).hypot(noisy.centre[1] - exact.centre[1]);
        assert!(gap < spread / 2.0, "{gap} vs {spread}");
        let centre = [
            noisy.errors.iter().map(|e| e[0]).sum::<f64>() / 100.0,
            noisy.errors.iter().map(|e| e[1]).sum::<f64>() / 100.0,
        ];
        assert_close(&noisy.centre, &centre, 1e-15, "centre of gravity");
        assert!((noisy.r - centre[0].hypot(centre[1])).abs() < 1e-15);
    }
    // The same seed, the same runs.
    assert_eq!(
        test,
        umbmark(
            &OdometryParams::default(),
            &errors,
            &UmbmarkParams {
                runs: 100,
                ..UmbmarkParams::default()
            },
        )
        .unwrap()
    );
}

#[test]
fn the_true_path_and_the_odometrys_part_ways() {
    let square = OdometryParams {
        shape: Shape::Square {
            side: 4.0,
            direction: Direction::Clockwise,
        },
        ..noiseless()
    };
    let errors = SystematicErrors {
        e_d: 1.01,
        e_b: 1.02,
    };
    let run = systematic(&square, &errors).unwrap();
    let nominal = propagate(&square).unwrap();
    assert_eq!(run.odometry, nominal.poses);
    assert_eq!(run.truth.len(), run.odometry.len());
    assert_eq!(run.truth[0], run.odometry[0]);
    // The same return error as the UMBmark's clockwise run.
    assert_close(
        &run.final_error,
        &umbmark_of(1.01, 1.02).clockwise.errors[0],
        1e-12,
        "final error",
    );
    // Straight ahead with E_d > 1 (right wheel larger) the robot curves left.
    let line = systematic(
        &OdometryParams {
            shape: Shape::Line { length: 2.0 },
            ..noiseless()
        },
        &SystematicErrors {
            e_d: 1.01,
            e_b: 1.0,
        },
    )
    .unwrap();
    assert!(
        line.final_error[1] > 0.0 && line.final_error[2] > 0.0,
        "{line:?}"
    );
    assert_eq!(line.odometry.last().unwrap()[1], 0.0);
}

#[test]
fn invalid_settings_are_named() {
    let message = |result: Result<MonteCarlo, labs::Error>| result.unwrap_err().to_string();
    let mc = |robots, cloud_every| MonteCarloParams {
        robots,
        seed: 1,
        cloud_every,
    };
    let params = OdometryParams::default();
    assert_eq!(
        message(monte_carlo(&params, &mc(1, 0))),
        "robots: must lie in 2..=100000, got 1"
    );
    assert_eq!(
        message(monte_carlo(&params, &mc(100_001, 0))),
        "robots: must lie in 2..=100000, got 100001"
    );
    assert_eq!(
        message(monte_carlo(&params, &mc(100_000, 0))),
        "robots: 100000 robots on a path of 344 steps is more than the 20000000 \
         robot-steps allowed: fewer robots or fewer steps"
    );
    assert_eq!(
        message(monte_carlo(&params, &mc(50_000, 1))),
        "cloud_every: 345 clouds of 50000 robots is more than the 1000000 poses allowed: \
         a larger cloud_every or fewer robots"
    );
    assert_eq!(
        message(monte_carlo(
            &OdometryParams {
                speed: -1.0,
                ..params.clone()
            },
            &mc(10, 0)
        )),
        "speed: must lie in (0, 1e6] metres per step, got -1"
    );
    let umbmark_error = |errors: SystematicErrors, test: UmbmarkParams| {
        umbmark(&params, &errors, &test).unwrap_err().to_string()
    };
    let d = SystematicErrors::default;
    assert_eq!(
        umbmark_error(
            SystematicErrors { e_d: 0.0, ..d() },
            UmbmarkParams::default()
        ),
        "e_d: must lie in [0.5, 2], got 0"
    );
    assert_eq!(
        umbmark_error(
            SystematicErrors {
                e_b: f64::NAN,
                ..d()
            },
            UmbmarkParams::default()
        ),
        "e_b: must lie in [0.5, 2], got NaN"
    );
    assert_eq!(
        umbmark_error(
            d(),
            UmbmarkParams {
                runs: 0,
                ..UmbmarkParams::default()
            }
        ),
        "runs: must lie in 1..=100, got 0"
    );
    assert_eq!(
        umbmark_error(
            d(),
            UmbmarkParams {
                side: -4.0,
                ..UmbmarkParams::default()
            }
        ),
        "side: must lie in (0, 1e6] metres, got -4"
    );
    assert_eq!(
        systematic(
            &OdometryParams {
                k_r: -1.0,
                ..params.clone()
            },
            &d()
        )
        .unwrap_err()
        .to_string(),
        "k_r: must lie in [0, 1] metres, got -1"
    );
    assert!(Path::new(&Shape::Line { length: 1.0 }, 0.1, f64::NAN).is_err());
}
