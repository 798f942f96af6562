//! The UMBmark test of odometry (Borenstein and Feng's University of Michigan Benchmark).
//!
//! The robot drives a square of side L (4 m in the original) several times clockwise and
//! several times counter-clockwise, each time stopping where its odometry says the start
//! is, and we measure where it really stopped. A run's return error is the real final
//! pose minus the odometry's final pose.
//!
//! Why both directions: the two systematic errors (see [`super::systematic`]) show
//! differently in them. A wrong wheel base makes every turn too short (or too long) in
//! either direction, so its clockwise and counter-clockwise errors are mirror images of
//! each other, with headings off by equal amounts of opposite sign. Unequal wheels bend
//! every straight leg the same way in either direction, which adds to the turns one way
//! round and takes from them the other way. Driven in one direction only, the two can
//! cancel and a badly calibrated robot can look good; in the other direction they then
//! add up.
//!
//! For each direction the centre of gravity of the runs' position errors is
//! (x_cg, y_cg) = (1/n) sum_i (dx_i, dy_i), at the distance r = sqrt(x_cg^2 + y_cg^2) from
//! where it should be, and the measure of the odometry's systematic error is
//!
//! E_max,syst = max(r_cw, r_ccw).
//!
//! The runs' random wheel slip (k_r, k_l) spreads each direction's errors into a cluster
//! round its centre of gravity; without slip every run ends at the centre.

use super::motion::{Increment, step};
use super::params::{OdometryParams, check_noise};
use super::path::{Direction, Path, Shape};
use super::systematic::{SystematicErrors, drive_both, pose_error};
use crate::Error;
use crate::rng::Rng;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The most runs per direction.
pub const MAX_RUNS: usize = 100;
/// The most poses the true paths of one direction's runs may hold together.
pub const MAX_RUN_POSES: usize = 1_000_000;

/// The square and how often it is driven each way.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct UmbmarkParams {
    /// L, the side of the square, metres.
    pub side: f64,
    /// Runs per direction.
    pub runs: usize,
    /// The seed of the runs' wheel slip.
    pub seed: u64,
}

impl Default for UmbmarkParams {
    fn default() -> Self {
        UmbmarkParams {
            side: 4.0,
            runs: 5,
            seed: 1,
        }
    }
}

/// The runs in one direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UmbmarkDirection {
    pub direction: Direction,
    /// The square as the odometry computes it, the same in every run.
    pub odometry: Vec<[f64; 3]>,
    /// Each run's true path.
    pub truths: Vec<Vec<[f64; 3]>>,
    /// Each run's return error: true final pose - the odometry's, the heading wrapped.
    pub errors: Vec<[f64; 3]>,
    /// The centre of gravity (x_cg, y_cg) of the position errors.
    pub centre: [f64; 2],
    /// Its distance from the origin, r = sqrt(x_cg^2 + y_cg^2).
    pub r: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Umbmark {
    pub clockwise: UmbmarkDirection,
    pub counter_clockwise: UmbmarkDirection,
    /// max(r_cw, r_ccw).
    pub e_max_syst: f64,
}

/// The UMBmark test of the robot with `params`' speed, wheel base and wheel noise (its
/// shape and initial covariance play no part: the runs start exactly at the origin) and
/// the systematic `errors`.
pub fn umbmark(
    params: &OdometryParams,
    errors: &SystematicErrors,
    test: &UmbmarkParams,
) -> Result<Umbmark, Error> {
    errors.validate()?;
    check_noise(params.k_r, params.k_l)?;
    if !(test.side.is_finite() && test.side > 0.0 && test.side <= super::path::MAX_SIZE) {
        return Err(Error::invalid(
            "side",
            format!("must lie in (0, 1e6] metres, got {}", test.side),
        ));
    }
    if !(1..=MAX_RUNS).contains(&test.runs) {
        return Err(Error::invalid(
            "runs",
            format!("must lie in 1..={MAX_RUNS}, got {}", test.runs),
        ));
    }
    let direction = |direction: Direction, part: u64| {
        let shape = Shape::Square {
            side: test.side,
            direction,
        };
        let path = Path::new(&shape, params.speed, params.wheel_base)?;
        if test.runs * (path.steps() + 1) > MAX_RUN_POSES {
            return Err(Error::invalid(
                "runs",
                format!(
                    "{} runs of {} steps is more than the {MAX_RUN_POSES} poses allowed: \
                     fewer runs or a larger speed",
                    test.runs,
                    path.steps()
                ),
            ));
        }
        let (odometry, _) = drive_both(&path, params.wheel_base, errors);
        let believed = *odometry.last().expect("a path starts somewhere");
        let truths: Vec<Vec<[f64; 3]>> = (0..test.runs)
            .map(|run| {
                let mut rng = Rng::substream(test.seed, 2 * run as u64 + part);
                slipping(&path, params, errors, &mut rng)
            })
            .collect();
        let errors: Vec<[f64; 3]> = truths
            .iter()
            .map(|truth| pose_error(truth.last().expect("a path starts somewhere"), &believed))
            .collect();
        let n = test.runs as f64;
        let centre = [
            errors.iter().map(|e| e[0]).sum::<f64>() / n,
            errors.iter().map(|e| e[1]).sum::<f64>() / n,
        ];
        Ok(UmbmarkDirection {
            direction,
            odometry,
            truths,
            errors,
            centre,
            r: libm::hypot(centre[0], centre[1]),
        })
    };
    let clockwise = direction(Direction::Clockwise, 0)?;
    let counter_clockwise = direction(Direction::CounterClockwise, 1)?;
    let e_max_syst = clockwise.r.max(counter_clockwise.r);
    Ok(Umbmark {
        clockwise,
        counter_clockwise,
        e_max_syst,
    })
}

/// The real robot's path when its wheels roll the systematic share of what the encoders
/// report plus random slip: c_r ds_r + e_r, e_r ~ N(0, k_r |ds_r|), and the same on the
/// left, with the real wheel base E_b b.
fn slipping(
    path: &Path,
    params: &OdometryParams,
    errors: &SystematicErrors,
    rng: &mut Rng,
) -> Vec<[f64; 3]> {
    let real_base = errors.e_b * params.wheel_base;
    let mut pose = Vector3::from(path.start);
    let mut poses = Vec::with_capacity(path.steps() + 1);
    poses.push(path.start);
    for &increment in &path.increments {
        let real = errors.real_increment(increment);
        let slip_r = libm::sqrt(params.k_r * increment.right.abs()) * rng.standard_normal();
        let slip_l = libm::sqrt(params.k_l * increment.left.abs()) * rng.standard_normal();
        pose = step(
            &pose,
            Increment::new(real.right + slip_r, real.left + slip_l),
            real_base,
        );
        poses.push(pose.into());
    }
    poses
}
