//! `estlab cases`: test cases of an exercise's student functions, as JSON.

use super::{print, read};
use crate::error::Error;
use labs::Exercise;
use labs::exercises::ekf_localization::{FIXTURE_FILES, load_fixtures};
use std::path::PathBuf;
use std::str::FromStr;

/// Print test cases of an exercise's student functions as a JSON array: generated from a
/// seed (each student's variant), or the original EL2320 suite of the EKF localization
/// exercise.
#[derive(clap::Args)]
pub struct Args {
    /// The exercise, by name.
    #[arg(long, value_parser = Exercise::from_str, default_value_t = Exercise::default())]
    lab: Exercise,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Cases of each function.
    #[arg(long, default_value_t = 20)]
    per_function: usize,
    /// Instead, convert the original EL2320 fixtures (test_case_*.json) in this directory
    /// (EKF localization only).
    #[arg(long, value_name = "DIR")]
    el2320: Option<PathBuf>,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let text = match (args.lab, &args.el2320) {
        (Exercise::EkfLocalization, Some(dir)) => {
            let mut cases = Vec::new();
            for (function, file) in FIXTURE_FILES {
                cases.extend(load_fixtures(function, file, &read(&dir.join(file))?)?);
            }
            serde_json::to_string(&cases).expect("cases serialise")
        }
        (exercise, Some(_)) => {
            return Err(Error::Invalid(format!(
                "--el2320: the original EL2320 fixtures are the {} exercise's, not the {exercise} exercise's",
                Exercise::EkfLocalization
            )));
        }
        (exercise, None) => exercise.generated_cases(args.seed, args.per_function),
    };
    print(&text)
}
