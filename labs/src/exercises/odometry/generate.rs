//! Test cases generated from a seed, so that every student can have a variant of their
//! own. Each function's cases cycle through its scenarios, the steps where classic
//! mistakes show: a turn (which heading the step follows, which way the robot turns, how
//! far), a heading that crosses +-pi (wrapping), a wheel rolling backwards (the absolute
//! value of the wheel noise), turning on the spot, one wheel standing still, a long sharp
//! step, and covariances that come from a drive, with unequal wheel constants throughout.

use super::Case;
use super::contract::Call;
use crate::grading::rows;
use crate::grading::{self, scenario_cases};
use crate::odometry::{
    Increment, increment_jacobian, pose_jacobian, propagate_covariance, wheel_noise,
};
use crate::rng::Rng;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// `per_function` cases of every student function, from `seed`.
pub fn generate(seed: u64, per_function: usize) -> Vec<Case> {
    scenario_cases(seed, per_function, &SCENARIOS)
}

type Scenario = grading::Scenario<Call>;

/// The scenarios of the three functions of one step (`odometry_step` and its Jacobians).
macro_rules! step_scenarios {
    ($function:ident) => {
        &[
            ("a gentle curve, both wheels forward", |rng| {
                $function(Step::draw(rng, Motion::Curve))
            }),
            ("turning on the spot", |rng| {
                $function(Step::draw(rng, Motion::Spin(1.0)))
            }),
            ("the heading crosses +-pi", |rng| {
                $function(Step::draw(rng, Motion::CrossingPi))
            }),
            ("reversing: both wheels backwards", |rng| {
                $function(Step::draw(rng, Motion::Reversing))
            }),
            ("a long step with a sharp turn", |rng| {
                $function(Step::draw(rng, Motion::LongSharp))
            }),
            ("one wheel standing still", |rng| {
                $function(Step::draw(rng, Motion::OneWheelStill))
            }),
        ]
    };
}

const SCENARIOS: [(&str, &[Scenario]); 5] = [
    ("odometry_step", step_scenarios!(odometry_step)),
    ("pose_jacobian", step_scenarios!(pose_jacobian_call)),
    (
        "increment_jacobian",
        step_scenarios!(increment_jacobian_call),
    ),
    (
        "wheel_noise",
        &[
            ("both wheels forward", |rng| noise(rng, Motion::Curve)),
            ("reversing: both wheels backwards", |rng| {
                noise(rng, Motion::Reversing)
            }),
            (
                "turning on the spot counter-clockwise: the left wheel backwards",
                |rng| noise(rng, Motion::Spin(1.0)),
            ),
            (
                "turning on the spot clockwise: the right wheel backwards",
                |rng| noise(rng, Motion::Spin(-1.0)),
            ),
            ("one wheel standing still", |rng| {
                noise(rng, Motion::OneWheelStill)
            }),
            ("a long step", |rng| noise(rng, Motion::LongSharp)),
        ],
    ),
    (
        "propagate",
        &[
            ("a step after a drive", |rng| {
                propagation(rng, Motion::Curve, Start::Driven)
            }),
            ("the first step from an exact start: Sigma_p = 0", |rng| {
                propagation(rng, Motion::Curve, Start::Exact)
            }),
            ("turning on the spot after a drive", |rng| {
                propagation(rng, Motion::Spin(1.0), Start::Driven)
            }),
            ("reversing after a drive", |rng| {
                propagation(rng, Motion::Reversing, Start::Driven)
            }),
            (
                "a long sharp step after a long drive: a large heading variance",
                |rng| propagation(rng, Motion::LongSharp, Start::LongDrive),
            ),
            ("the heading crosses +-pi after a drive", |rng| {
                propagation(rng, Motion::CrossingPi, Start::Driven)
            }),
        ],
    ),
];

// ---- one step ----

/// How the wheels roll in a step.
#[derive(Clone, Copy)]
enum Motion {
    /// Both forward, unequally: a gentle curve either way.
    Curve,
    /// On the spot, counter-clockwise (+1) or clockwise (-1).
    Spin(f64),
    /// A turn from a heading within 0.05 rad of +-pi across it.
    CrossingPi,
    /// Both backwards, unequally.
    Reversing,
    /// Up to 2 m with a turn of up to 1.5 rad.
    LongSharp,
    /// One wheel rolls, forwards or backwards, the other stands still.
    OneWheelStill,
}

/// A step from a pose: the wheels' distances and the wheel base.
struct Step {
    p: Vector3<f64>,
    increment: Increment,
    b: f64,
}

