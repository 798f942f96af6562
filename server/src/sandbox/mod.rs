//! Student code on the server: a worker process per grading, running JavaScript on V8 in an
//! operating-system sandbox (in QuickJS where that does not start) and other languages in
//! their interpreters, each in a sandbox of its own.

mod cpu;
mod engine;
mod error;
mod memory;
mod native;
mod watchdog;
mod worker;

pub use cpu::{started_by, workers_spent};
pub use engine::carry_out;
pub use error::{Failure, TooLarge};
pub use native::Unavailable;
pub use worker::{
    Code, JavaScript, MAX_SOURCE, Sandbox, Tried, WorkerInput, check_length, check_size,
};

/// Why the sandbox could not grade a file now, through no doing of the file's: the
/// grader puts the grading back in line and tries again later (`estlab grade`, which
/// cannot, says it as "not gradable", which costs nothing).
#[derive(Debug, thiserror::Error)]
pub enum NotNow {
    #[error(transparent)]
    DidNotStart(#[from] DidNotStart),
    /// Its worker did not finish within its allowance by the clock, though its CPU time
    /// was not used up (the kernel ends a worker that uses it up): the machine gave it too
    /// little of a core, or stopped it. The student's code is judged by its CPU time
    /// alone, never by how busy the machine was.
    #[error(
        "the sandbox did not finish within {seconds} s by the clock, its CPU time not used up: the machine was too busy"
    )]
    Starved { seconds: u64 },
}

/// A worker that could not be started (`Command::spawn` failed: no descriptors left for
/// its pipes, no memory or processes for a fork, the executable missing). The student's
/// code has not run, so this is the server's fault, never a result: the grader waits and
/// tries again (`Sandbox::try_grade`), while `estlab grade` reports it as "not gradable".
#[derive(Debug, thiserror::Error)]
#[error("the sandbox did not start: {0}")]
pub struct DidNotStart(pub std::io::Error);

/// The cores this process may use: what a lone grading spreads its phases over.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// Marks every descriptor from `first` on to be closed at the next exec.
pub(crate) fn close_others_at_exec(first: std::os::fd::RawFd) -> std::io::Result<()> {
    // SAFETY: close_range only changes this process's descriptor table.
    let status = unsafe {
        libc::syscall(
            libc::SYS_close_range,
            first as libc::c_uint,
            libc::c_uint::MAX,
            libc::CLOSE_RANGE_CLOEXEC,
        )
    };
    if status < 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}
