use std::fmt;

/// Everything that can go wrong in `labs`: bad input, named precisely.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A data file that does not follow its format. `line` is 1-based; 0 means the whole
    /// file.
    #[error("{file}{}: {message}", Line(*line))]
    Parse {
        file: String,
        line: usize,
        message: String,
    },
    /// A setting or an input that is out of its domain.
    #[error("{field}: {message}")]
    Invalid { field: String, message: String },
}

impl Error {
    pub fn parse(file: &str, line: usize, message: impl Into<String>) -> Self {
        Error::Parse {
            file: file.to_owned(),
            line,
            message: message.into(),
        }
    }

    pub fn invalid(field: &str, message: impl Into<String>) -> Self {
        Error::Invalid {
            field: field.to_owned(),
            message: message.into(),
        }
    }
}

struct Line(usize);

impl fmt::Display for Line {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            0 => Ok(()),
            line => write!(f, ":{line}"),
        }
    }
}
