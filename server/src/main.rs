//! `estlab`: the estlab server and command line.

mod commands;
mod error;
mod sandbox;
mod submissions;
mod web;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "estlab",
    version,
    about = "Kalman filtering and EKF localization, taught and graded"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Serve(commands::serve::Args),
    Run(commands::run::Args),
    Simulate(commands::simulate::Args),
    Car(commands::car::Args),
    Cases(commands::cases::Args),
    Grade(commands::grade::Args),
    /// The sandbox's worker process (started by `grade` and `serve`).
    #[command(hide = true)]
    SandboxWorker,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Serve(args) => commands::serve::run(&args),
        Command::Run(args) => commands::run::run(&args),
        Command::Simulate(args) => commands::simulate::run(&args),
        Command::Car(args) => commands::car::run(&args),
        Command::Cases(args) => commands::cases::run(&args),
        Command::Grade(args) => commands::grade::run(&args),
        Command::SandboxWorker => commands::sandbox_worker::run(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("estlab: {err}");
            ExitCode::FAILURE
        }
    }
}
