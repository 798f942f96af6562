//! One module per subcommand of `estlab`.

pub mod car;
pub mod cases;
pub mod grade;
pub mod run;
pub mod sandbox_worker;
pub mod serve;
pub mod simulate;

use crate::error::Error;
use std::path::Path;

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
