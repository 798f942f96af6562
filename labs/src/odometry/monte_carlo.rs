//! Many simulated robots whose wheels really slip, beside the odometry's propagated
//! covariance: where the linearised Gaussian describes the spread and where it does not.
//!
//! Robot i starts from a pose drawn from N(p_0, Sigma_p0) and at every step its wheels
//! roll the path's increments plus an error of the variance the odometry assumes:
//!
//! ds_r + e_r,  e_r ~ N(0, k_r |ds_r|);   ds_l + e_l,  e_l ~ N(0, k_l |ds_l|),
//!
//! independent from step to step, wheel to wheel and robot to robot. Robot i draws from
//! its own stream (`Rng::substream(seed, i)`), so it takes the same path whatever the
//! number of robots, and the same seed gives the same numbers natively and in wasm.

use super::covariance::{from_rows, square_root, to_rows};
use super::motion::{Increment, step};
use super::params::OdometryParams;
use super::propagation::propagate;
use crate::Error;
use crate::angle::wrap;
use crate::rng::Rng;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The most robots of a run.
pub const MAX_ROBOTS: usize = 100_000;
/// The most robot-steps of a run (robots times the path's steps).
pub const MAX_ROBOT_STEPS: usize = 20_000_000;
/// The most poses all the clouds of a run may hold together.
pub const MAX_CLOUD_POSES: usize = 1_000_000;

/// How many robots, their seed, and which steps to keep every robot's pose at.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MonteCarloParams {
    pub robots: usize,
    pub seed: u64,
    /// Keep every robot's pose at steps 0, `cloud_every`, 2 `cloud_every`, ... (the
    /// clouds to draw); 0 keeps none.
    pub cloud_every: usize,
}

impl Default for MonteCarloParams {
    fn default() -> Self {
        MonteCarloParams {
            robots: 1000,
            seed: 1,
            cloud_every: 0,
        }
    }
}

/// Every robot's pose at one step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cloud {
    pub step: usize,
    pub poses: Vec<[f64; 3]>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MonteCarlo {
    pub robots: usize,
    pub steps: usize,
    /// The odometry's final pose and propagated covariance (rows).
    pub nominal: [f64; 3],
    pub covariance: [[f64; 3]; 3],
    /// Every robot's pose after the last step.
    pub final_poses: Vec<[f64; 3]>,
    pub clouds: Vec<Cloud>,
    /// The sample mean of the final poses: x and y averaged, the heading the nominal one
    /// plus the mean of the wrapped differences wrap(theta_i - theta_nominal).
    pub sample_mean: [f64; 3],
    /// The sample covariance (divided by N - 1) of the final poses, heading differences
    /// taken as above: comparable with `covariance`.
    pub sample_covariance: [[f64; 3]; 3],
    /// The share of final poses inside the 3-sigma ellipse of the propagated position
    /// covariance P (its 2 x 2 block) around the nominal position:
    /// d' P^-1 d <= 9, d = (x_i - x, y_i - y). None when P is singular (no position
    /// uncertainty in some direction, as after turns on the spot alone).
    pub inside_3_sigma: Option<f64>,
    /// The share a Gaussian puts inside its 3-sigma ellipse in two dimensions,
    /// 1 - e^(-9/2) = 0.98889.
    pub gaussian_inside_3_sigma: f64,
}

/// The probability mass of a 2-D Gaussian inside the ellipse d' P^-1 d <= `mahalanobis_sq`:
/// d' P^-1 d is chi-square with 2 degrees of freedom, whose distribution function is
/// 1 - e^(-m/2).
pub fn gaussian_share_inside(mahalanobis_sq: f64) -> f64 {
    1.0 - libm::exp(-mahalanobis_sq / 2.0)
}

