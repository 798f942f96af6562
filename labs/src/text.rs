//! The lines of a whitespace-separated data file (the EL2320 files, MRCLAM's), read with
//! messages that name the file, the line and the value.

use crate::Error;
use std::fmt;

/// A line of a data file that holds something: its 1-based number and its values.
pub(crate) struct Line<'a> {
    pub file: &'a str,
    pub number: usize,
    pub tokens: Vec<&'a str>,
}

/// The lines of `text` that hold something (CRLF or LF; blank lines skipped).
pub(crate) fn lines<'a>(text: &'a str, file: &'a str) -> impl Iterator<Item = Line<'a>> {
    text.lines()
        .enumerate()
        .map(move |(i, line)| Line {
            file,
            number: i + 1,
            tokens: line.split_ascii_whitespace().collect(),
        })
        .filter(|line| !line.tokens.is_empty())
}

impl Line<'_> {
    pub fn error(&self, message: String) -> Error {
        Error::parse(self.file, self.number, message)
    }

    /// The finite number at `index`, which the message calls `what`.
    pub fn number(&self, index: usize, what: impl fmt::Display) -> Result<f64, Error> {
        let token = self.tokens[index];
        match token.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(value),
            _ => Err(self.error(format!(
                "value {} ({what}) is '{token}', which is not a finite number",
                index + 1
            ))),
        }
    }

    /// The non-negative whole number at `index` (`7` and `7.000000` both are).
    pub fn whole(&self, index: usize, what: impl fmt::Display) -> Result<u32, Error> {
        let value = self.number(index, &what)?;
        if value < 0.0 || value.fract() != 0.0 || value > f64::from(u32::MAX) {
            return Err(self.error(format!(
                "value {} ({what}) is '{}', which is not a whole number >= 0",
                index + 1,
                self.tokens[index]
            )));
        }
        Ok(value as u32)
    }
}

/// The times of a file's lines, which never go backwards (equal times may follow).
#[derive(Default)]
pub(crate) struct Times(Option<(usize, f64)>);

impl Times {
    /// Takes `t`, the time on `line`: an error naming both lines if it is earlier than the
    /// time before it.
    pub fn next(&mut self, line: &Line, t: f64) -> Result<(), Error> {
        if let Some((previous_line, previous_t)) = self.0
            && t < previous_t
        {
            return Err(line.error(format!(
                "time goes backwards: t = {t} here, but t = {previous_t} on line {previous_line}"
            )));
        }
        self.0 = Some((line.number, t));
        Ok(())
    }
}
