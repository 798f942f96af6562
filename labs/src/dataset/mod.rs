//! Data sets in the EL2320 format: a landmark map and a sensor log, how to read and write
//! them, and a simulator that makes new ones.

mod format;
mod simulate;

pub use format::{parse_map, parse_sensor_log, write_map, write_sensor_log};
pub use simulate::{Kind, simulate};

use crate::ekf::Map;
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// A map and the sensor log of one run through it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dataset {
    pub map: Map,
    pub log: SensorLog,
}

/// One line of a sensor file per time step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorLog {
    pub steps: Vec<Step>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// Time, seconds.
    pub t: f64,
    /// The simulator's own dead reckoning (not used by the filter).
    pub odometry: Vector3<f64>,
    /// Cumulative encoder ticks of the right and the left wheel.
    pub encoders: Encoders,
    /// The true pose.
    pub truth: Vector3<f64>,
    pub readings: Vec<Reading>,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Encoders {
    pub right: f64,
    pub left: f64,
}

/// One range-bearing reading of a landmark.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reading {
    /// The id of the landmark that produced the reading (the true association).
    pub id: u32,
    /// The index of that landmark in the map.
    pub landmark: usize,
    /// `[range, bearing]`, bearing as in the file (not necessarily wrapped).
    pub z: Vector2<f64>,
}

impl SensorLog {
    pub fn readings(&self) -> usize {
        self.steps.iter().map(|step| step.readings.len()).sum()
    }
}