/// Runs `mc.robots` robots along `params`' path.
pub fn monte_carlo(params: &OdometryParams, mc: &MonteCarloParams) -> Result<MonteCarlo, Error> {
    let propagation = propagate(params)?;
    let path = &propagation.path;
    let steps = path.steps();
    let robots = mc.robots;
    if !(2..=MAX_ROBOTS).contains(&robots) {
        return Err(Error::invalid(
            "robots",
            format!("must lie in 2..={MAX_ROBOTS}, got {robots}"),
        ));
    }
    if robots.saturating_mul(steps) > MAX_ROBOT_STEPS {
        return Err(Error::invalid(
            "robots",
            format!(
                "{robots} robots on a path of {steps} steps is more than the \
                 {MAX_ROBOT_STEPS} robot-steps allowed: fewer robots or fewer steps"
            ),
        ));
    }
    let snapshots: Vec<usize> = match mc.cloud_every {
        0 => Vec::new(),
        every => (0..=steps).step_by(every).collect(),
    };
    if robots * snapshots.len() > MAX_CLOUD_POSES {
        return Err(Error::invalid(
            "cloud_every",
            format!(
                "{} clouds of {robots} robots is more than the {MAX_CLOUD_POSES} poses \
                 allowed: a larger cloud_every or fewer robots",
                snapshots.len()
            ),
        ));
    }

    let b = params.wheel_base;
    let slips: Vec<(f64, f64)> = path
        .increments
        .iter()
        .map(|i| {
            (
                libm::sqrt(params.k_r * i.right.abs()),
                libm::sqrt(params.k_l * i.left.abs()),
            )
        })
        .collect();
    let root = square_root(&from_rows(&params.sigma0));
    let start = Vector3::from(path.start);
    let mut clouds: Vec<Cloud> = snapshots
        .iter()
        .map(|&step| Cloud {
            step,
            poses: Vec::with_capacity(robots),
        })
        .collect();
    let mut final_poses = Vec::with_capacity(robots);
    for robot in 0..robots {
        let mut rng = Rng::substream(mc.seed, robot as u64);
        let z = Vector3::new(
            rng.standard_normal(),
            rng.standard_normal(),
            rng.standard_normal(),
        );
        let mut pose = start + root * z;
        pose.z = wrap(pose.z);
        let mut cloud = clouds.iter_mut().peekable();
        if let Some(c) = cloud.next_if(|c| c.step == 0) {
            c.poses.push(pose.into());
        }
        for (k, (increment, (slip_r, slip_l))) in path.increments.iter().zip(&slips).enumerate() {
            let actual = Increment::new(
                increment.right + slip_r * rng.standard_normal(),
                increment.left + slip_l * rng.standard_normal(),
            );
            pose = step(&pose, actual, b);
            if let Some(c) = cloud.next_if(|c| c.step == k + 1) {
                c.poses.push(pose.into());
            }
        }
        final_poses.push(pose.into());
    }

    let nominal = propagation.final_pose();
    let covariance = propagation.final_covariance();
    let deviation = |p: &[f64; 3]| {
        Vector3::new(
            p[0] - nominal[0],
            p[1] - nominal[1],
            wrap(p[2] - nominal[2]),
        )
    };
    let n = robots as f64;
    let mean = final_poses.iter().map(deviation).sum::<Vector3<f64>>() / n;
    let scatter = final_poses
        .iter()
        .map(|p| {
            let d = deviation(p) - mean;
            d * d.transpose()
        })
        .sum::<Matrix3<f64>>();
    let [[a, c, _], [_, d, _], _] = covariance;
    let det = a * d - c * c;
    let inside_3_sigma = (det > 0.0 && det > 1e-12 * a * d).then(|| {
        let inside = final_poses
            .iter()
            .filter(|p| {
                let (dx, dy) = (p[0] - nominal[0], p[1] - nominal[1]);
                (d * dx * dx - 2.0 * c * dx * dy + a * dy * dy) / det <= 9.0
            })
            .count();
        inside as f64 / n
    });
    Ok(MonteCarlo {
        robots,
        steps,
        nominal,
        covariance,
        final_poses,
        clouds,
        sample_mean: [
            nominal[0] + mean.x,
            nominal[1] + mean.y,
            wrap(nominal[2] + mean.z),
        ],
        sample_covariance: to_rows(&(scatter / (n - 1.0))),
        inside_3_sigma,
        gaussian_inside_3_sigma: gaussian_share_inside(9.0),
    })
}
