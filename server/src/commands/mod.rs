//! One module per subcommand of `estlab`.

pub mod autograde;
pub mod backup;
pub mod car;
pub mod cases;
pub mod course;
pub mod data;
pub mod fusion;
pub mod grade;
pub mod grade_class;
pub mod grader;
pub mod grading;
pub mod mrclam;
pub mod odometry;
pub mod package;
pub mod run;
pub mod sandbox_worker;
pub mod serve;
pub mod simulate;

use crate::error::Error;
use clap::{Parser, Subcommand};
use std::path::Path;
use std::process::ExitCode;

/// What `estlab --version` prints: the release and the hash of the sources it was built
/// from (`build.rs`).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (sources ",
    env!("ESTLAB_SOURCES"),
    ")"
);

#[derive(Parser)]
#[command(
    name = "estlab",
    version = VERSION,
    about = "Kalman filtering and EKF localization, taught and graded"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Serve(serve::Args),
    Run(run::Args),
    Simulate(simulate::Args),
    Car(car::Args),
    Odometry(odometry::Args),
    Fusion(fusion::Args),
    Mrclam(mrclam::Args),
    Cases(cases::Args),
    Grade(grade::Args),
    GradeClass(grade_class::Args),
    Grader(grader::Args),
    Course(course::Args),
    Backup(backup::Args),
    Package(package::Args),
    Autograde(autograde::Args),
    /// The sandbox's worker process (started by `grade` and `serve`).
    #[command(hide = true)]
    SandboxWorker,
}

/// Runs the command the command line names; prints its error, if any, on stderr.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    if matches!(
        cli.command,
        Command::Serve(_)
            | Command::Grader(_)
            | Command::Course(_)
            | Command::Backup(_)
            | Command::GradeClass(_)
    ) {
        private_files();
    }
    let result = match cli.command {
        Command::Serve(args) => serve::run(&args),
        Command::Run(args) => run::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Car(args) => car::run(&args),
        Command::Odometry(args) => odometry::run(&args),
        Command::Fusion(args) => fusion::run(&args),
        Command::Mrclam(args) => mrclam::run(&args),
        Command::Cases(args) => cases::run(&args),
        Command::Grade(args) => grade::run(&args),
        Command::GradeClass(args) => grade_class::run(&args),
        Command::Grader(args) => grader::run(&args),
        Command::Course(args) => course::run(&args),
        Command::Backup(args) => backup::run(&args),
        Command::Package(args) => package::run(&args),
        Command::Autograde(args) => autograde::run(&args),
        Command::SandboxWorker => sandbox_worker::run(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("estlab: {err}");
            ExitCode::FAILURE
        }
    }
}

/// Files and folders made from here on are the user's alone: the database, its backups,
/// exports and grades hold students' work, names and emails.
fn private_files() {
    // SAFETY: umask only sets the process's file mode mask; it cannot fail.
    unsafe {
        libc::umask(0o077);
    }
}

/// A comma-separated list of exactly `N` numbers, for flags such as `--R 1e-4,1e-4,3e-4`.
pub fn numbers<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| {
            part.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{}' is not a number", part.trim()))
        })
        .collect::<Result<_, _>>()?;
    values.try_into().map_err(|values: Vec<f64>| {
        format!("expected {N} comma-separated numbers, got {}", values.len())
    })
}

/// The text of a file, or an error naming it.
pub fn read(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(Error::io(path))
}

/// Prints `text` and a newline on standard output; a reader that has stopped reading (as
/// `| head` does) is not an error.
pub fn print(text: &str) -> Result<(), Error> {
    use std::io::Write;
    match writeln!(std::io::stdout().lock(), "{text}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Error::io("standard output")(e))
        }
        _ => Ok(()),
    }
}

/// The file name of a path, for messages.
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |name| name.to_string_lossy().into_owned(),
    )
}

/// A number in scientific notation with at most 5 significant digits: `1e-4`, `3.0462e-4`.
pub fn short(value: f64) -> String {
    let text = format!("{value:.4e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            format!(
                "{}e{exponent}",
                mantissa.trim_end_matches('0').trim_end_matches('.')
            )
        }
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    /// Every subcommand's flags are well formed (clap checks them only as the subcommand
    /// is parsed): no two of a name, no group named twice.
    #[test]
    fn the_command_line_is_well_formed() {
        use clap::CommandFactory;
        super::Cli::command().debug_assert();
    }
}
