//! EKF localization of a differential-drive robot (EL2320 Lab 1, section 3.2): one
//! function per step of the algorithm, each with the conventions the lab's original test
//! fixtures fix, and the filter loop over a whole data set.

mod association;
mod encoders;
mod filter;
mod geometry;
mod map;
mod observation;
mod predict;
mod update;

pub use association::{
    Association, Candidate, Match, associate, batch_associate, lambda_m, most_likely,
};
pub use encoders::{Robot, calculate_odometry};
pub use filter::{
    Decision, ReadingOutcome, Run, Settings, StepEstimate, Summary, UpdateMode, assemble,
    increments, run,
};
pub use geometry::{covariance_ellipse, reading_position};
pub use map::{Landmark, Map};
pub use observation::{jacobian_observation_model, observation_model};
pub use predict::{motion_jacobian, predict};
pub use update::{batch_update, update};

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// A Gaussian belief over the pose `[x, y, theta]`: mean `mu` and covariance `Sigma`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Belief {
    pub mu: Vector3<f64>,
    pub sigma: Matrix3<f64>,
}

impl Belief {
    pub fn new(mu: Vector3<f64>, sigma: Matrix3<f64>) -> Self {
        Belief { mu, sigma }
    }
}

/// `(A + A') / 2`: removes the asymmetry rounding leaves in a covariance.
fn symmetrise(a: &Matrix3<f64>) -> Matrix3<f64> {
    (a + a.transpose()) * 0.5
}
