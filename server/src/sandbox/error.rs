//! What the sandbox fails with: a fault of its own, never the student's code (which ends
//! in a result that says what it did). A grading the sandbox failed is "not gradable",
//! which costs the student nothing; the texts below are its reason.

use std::process::ExitStatus;

/// The sandbox could not carry out a job.
#[derive(Debug, thiserror::Error)]
pub enum Failure {
    /// A worker outlived its allowance by the clock without using its CPU time.
    #[error("the sandbox did not finish within {seconds} s")]
    Hung { seconds: u64 },
    #[error("the sandbox could not be watched: {0}")]
    Unwatched(std::io::Error),
    /// A worker ended otherwise than the student's code can make it end.
    #[error("the sandbox failed ({status}){}", said(.complaints))]
    Crashed {
        status: ExitStatus,
        /// What it wrote on stderr.
        complaints: String,
    },
    #[error("the sandbox wrote unreadable outputs: {0}")]
    Unreadable(serde_json::Error),
    /// QuickJS refused to make a runtime or a context.
    #[error("QuickJS: {0}")]
    Engine(rquickjs::Error),
    /// The harness (or an exercise's loop, `the harness's loop`) did not load.
    #[error("{part}: {reason}")]
    Harness { part: &'static str, reason: String },
    /// The operating-system sandbox of an interpreter did not start.
    #[error("the interpreter's sandbox: {0}")]
    Jail(String),
    #[error("the sandbox could not start a thread: {0}")]
    Thread(std::io::Error),
    #[error("a sandbox thread panicked")]
    Panicked,
}

/// A worker's complaints after its status, if it made any.
fn said(complaints: &str) -> String {
    match complaints.trim() {
        "" => String::new(),
        said => format!(": {said}"),
    }
}

/// A submission too large to be graded.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
#[error("{bytes} bytes; a submission may have at most {} KB", .limit >> 10)]
pub struct TooLarge {
    pub bytes: u64,
    pub limit: usize,
}
