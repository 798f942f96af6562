//! The job the JavaScript harness carries out with the student's code: one phase per
//! function (the arguments of its calls, never the expected outputs) and one per run of
//! the exercise's loop (the data, never the ground truth), each with its time limit. Made
//! by [`Plan::job`](super::Plan::job); the harness reads it as JSON.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use ts_rs::TS;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Job {
    pub functions: Vec<FunctionPhase>,
    pub runs: Vec<RunPhase>,
}

/// The calls of one student function (`estlabHarness.callFunction`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct FunctionPhase {
    pub function: String,
    pub calls: Vec<CallJob>,
    /// CPU time for all the calls of the phase, repeats included.
    pub limit_ms: u32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct CallJob {
    /// `predict/p3`.
    pub id: String,
    /// The arguments in the contract's order; an infinite `Lambda_M` as "Infinity".
    pub args: Vec<Value>,
}

/// One run of an exercise's loop with the student's functions (`estlabHarness.run`): the
/// envelope every exercise's runs share around the exercise's own data, which its loop in
/// the harness reads. The browser's type is the envelope alone: a loop types its phase as
/// `RunPhase & Data`, with its exercise's own data type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct RunPhase {
    /// The harness's loop: the exercise's [`run_loop`](crate::exercises::Declaration::run_loop).
    #[serde(rename = "loop")]
    pub run_loop: String,
    /// `no-odometry/batch`.
    pub name: String,
    /// The student functions the loop calls, which the harness takes from the file (and
    /// says which is missing) before the loop starts.
    pub functions: Vec<String>,
    /// CPU time for the whole run.
    pub limit_ms: u32,
    /// The exercise's data of the run, as its loop reads it.
    #[serde(flatten)]
    #[ts(skip)]
    pub data: Map<String, Value>,
}

impl RunPhase {
    /// A run of the loop `run_loop` called `name`, calling `functions`, over `data` (an
    /// object).
    pub fn new(
        run_loop: &str,
        name: &str,
        functions: &[&str],
        limit_ms: u32,
        data: &impl Serialize,
    ) -> RunPhase {
        let Ok(Value::Object(data)) = serde_json::to_value(data) else {
            panic!("a run's data serialises as an object");
        };
        RunPhase {
            run_loop: run_loop.to_owned(),
            name: name.to_owned(),
            functions: functions.iter().map(|&f| f.to_owned()).collect(),
            limit_ms,
            data,
        }
    }
}

/// Which of the harness's entry points a phase goes to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
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
    /// The job with every phase's time limit `factor` times as long (for a language
    /// whose interpreter is that much slower: [`crate::Language::time_factor`]).
    pub fn with_time_factor(mut self, factor: u32) -> Job {
        for phase in &mut self.functions {
            phase.limit_ms *= factor;
        }
        for run in &mut self.runs {
            run.limit_ms *= factor;
        }
        self
    }

    /// Every phase, the runs of the loop (the longest) first.
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
