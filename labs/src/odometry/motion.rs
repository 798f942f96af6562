//! One step of differential-drive odometry and its two Jacobians.
//!
//! The pose is `p = (x, y, theta)`. In one step the right wheel rolls `ds_r` and the left
//! wheel `ds_l` (signed: backwards is negative); `b` is the wheel base, the distance
//! between the wheels' contact points.

use crate::angle::wrap;
use nalgebra::{Matrix3, Matrix3x2, Vector3};
use serde::{Deserialize, Serialize};

/// How far each wheel rolled during one step, metres (negative: backwards).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Increment {
    /// `ds_r`
    pub right: f64,
    /// `ds_l`
    pub left: f64,
}

impl Increment {
    pub fn new(right: f64, left: f64) -> Self {
        Increment { right, left }
    }

    /// The distance the robot's centre moves and the change of heading:
    ///
    /// ds = (ds_r + ds_l) / 2,   dtheta = (ds_r - ds_l) / b
    pub fn displacement(&self, wheel_base: f64) -> (f64, f64) {
        (
            (self.right + self.left) / 2.0,
            (self.right - self.left) / wheel_base,
        )
    }
}

/// The heading the step is taken along, halfway through the turn: `phi = theta + dtheta/2`.
/// The chord of an arc that turns by `dtheta` points that way.
fn midpoint_heading(pose: &Vector3<f64>, increment: Increment, wheel_base: f64) -> (f64, f64, f64) {
    let (ds, dtheta) = increment.displacement(wheel_base);
    (ds, dtheta, pose.z + dtheta / 2.0)
}

/// The pose after one step:
///
/// p' = p + [ds cos(theta + dtheta/2), ds sin(theta + dtheta/2), dtheta],
///
/// the heading wrapped to [-pi, pi).
pub fn step(pose: &Vector3<f64>, increment: Increment, wheel_base: f64) -> Vector3<f64> {
    let (ds, dtheta, phi) = midpoint_heading(pose, increment, wheel_base);
    // One argument reduction for both (exactly libm's sin and cos: see the test of `Rng`).
    let (sin, cos) = libm::sincos(phi);
    Vector3::new(pose.x + ds * cos, pose.y + ds * sin, wrap(pose.z + dtheta))
}

/// `F_p = d p' / d p`, with `phi = theta + dtheta/2`:
///
/// ```text
///       | 1  0  -ds sin(phi) |
/// F_p = | 0  1   ds cos(phi) |
///       | 0  0   1           |
/// ```
///
/// x and y enter p' only through themselves; theta turns the direction of the step, so
/// an error of heading becomes an error of position that grows with the distance driven.
pub fn pose_jacobian(pose: &Vector3<f64>, increment: Increment, wheel_base: f64) -> Matrix3<f64> {
    let (ds, _, phi) = midpoint_heading(pose, increment, wheel_base);
    Matrix3::new(
        1.0,
        0.0,
        -ds * libm::sin(phi),
        0.0,
        1.0,
        ds * libm::cos(phi),
        0.0,
        0.0,
        1.0,
    )
}

/// `F_delta = d p' / d(ds_r, ds_l)`. Each wheel moves ds by 1/2 and dtheta by +-1/b, and
/// dtheta moves phi by half as much, so with `phi = theta + dtheta/2`:
///
/// ```text
///           | cos(phi)/2 - ds sin(phi)/(2b)    cos(phi)/2 + ds sin(phi)/(2b) |
/// F_delta = | sin(phi)/2 + ds cos(phi)/(2b)    sin(phi)/2 - ds cos(phi)/(2b) |
///           | 1/b                              -1/b                          |
/// ```
pub fn increment_jacobian(
    pose: &Vector3<f64>,
    increment: Increment,
    wheel_base: f64,
) -> Matrix3x2<f64> {
    let (ds, _, phi) = midpoint_heading(pose, increment, wheel_base);
    let (sin, cos) = (libm::sin(phi), libm::cos(phi));
    let b = wheel_base;
    Matrix3x2::new(
        cos / 2.0 - ds * sin / (2.0 * b),
        cos / 2.0 + ds * sin / (2.0 * b),
        sin / 2.0 + ds * cos / (2.0 * b),
        sin / 2.0 - ds * cos / (2.0 * b),
        1.0 / b,
        -1.0 / b,
    )
}
