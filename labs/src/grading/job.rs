//! The job the JavaScript harness carries out with the student's code: one phase per
//! function (the arguments of its calls, never the expected outputs) and one per data-set
//! run (the data, never the ground truth), each with its time limit. Made by
//! [`Plan::job`](super::Plan::job); the harness reads it as JSON.

use serde::{Deserialize, Serialize};
use serde_json::Value;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    pub functions: Vec<FunctionPhase>,
    pub runs: Vec<RunPhase>,
}

/// The calls of one student function (`estlabHarness.callFunction`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FunctionPhase {
    pub function: String,
    pub calls: Vec<CallJob>,
    /// CPU time for all the calls of the phase, repeats included.
    pub limit_ms: u32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CallJob {
    /// `predict/p3`.
    pub id: String,
    /// The arguments in the contract's order; an infinite `Lambda_M` as "Infinity".
    pub args: Vec<Value>,
}

/// One run of the lab's filter loop with the student's functions
/// (`estlabHarness.runFilter`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunPhase {
    /// `no-odometry/batch`.
    pub name: String,
    /// What `init` is called with: `o3`, `outliers`, `no-odometry`.
    pub dataset: String,
    pub mode: Mode,
    pub robot: RobotJob,
    /// The map, 2 x N: x of every landmark, then y.
    #[serde(rename = "M")]
    pub m: [Vec<f64>; 2],
    pub steps: Vec<StepJob>,
    /// CPU time for the whole run.
    pub limit_ms: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    Sequential,
    Batch,
}

/// The robot's constants, named as the contract's arguments of `calculate_odometry`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepJob {
    /// Seconds since the previous step (0 for the first).
    pub delta_t: f64,
    /// Encoder ticks of the right and the left wheel since the previous step.
    pub e_r: f64,
    pub e_l: f64,
    /// The readings of the step, 2 x n: ranges, then bearings.
    pub z: [Vec<f64>; 2],
}

/// Which of the harness's entry points a phase goes to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhaseKind {
    Function,
    Run,
}

/// One phase of a job, of either kind.
#[derive(Clone, Copy, Debug)]
pub enum Phase<'a> {
    Function(&'a FunctionPhase),
    Run(&'a RunPhase),
}

impl Job {
    /// Every phase, the data-set runs (the longest) first.
    pub fn phases(&self) -> impl Iterator<Item = Phase<'_>> {
        self.runs
            .iter()
            .map(Phase::Run)
            .chain(self.functions.iter().map(Phase::Function))
    }

    /// Every phase's time limit, together, in milliseconds.
    pub fn limits_ms(&self) -> u64 {
        self.phases().map(|phase| u64::from(phase.limit_ms())).sum()
    }
}

impl Phase<'_> {
    pub fn kind(&self) -> PhaseKind {
        match self {
            Phase::Function(_) => PhaseKind::Function,
            Phase::Run(_) => PhaseKind::Run,
        }
    }

    /// The function's name, or the run's.
    pub fn name(&self) -> &str {
        match self {
            Phase::Function(phase) => &phase.function,
            Phase::Run(phase) => &phase.name,
        }
    }

    pub fn limit_ms(&self) -> u32 {
        match self {
            Phase::Function(phase) => phase.limit_ms,
            Phase::Run(phase) => phase.limit_ms,
        }
    }

    /// The phase as the harness reads it.
    pub fn to_json(&self) -> String {
        match self {
            Phase::Function(phase) => serde_json::to_string(phase),
            Phase::Run(phase) => serde_json::to_string(phase),
        }
        .expect("phases serialise")
    }
}
