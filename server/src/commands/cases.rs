//! `estlab cases`: test cases of the student functions, as JSON.

use super::{print, read};
use crate::error::Error;
use labs::cases::{Case, FIXTURE_FILES, generate, load_fixtures};
use std::path::PathBuf;

/// Print test cases of the EKF localization functions as a JSON array: generated from a
/// seed (each student's variant), or the original EL2320 suite.
#[derive(clap::Args)]
pub struct Args {
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Cases of each function.
    #[arg(long, default_value_t = 20)]
    per_function: usize,
    /// Instead, convert the original EL2320 fixtures (test_case_*.json) in this directory.
    #[arg(long, value_name = "DIR")]
    el2320: Option<PathBuf>,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let cases: Vec<Case> = match &args.el2320 {
        Some(dir) => {
            let mut cases = Vec::new();
            for (function, file) in FIXTURE_FILES {
                cases.extend(load_fixtures(function, file, &read(&dir.join(file))?)?);
            }
            cases
        }
        None => generate(args.seed, args.per_function),
    };
    print(&serde_json::to_string(&cases).expect("cases serialise"))
}
