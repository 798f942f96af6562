//! Student code on the server: QuickJS in a worker process per grading.

mod cpu;
mod engine;
mod watchdog;
mod worker;

pub use engine::carry_out;
pub use worker::{MAX_SOURCE, Sandbox, WorkerInput, check_length, check_size};

/// The cores this process may use: what a lone grading spreads its phases over.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}
