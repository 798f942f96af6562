//! What the JavaScript harness reports after calling the student's code: the output (or
//! the error) of every call, and the trajectory of every data-set run. Numbers that JSON
//! cannot hold come as the strings "NaN", "Infinity" and "-Infinity"; `undefined` as the
//! string "undefined".

use serde::{Deserialize, Serialize};
use serde_json::Value;

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    #[serde(default)]
    pub functions: Vec<FunctionOutput>,
    #[serde(default)]
    pub runs: Vec<RunOutput>,
}

/// The calls of one function.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FunctionOutput {
    pub function: String,
    /// Why none or only some of the calls were made: the file does not compile, the
    /// function is missing, or the time limit ran out.
    #[serde(default)]
    pub error: Option<String>,
    #[serde(default)]
    pub results: Vec<CallResult>,
    /// Set by the host when it stopped the code.
    #[serde(default)]
    pub stopped: Option<Stopped>,
    /// Every call made once more, in reverse order, in a fresh copy of the file: a
    /// different answer means the function keeps state between calls.
    #[serde(default)]
    pub repeats: Vec<CallResult>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CallResult {
    pub id: String,
    #[serde(default)]
    pub output: Option<Value>,
    /// What the call threw.
    #[serde(default)]
    pub error: Option<String>,
}

/// One run of the given filter loop with the student's functions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunOutput {
    pub name: String,
    /// What stopped the run, naming the step and the function.
    #[serde(default)]
    pub error: Option<String>,
    /// Set by the host when it stopped the code.
    #[serde(default)]
    pub stopped: Option<Stopped>,
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

/// The host stopped the student's code: the time limit ran out, or the sandbox ran out of
/// memory or crashed. The outputs of that phase are lost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stopped {
    /// What was running: a case id, or a data-set run's time step.
    pub during: String,
    /// "time", or what else stopped it ("out of memory").
    pub cause: String,
}

impl Stopped {
    pub fn message(&self, limit_ms: u32) -> String {
        if self.cause == "time" {
            format!(
                "Stopped after {} s, the time limit, while running {}: an endless loop, or far too much work?",
                f64::from(limit_ms) / 1000.0,
                self.during
            )
        } else {
            format!("Stopped while running {}: {}.", self.during, self.cause)
        }
    }
}
