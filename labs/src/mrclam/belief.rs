//! What every filter offers: its belief about the pose after each step, the interface
//! the run drives, and what became of the step's readings.

use super::grid::{Control, Reading};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// A Gaussian belief about the pose (x, y, heading): the heading wrapped, and the
/// covariance's heading row and column in radians.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Belief {
    pub mean: Vector3<f64>,
    pub covariance: Matrix3<f64>,
}

/// What became of a step's readings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "MrclamReadings")]
pub struct Readings {
    /// Readings that corrected the belief.
    #[ts(type = "number")]
    pub used: usize,
    /// Readings the gate turned away.
    #[ts(type = "number")]
    pub rejected: usize,
}

impl std::ops::AddAssign for Readings {
    fn add_assign(&mut self, other: Readings) {
        self.used += other.used;
        self.rejected += other.rejected;
    }
}

/// A localization filter on the grid: a prediction under the step's control, then the
/// step's readings.
pub trait Filter {
    fn predict(&mut self, u: Control, dt: f64);
    fn update(&mut self, readings: &[Reading]) -> Readings;
    fn belief(&self) -> Belief;
    /// The poses the filter carries besides its belief, to draw: the particle filter's
    /// particles, the UKF's sigma points of its last prediction; none for the EKF.
    fn samples(&self) -> Vec<Vector3<f64>> {
        Vec::new()
    }
}
