//! What the harness's filter loop gets for one data-set run (the robot's constants, the
//! map and every step's encoder ticks and readings, never the ground truth) and what it
//! records.

use serde::{Deserialize, Serialize};
use serde_json::Value;
use ts_rs::TS;

/// One run of the lab's filter loop with the student's functions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct FilterRun {
    /// What `init` is called with: `o3`, `outliers`, `no-odometry`.
    pub dataset: String,
    pub mode: Mode,
    pub robot: RobotJob,
    /// The map, 2 x N: x of every landmark, then y.
    #[serde(rename = "M")]
    pub m: [Vec<f64>; 2],
    pub steps: Vec<StepJob>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    Sequential,
    Batch,
}

/// The robot's constants, named as the contract's arguments of `calculate_odometry`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct RobotJob {
    #[serde(rename = "E_T")]
    pub e_t: f64,
    #[serde(rename = "B")]
    pub b: f64,
    #[serde(rename = "R_R")]
    pub r_r: f64,
    #[serde(rename = "R_L")]
    pub r_l: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct StepJob {
    /// Seconds since the previous step (0 for the first).
    pub delta_t: f64,
    /// Encoder ticks of the right and the left wheel since the previous step.
    pub e_r: f64,
    pub e_l: f64,
    /// The readings of the step, 2 x n: ranges, then bearings.
    pub z: [Vec<f64>; 2],
}

/// What the filter loop records of a run: `init`'s answer, the belief after every step,
/// and every reading's association.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, TS)]
pub struct FilterRecord {
    /// What `init` returned.
    #[serde(default)]
    pub init: Option<Value>,
    /// The belief after every step: `mu` and `sigma` (9 numbers, row by row).
    #[serde(default)]
    pub mu: Vec<[f64; 3]>,
    #[serde(default)]
    pub sigma: Vec<[f64; 9]>,
    /// Per reading, in the order of the file: the associated landmark and whether it was
    /// rejected as an outlier.
    #[serde(default)]
    pub c: Vec<usize>,
    #[serde(default)]
    pub outlier: Vec<bool>,
}
