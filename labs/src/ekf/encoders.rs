//! The control of a step from the wheel encoders: the distance each wheel rolled from its
//! ticks, and the pose increment they make (the lab's `calculate_odometry`; the model of
//! odometry and its error growth is [`crate::odometry`]).

use crate::angle::wrap;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// The robot's odometry constants.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Robot {
    /// `E_T`: encoder ticks per wheel revolution.
    pub ticks_per_revolution: f64,
    /// `B`: wheel base, metres.
    pub wheel_base: f64,
    /// `R_R`: right wheel radius, metres.
    pub right_radius: f64,
    /// `R_L`: left wheel radius, metres.
    pub left_radius: f64,
}

impl Robot {
    /// The robot of the EL2320 data sets.
    pub const EL2320: Robot = Robot {
        ticks_per_revolution: 2048.0,
        wheel_base: 0.35,
        right_radius: 0.1,
        left_radius: 0.1,
    };
}

/// The control `u` from the encoder ticks counted during the last `delta_t` seconds
/// (EL2320 eq. 4):
///
/// omega_R = 2 pi dE_R / (E_T dt),  omega_L = 2 pi dE_L / (E_T dt)
/// v = (omega_R R_R + omega_L R_L) / 2,  omega = (omega_R R_R - omega_L R_L) / B
/// u = [v dt cos(theta), v dt sin(theta), omega dt]
///
/// with theta the heading of `mu`. `u` is zero when `delta_t` is 0 (the first step).
pub fn calculate_odometry(
    delta_right: f64,
    delta_left: f64,
    robot: &Robot,
    delta_t: f64,
    mu: &Vector3<f64>,
) -> Vector3<f64> {
    if delta_t == 0.0 {
        return Vector3::zeros();
    }
    let omega_right = TAU * delta_right / (robot.ticks_per_revolution * delta_t);
    let omega_left = TAU * delta_left / (robot.ticks_per_revolution * delta_t);
    let v = (omega_right * robot.right_radius + omega_left * robot.left_radius) / 2.0;
    let omega =
        (omega_right * robot.right_radius - omega_left * robot.left_radius) / robot.wheel_base;
    let theta = mu.z;
    Vector3::new(
        v * delta_t * libm::cos(theta),
        v * delta_t * libm::sin(theta),
        wrap(omega * delta_t),
    )
}
