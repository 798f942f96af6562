//! The database: one SQLite file in the data directory (WAL, a busy timeout, the schema
//! migrated forward at every open). It holds the submissions and their results, the
//! courses with their people and assignments, and what signs people in (hashes only).
//! Every call is short and synchronous: the web handlers make them on blocking threads,
//! never on the async executor.

mod access;
mod answers;
mod courses;
mod regrades;
mod reports;
mod reviews;
mod schema;
mod staff;
mod submissions;

pub use access::{CodeCheck, FoundCode, TokenInfo};
pub use answers::SavedAnswer;
pub use courses::{Assignment, Course, Member, NewMember, Role, RosterChange};
pub use regrades::{Change, EarlierResult, Regrade, Scope};
pub use reports::Closed;
pub use reviews::{Mark, NewRound, Round, SheetAnswer, StoredPair};
pub use staff::{
    AuditEntry, Extension, Granted, NewExtension, NewWaiver, Rejudged, Waived, Waiver,
};
pub use submissions::{NewSubmission, Status, Submission, SubmissionSummary, ToGrade, Unfinished};

use rusqlite::Connection;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

/// The database file inside the data directory.
pub const FILE: &str = "estlab.sqlite3";

/// How long a statement waits for another process (a command of `estlab course` while
/// the server runs) to finish writing.
const BUSY_TIMEOUT: Duration = Duration::from_secs(10);

/// What can go wrong with the data directory and the database.
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
    #[error("a stored answer or question set is unreadable: {0}")]
    StoredAnswer(serde_json::Error),
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
    /// A course that is not set up; the message lists those that are.
    #[error("there is no course {name:?}; {}", known_courses(known))]
    UnknownCourse { name: String, known: Vec<String> },
    /// Nobody of that id or email in the course.
    #[error("course {course:?} has nobody with the id or email {login:?}")]
    UnknownMember { course: String, login: String },
    /// Input that contradicts what is stored (a student's id given to a staff member).
    #[error("{0}")]
    Conflict(String),
    #[error("a grading task stopped: {0}")]
    Task(String),
}

/// What an error of the store is, for whoever answers for it: an outcome of the request
/// (the asker can do something about it) or a failure of the server's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Someone or something the request names is not there.
    Missing,
    /// The request contradicts what is stored, or waits on it.
    Conflict,
    /// The data directory, the database, the secret or a task failed.
    Failure,
}

impl Error {
    pub fn kind(&self) -> Kind {
        match self {
            Error::UnknownCourse { .. } | Error::UnknownMember { .. } => Kind::Missing,
            Error::Busy(_) | Error::Conflict(_) => Kind::Conflict,
            Error::DataDir { .. }
            | Error::Database { .. }
            | Error::Sql(_)
            | Error::StoredResult(_)
            | Error::StoredAnswer(_)
            | Error::Secret { .. }
            | Error::Task(_) => Kind::Failure,
        }
    }
}

/// The names of the exercises this release grades, as a JSON array for `json_each`: rows of
/// another exercise (in the database of a later release) are left for a release that
/// grades it.
fn known_exercises() -> String {
    serde_json::to_string(&labs::Exercise::names()).expect("names serialise")
}

/// The exercise a row's column names (`lab`).
fn exercise(row: &rusqlite::Row, column: usize) -> rusqlite::Result<labs::Exercise> {
    named(row, column)
}

/// A value stored by its name (an exercise, a language).
fn named<T>(row: &rusqlite::Row, column: usize) -> rusqlite::Result<T>
where
    T: std::str::FromStr,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    let name: String = row.get(column)?;
    name.parse().map_err(|e| {
        rusqlite::Error::FromSqlConversionFailure(column, rusqlite::types::Type::Text, Box::new(e))
    })
}

/// A moment stored as whole seconds since 1970 (as `Timestamp::as_second` wrote it).
fn timestamp(seconds: i64) -> jiff::Timestamp {
    jiff::Timestamp::from_second(seconds).unwrap_or(jiff::Timestamp::UNIX_EPOCH)
}

fn known_courses(known: &[String]) -> String {
    if known.is_empty() {
        "no course is set up yet (estlab course create NAME --title TITLE)".into()
    } else {
        format!("the courses are: {}", known.join(", "))
    }
}

impl Error {
    fn database(path: &Path) -> impl FnOnce(rusqlite::Error) -> Error {
        let path = path.to_path_buf();
        move |source| Error::Database { path, source }
    }
}

/// The database, one connection shared behind a lock (every statement is short).
pub struct Store {
    connection: Mutex<Connection>,
    path: PathBuf,
}

impl Store {
    /// Opens the database in `dir`, creating the directory and the schema as needed and
    /// migrating an older schema forward.
    pub fn open(dir: &Path) -> Result<Store, Error> {
        std::fs::create_dir_all(dir).map_err(|source| Error::DataDir {
            path: dir.to_path_buf(),
            source,
        })?;
        let path = dir.join(FILE);
        let connection = Connection::open(&path).map_err(Error::database(&path))?;
        connection
            .busy_timeout(BUSY_TIMEOUT)
            .map_err(Error::database(&path))?;
        connection
            .execute_batch(
                "PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON;",
            )
            .map_err(Error::database(&path))?;
        schema::migrate(&connection).map_err(Error::database(&path))?;
        Ok(Store {
            connection: Mutex::new(connection),
            path,
        })
    }

    fn connection(&self) -> MutexGuard<'_, Connection> {
        // A panic while holding the lock leaves the connection usable: SQLite rolls back.
        self.connection.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Writes a consistent copy of the database to `target` with SQLite's online backup,
    /// while others go on reading and writing.
    pub fn backup(&self, target: &Path) -> Result<(), Error> {
        let connection = self.connection();
        connection
            .backup(
                rusqlite::MAIN_DB,
                target,
                None::<fn(rusqlite::backup::Progress)>,
            )
            .map_err(|source| Error::Database {
                path: target.to_path_buf(),
                source,
            })
    }

    /// Checks a copy of the database (read only): SQLite's integrity check passes, and
    /// it holds this many submissions.
    pub fn check_copy(path: &Path) -> Result<i64, Error> {
        let failed = Error::database(path);
        let copy = Connection::open_with_flags(path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
            .map_err(Error::database(path))?;
        let verdict: String = copy
            .query_row("PRAGMA integrity_check", [], |row| row.get(0))
            .map_err(Error::database(path))?;
        if verdict != "ok" {
            return Err(Error::Conflict(format!(
                "the copy {} fails SQLite's integrity check: {verdict}",
                path.display()
            )));
        }
        copy.query_row("SELECT count(*) FROM submissions", [], |row| row.get(0))
            .map_err(failed)
    }

    /// The database's file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}