impl Step {
    fn draw(rng: &mut Rng, motion: Motion) -> Step {
        let b = rng.uniform_in(0.2, 0.6);
        let position = [rng.uniform_in(-5.0, 5.0), rng.uniform_in(-5.0, 5.0)];
        let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
        let mut heading = rng.uniform_in(-PI, PI);
        // The wheels of a step that moves the centre by ds and turns by dtheta.
        let turning =
            |ds: f64, dtheta: f64| Increment::new(ds + dtheta * b / 2.0, ds - dtheta * b / 2.0);
        // Where both wheels roll the same way, |dtheta| b / 2 <= 0.09 m < |ds|.
        let increment = match motion {
            Motion::Curve => turning(rng.uniform_in(0.1, 0.2), side * rng.uniform_in(0.05, 0.3)),
            Motion::Spin(direction) => turning(0.0, direction * rng.uniform_in(0.1, 0.8)),
            Motion::CrossingPi => {
                // From pi - a counter-clockwise, or from -pi + a clockwise, by more than a.
                let a = rng.uniform_in(0.005, 0.05);
                heading = side * (PI - a);
                turning(
                    rng.uniform_in(0.05, 0.2),
                    side * (a + rng.uniform_in(0.05, 0.3)),
                )
            }
            Motion::Reversing => {
                turning(-rng.uniform_in(0.1, 0.3), side * rng.uniform_in(0.05, 0.3))
            }
            Motion::LongSharp => turning(rng.uniform_in(0.5, 2.0), side * rng.uniform_in(0.6, 1.5)),
            Motion::OneWheelStill => {
                let rolled = side * rng.uniform_in(0.05, 0.3);
                if rng.chance(0.5) {
                    Increment::new(rolled, 0.0)
                } else {
                    Increment::new(0.0, rolled)
                }
            }
        };
        Step {
            p: Vector3::new(position[0], position[1], heading),
            increment,
            b,
        }
    }
}

fn odometry_step(step: Step) -> Call {
    Call::OdometryStep {
        p: step.p.into(),
        ds_r: step.increment.right,
        ds_l: step.increment.left,
        b: step.b,
    }
}

fn pose_jacobian_call(step: Step) -> Call {
    Call::PoseJacobian {
        p: step.p.into(),
        ds_r: step.increment.right,
        ds_l: step.increment.left,
        b: step.b,
    }
}

fn increment_jacobian_call(step: Step) -> Call {
    Call::IncrementJacobian {
        p: step.p.into(),
        ds_r: step.increment.right,
        ds_l: step.increment.left,
        b: step.b,
    }
}

// ---- the wheels' noise ----

/// Wheel constants k_r, k_l between 1e-5 and 1e-2 m, one 1.4 to 3 times the other.
pub(super) fn wheel_constants(rng: &mut Rng) -> (f64, f64) {
    let k = libm::pow(10.0, rng.uniform_in(-5.0, -2.5));
    let ratio = libm::pow(10.0, rng.uniform_in(0.15, 0.5));
    if rng.chance(0.5) {
        (k * ratio, k)
    } else {
        (k, k * ratio)
    }
}

fn noise(rng: &mut Rng, motion: Motion) -> Call {
    let step = Step::draw(rng, motion);
    let (k_r, k_l) = wheel_constants(rng);
    Call::WheelNoise {
        ds_r: step.increment.right,
        ds_l: step.increment.left,
        k_r,
        k_l,
    }
}

// ---- propagation ----

/// What the pose's covariance is before the step.
#[derive(Clone, Copy)]
enum Start {
    /// Zero: the start is known exactly.
    Exact,
    /// After 3 to 20 random steps of a gentle curve.
    Driven,
    /// After 40 to 80 random steps with noisy wheels: a large heading variance.
    LongDrive,
}

/// The covariance of the pose after a drive from an exact start, as the model propagates
/// it (so it has the correlations a real one has).
fn driven_covariance(rng: &mut Rng, start: Start) -> Matrix3<f64> {
    let (steps, k_scale) = match start {
        Start::Exact => return Matrix3::zeros(),
        Start::Driven => (3 + (rng.uniform() * 18.0) as usize, 1.0),
        Start::LongDrive => (40 + (rng.uniform() * 41.0) as usize, 10.0),
    };
    let (k_r, k_l) = wheel_constants(rng);
    let mut sigma = Matrix3::zeros();
    for _ in 0..steps {
        let step = Step::draw(rng, Motion::Curve);
        sigma = propagate_covariance(
            &sigma,
            &step.p,
            step.increment,
            step.b,
            k_scale * k_r,
            k_scale * k_l,
        );
    }
    sigma
}

fn propagation(rng: &mut Rng, motion: Motion, start: Start) -> Call {
    let sigma_p = driven_covariance(rng, start);
    let step = Step::draw(rng, motion);
    let (k_r, k_l) = wheel_constants(rng);
    Call::Propagate {
        sigma_p: rows(&sigma_p),
        f_p: rows(&pose_jacobian(&step.p, step.increment, step.b)),
        f_delta: rows(&increment_jacobian(&step.p, step.increment, step.b)),
        sigma_delta: rows(&wheel_noise(step.increment, k_r, k_l)),
    }
}
