//! What the harness's path loop gets for one run (the robot, its wheels' noise, where the
//! path starts and how far each wheel rolls at every step) and what it records.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// One run of the path loop with the student's functions: from `start` with Sigma_p = 0,
/// at every step
///
/// F_p = pose_jacobian(p, ds_r, ds_l, b), F_delta = increment_jacobian(p, ds_r, ds_l, b),
/// Sigma_delta = wheel_noise(ds_r, ds_l, k_r, k_l),
/// Sigma_p = propagate(Sigma_p, F_p, F_delta, Sigma_delta), p = odometry_step(p, ds_r, ds_l, b),
///
/// recording p and Sigma_p after the step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct PathRun {
    /// The pose before the first step, [x, y, theta].
    pub start: [f64; 3],
    /// The wheel base, metres.
    pub b: f64,
    /// Each wheel's distance variance per metre rolled, metres.
    pub k_r: f64,
    pub k_l: f64,
    /// [ds_r, ds_l] of every step, metres.
    pub steps: Vec<[f64; 2]>,
}

/// What the path loop records of a run: the pose and its covariance after every step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, TS)]
pub struct PathRecord {
    #[serde(default)]
    pub poses: Vec<[f64; 3]>,
    /// Sigma_p, as an array of rows.
    #[serde(default)]
    pub covariances: Vec<[[f64; 3]; 3]>,
}
