//! `estlab autograde`: what a package runs on the platform for every submission.

use crate::error::Error;
use crate::platforms::{gradescope, prairielearn};
use std::path::PathBuf;

/// Grade the submission a platform laid out, as a package of `estlab package` does, and
/// write the platform's results.json.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    platform: Platform,
}

#[derive(clap::Subcommand)]
enum Platform {
    /// Gradescope: source/ (the package), submission/, submission_metadata.json;
    /// writes results/results.json.
    Gradescope {
        #[arg(long, default_value = "/autograder")]
        root: PathBuf,
    },
    /// PrairieLearn: tests/ (the package's), student/, data/data.json; writes
    /// results/results.json.
    Prairielearn {
        #[arg(long, default_value = "/grade")]
        root: PathBuf,
    },
}

pub fn run(args: &Args) -> Result<(), Error> {
    match &args.platform {
        Platform::Gradescope { root } => gradescope::autograde(root),
        Platform::Prairielearn { root } => prairielearn::autograde(root),
    }
}
