//! What the JavaScript harness reports after calling the student's code: the output (or
//! the error) of every call, and what every run of the exercise's loop recorded. Numbers
//! that JSON cannot hold come as the strings "NaN", "Infinity" and "-Infinity"; `undefined`
//! as the string "undefined".

use super::job::Job;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use ts_rs::TS;

/// Why a phase's report could not be read; the student's code can spoil what the harness
/// writes (not what it records), so this fails the phase and leaves the rest gradable.
const UNREADABLE: &str = "The test harness's report of this phase is unreadable, which happens when a file changes built-in objects";

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, TS)]
pub struct Outputs {
    #[serde(default)]
    pub functions: Vec<FunctionOutput>,
    #[serde(default)]
    pub runs: Vec<RunOutput>,
}

impl Outputs {
    /// Every phase of `job` ended alike, before or instead of running: what stopped the
    /// file, or why its outputs cannot be used.
    pub fn every_phase(
        job: &Job,
        function: impl Fn(&str) -> FunctionOutput,
        run: impl Fn(&str) -> RunOutput,
    ) -> Outputs {
        Outputs {
            functions: job
                .functions
                .iter()
                .map(|p| function(&p.function))
                .collect(),
            runs: job.runs.iter().map(|p| run(&p.name)).collect(),
        }
    }
}

/// The harness's reports as the host received them, each phase read on its own.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct Reports {
    #[serde(default)]
    pub functions: Vec<Value>,
    #[serde(default)]
    pub runs: Vec<Value>,
}

impl Reports {
    /// Every report read as its phase's output; one that does not read is that phase
    /// failed (it names its function or run, when that much can be read).
    pub fn outputs(self) -> Outputs {
        let name = |report: &Value, field: &str| {
            report
                .get(field)
                .and_then(Value::as_str)
                .unwrap_or("unknown")
                .to_owned()
        };
        Outputs {
            functions: self
                .functions
                .into_iter()
                .map(|report| FunctionOutput::from_value(&name(&report, "function"), report))
                .collect(),
            runs: self
                .runs
                .into_iter()
                .map(|report| RunOutput::from_value(&name(&report, "name"), report))
                .collect(),
        }
    }
}

/// The output of one phase, read from the harness's report: what a report that does not
/// read becomes is that phase failed, with the reason.
pub trait PhaseOutput: DeserializeOwned {
    /// The function's name, or the run's.
    fn phase_name(&self) -> &str;

    /// The phase failed before anything ran, and why.
    fn failed(name: &str, error: String) -> Self;

    /// The harness's report (JSON text) of the phase called `name`.
    fn from_report(name: &str, report: &str) -> Self {
        match serde_json::from_str(report) {
            Ok(value) => Self::from_value(name, value),
            Err(e) => Self::failed(name, format!("{UNREADABLE} ({e}).")),
        }
    }

    /// The same, already parsed (the browser's runner parses what its worker posts).
    fn from_value(name: &str, report: Value) -> Self {
        match serde_json::from_value::<Self>(report) {
            Ok(output) if output.phase_name() == name => output,
            Ok(output) => Self::failed(
                name,
                format!("{UNREADABLE} (it names {:?}).", output.phase_name()),
            ),
            Err(e) => Self::failed(name, format!("{UNREADABLE} ({e}).")),
        }
    }
}

impl PhaseOutput for FunctionOutput {
    fn phase_name(&self) -> &str {
        &self.function
    }

    fn failed(function: &str, error: String) -> FunctionOutput {
        FunctionOutput {
            function: function.to_owned(),
            error: Some(error),
            results: Vec::new(),
            stopped: None,
            repeats: Vec::new(),
        }
    }
}

impl PhaseOutput for RunOutput {
    fn phase_name(&self) -> &str {
        &self.name
    }

    fn failed(name: &str, error: String) -> RunOutput {
        RunOutput {
            name: name.to_owned(),
            error: Some(error),
            stopped: None,
            recorded: None,
        }
    }
}

/// The calls of one function.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
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

