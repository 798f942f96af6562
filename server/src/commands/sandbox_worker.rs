//! `estlab sandbox-worker` (hidden): the worker process of the sandbox. Reads
//! `{ "source": ..., "job": ... }` on stdin, runs the student's code in QuickJS, writes
//! the outputs on stdout.

use crate::error::Error;
use crate::sandbox::{MAX_SOURCE, carry_out};
use serde::Deserialize;
use std::io::Read;

#[derive(Deserialize)]
struct Input {
    source: String,
    job: serde_json::Value,
}

pub fn run() -> Result<(), Error> {
    let mut text = String::new();
    std::io::stdin()
        .take(4 * MAX_SOURCE as u64 + (16 << 20))
        .read_to_string(&mut text)
        .map_err(Error::io("stdin"))?;
    let input: Input =
        serde_json::from_str(&text).map_err(|e| Error::Invalid(format!("stdin: {e}")))?;
    let outputs = carry_out(&input.source, &input.job).map_err(Error::Invalid)?;
    println!("{outputs}");
    Ok(())
}
