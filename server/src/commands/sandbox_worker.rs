//! `estlab sandbox-worker` (hidden): the worker process of the sandbox. Reads a
//! `WorkerInput` (the source, the job, how many engines at once) on stdin, runs the
//! student's code in QuickJS, writes the outputs on stdout.

use crate::error::Error;
use crate::sandbox::{MAX_SOURCE, WorkerInput, carry_out};
use std::io::Read;

pub fn run() -> Result<(), Error> {
    let mut text = String::new();
    std::io::stdin()
        .take(4 * MAX_SOURCE as u64 + (16 << 20))
        .read_to_string(&mut text)
        .map_err(Error::io("stdin"))?;
    let input: WorkerInput =
        serde_json::from_str(&text).map_err(|e| Error::Invalid(format!("stdin: {e}")))?;
    let outputs = carry_out(
        &input.source,
        input.native.as_ref(),
        &input.job,
        input.threads,
    )?;
    println!(
        "{}",
        serde_json::to_string(&outputs).expect("outputs serialise")
    );
    Ok(())
}
