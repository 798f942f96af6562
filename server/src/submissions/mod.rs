//! Submissions: stored first, then graded in the sandbox, one worker process each, a
//! bounded number at a time; the result is stored and shown to the student.

mod queue;
mod secret;
mod store;

pub use queue::Grader;
pub use secret::Secret;
pub use store::{NewSubmission, Store};

use std::path::{Path, PathBuf};

/// What can go wrong with the stored submissions.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("the data directory {}: {source}", path.display())]
    DataDir {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the database {}: {source}", path.display())]
    Database {
        path: PathBuf,
        source: rusqlite::Error,
    },
    #[error("the database: {0}")]
    Sql(#[from] rusqlite::Error),
    #[error("a stored result is unreadable: {0}")]
    StoredResult(serde_json::Error),
    #[error("the server's secret {}: {source}", path.display())]
    Secret {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The student already has a submission waiting or being graded.
    #[error(
        "your submission {0} is still waiting to be graded or being graded: submit again once it has its result"
    )]
    Busy(i64),
    #[error("a grading task stopped: {0}")]
    Task(String),
}

impl Error {
    fn database(path: &Path) -> impl FnOnce(rusqlite::Error) -> Error {
        let path = path.to_path_buf();
        move |source| Error::Database { path, source }
    }
}
