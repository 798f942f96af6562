//! The odometry's belief along a whole path: the nominal poses and how their covariance
//! grows.

use super::covariance::{from_rows, propagate_covariance, to_rows};
use super::motion::step;
use super::params::OdometryParams;
use super::path::Path;
use crate::Error;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// A path with the odometry's pose and covariance before the first step and after every
/// step: `poses[k]` and `covariances[k]` after `k` steps (so one more than the steps).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Propagation {
    pub path: Path,
    /// (x, y, theta), theta wrapped to [-pi, pi).
    pub poses: Vec<[f64; 3]>,
    /// Sigma_p, rows.
    pub covariances: Vec<[[f64; 3]; 3]>,
}

impl Propagation {
    /// The pose after the last step.
    pub fn final_pose(&self) -> [f64; 3] {
        *self
            .poses
            .last()
            .expect("a propagation starts with the start pose")
    }

    /// The covariance after the last step.
    pub fn final_covariance(&self) -> [[f64; 3]; 3] {
        *self
            .covariances
            .last()
            .expect("a propagation starts with the start covariance")
    }
}

/// Drives `params`' path with the odometry and propagates the covariance step by step:
///
/// p_{k+1} = f(p_k, delta_k),
/// Sigma_{k+1} = F_p Sigma_k F_p' + F_delta Sigma_delta F_delta',  Sigma_0 = `sigma0`
///
/// (see [`step`] and [`propagate_covariance`]).
pub fn propagate(params: &OdometryParams) -> Result<Propagation, Error> {
    let path = params.path()?;
    let mut poses = Vec::with_capacity(path.steps() + 1);
    let mut covariances = Vec::with_capacity(path.steps() + 1);
    let mut pose = Vector3::from(path.start);
    let mut sigma: Matrix3<f64> = from_rows(&params.sigma0);
    poses.push(pose.into());
    covariances.push(to_rows(&sigma));
    for &increment in &path.increments {
        sigma = propagate_covariance(
            &sigma,
            &pose,
            increment,
            params.wheel_base,
            params.k_r,
            params.k_l,
        );
        pose = step(&pose, increment, params.wheel_base);
        poses.push(pose.into());
        covariances.push(to_rows(&sigma));
    }
    Ok(Propagation {
        path,
        poses,
        covariances,
    })
}