impl FunctionOutput {
    /// A phase the host stopped.
    pub fn stopped(function: &str, stopped: Stopped) -> FunctionOutput {
        FunctionOutput {
            error: None,
            stopped: Some(stopped),
            ..FunctionOutput::failed(function, String::new())
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct CallResult {
    pub id: String,
    /// What the call returned: `null` is an answer too (`Some(Value::Null)`).
    #[serde(default, deserialize_with = "answer")]
    pub output: Option<Value>,
    /// What the call threw.
    #[serde(default)]
    pub error: Option<String>,
}

/// An output that is there, even as `null`: a call that returned null returned something,
/// where serde's own `Option` would read null as no output at all ("not run").
fn answer<'de, D: serde::Deserializer<'de>>(output: D) -> Result<Option<Value>, D::Error> {
    Value::deserialize(output).map(Some)
}

/// One run of an exercise's loop with the student's functions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct RunOutput {
    pub name: String,
    /// What stopped the run, naming the step and the function.
    #[serde(default)]
    pub error: Option<String>,
    /// Set by the host when it stopped the code.
    #[serde(default)]
    pub stopped: Option<Stopped>,
    /// What the loop recorded until it ended (none when the file did not load), as the
    /// exercise's loop writes it: read with [`RunOutput::record`].
    #[serde(default, rename = "record")]
    pub recorded: Option<Value>,
}

impl RunOutput {
    /// What the loop recorded, read as the exercise's record `R`: its default when the
    /// run recorded nothing, and why not when the record does not read (the student's
    /// code can spoil what the harness writes).
    pub fn record<R: DeserializeOwned + Default>(&self) -> Result<R, String> {
        match &self.recorded {
            None => Ok(R::default()),
            Some(record) => R::deserialize(record).map_err(|e| format!("{UNREADABLE} ({e}).")),
        }
    }

    /// The record of a run that went to its end, or why it did not: its record does not
    /// read, the student's code (or the loop's check of what it returned) threw, or the
    /// host stopped it (`limit_ms`, the run's time limit, for the message).
    pub fn completed<R: DeserializeOwned + Default>(&self, limit_ms: u32) -> Result<R, String> {
        let record = self.record::<R>();
        let ended = record
            .as_ref()
            .err()
            .cloned()
            .or_else(|| self.error.clone());
        match ended.or_else(|| self.stopped.as_ref().map(|s| s.message(limit_ms))) {
            Some(why) => Err(why),
            None => record,
        }
    }

    /// A run the host stopped.
    pub fn stopped(name: &str, stopped: Stopped) -> RunOutput {
        RunOutput {
            error: None,
            stopped: Some(stopped),
            ..RunOutput::failed(name, String::new())
        }
    }
}

/// The host stopped the student's code: the time limit ran out, or the sandbox ran out of
/// memory or crashed. The outputs of that phase are lost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct Stopped {
    /// What was running: a case id, or a run's step.
    pub during: String,
    pub cause: Cause,
    /// The time limit that ran out, when it was not the phase's own (the file's top level
    /// is evaluated once, with a limit of its own, before any phase).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_ms: Option<u32>,
}

impl Stopped {
    /// What happened, for the student; `phase_limit_ms` is the phase's time limit.
    pub fn message(&self, phase_limit_ms: u32) -> String {
        match &self.cause {
            Cause::Time => format!(
                "Stopped after {} s, the time limit, while running {}: an endless loop, or far too much work?",
                f64::from(self.limit_ms.unwrap_or(phase_limit_ms)) / 1000.0,
                self.during
            ),
            Cause::Cancelled => format!("Stopped while running {}: you stopped it.", self.during),
            Cause::Other(what) => format!("Stopped while running {}: {what}.", self.during),
        }
    }
}

/// What stopped the student's code.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub enum Cause {
    /// The phase's time limit ran out.
    #[serde(rename = "time")]
    Time,
    /// The student stopped it (in the browser).
    #[serde(rename = "you stopped it")]
    Cancelled,
    /// Anything else, in words: "out of memory (the limit is 64 MB)".
    #[serde(untagged)]
    Other(String),
}
