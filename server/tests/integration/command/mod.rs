//! Running the `estlab` binary as a user runs it, and reading what it said.

#![allow(dead_code)]

use std::process::{Command, Output};

/// `estlab ARGS`, run to its end.
pub fn estlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_estlab"))
        .args(args)
        .output()
        .unwrap()
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}
