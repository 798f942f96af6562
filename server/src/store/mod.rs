//! The database: by default one SQLite file in the data directory (WAL, a busy timeout),
//! or a PostgreSQL database that several web and grader processes share (`--database
//! postgres://...`); on either, the schema is migrated forward at every open. It holds the
//! submissions and their results, the courses with their people and assignments, and what
//! signs people in (hashes only). Every call is short and synchronous: the web handlers
//! make them on blocking threads, never on the async executor.

mod access;
mod answers;
mod codes_jobs;
mod courses;
pub mod db;
mod leases;
mod rates;
mod regrades;
mod reports;
mod reviews;
mod schema;
mod staff;
mod submissions;

pub use access::{CodeCheck, FoundCode, TokenInfo};
pub use answers::SavedAnswer;
pub use codes_jobs::CodesJob;
pub use courses::{Assignment, Course, Member, NewMember, Role, RosterChange};
pub use leases::{Claimable, Holder, Lease};
pub use rates::{Event, Window};
pub use regrades::{Change, EarlierResult, Regrade, Scope};
pub use reports::{Closed, ReportMaking};
pub use reviews::{Mark, NewRound, Round, SheetAnswer, StoredPair};
pub use staff::{
    AuditEntry, Extension, Granted, NewExtension, NewWaiver, Rejudged, Waived, Waiver,
};
pub use submissions::{NewSubmission, Status, Submission, SubmissionSummary, ToGrade, Unfinished};

use db::Connection;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

/// The database file inside the data directory.
pub const FILE: &str = "estlab.sqlite3";

/// How many times a transaction is tried when it keeps losing races (PostgreSQL).
const TRIES: u32 = 10;

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
    #[error("the database {place}: {source}")]
    Database { place: String, source: db::Error },
    #[error("the database: {0}")]
    Sql(#[from] db::Error),
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
    /// A grading's result, refused: its lease ran out and another grader took it (or
    /// wrote it already).
    #[error("{0} is no longer this grader's to write: its lease ran out")]
    LeaseLost(String),
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
            | Error::LeaseLost(_)
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
fn exercise(row: &db::Row, column: usize) -> db::Result<labs::Exercise> {
    named(row, column)
}

/// A value stored by its name (an exercise, a language).
fn named<T>(row: &db::Row, column: usize) -> db::Result<T>
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    let name: String = row.get(column)?;
    name.parse().map_err(|e: T::Err| db::Error::Column {
        column,
        reason: e.to_string(),
    })
}

/// A moment stored as whole seconds since 1970 (as `Timestamp::as_second` wrote it).
fn timestamp(seconds: i64) -> jiff::Timestamp {
    jiff::Timestamp::from_second(seconds).unwrap_or(jiff::Timestamp::UNIX_EPOCH)
}

/// A PostgreSQL database as its URL names it, without the password: `user@host:port/name`.
fn server_name(config: &postgres::Config) -> String {
    let host = match config.get_hosts().first() {
        Some(postgres::config::Host::Tcp(name)) => name.clone(),
        #[cfg(unix)]
        Some(postgres::config::Host::Unix(dir)) => dir.display().to_string(),
        None => "localhost".into(),
    };
    let port = config.get_ports().first().copied().unwrap_or(5432);
    let user = config.get_user().unwrap_or("");
    let name = config.get_dbname().unwrap_or(user);
    format!("postgres://{user}@{host}:{port}/{name}")
}

fn known_courses(known: &[String]) -> String {
    if known.is_empty() {
        "no course is set up yet (estlab course create NAME --title TITLE)".into()
    } else {
        format!("the courses are: {}", known.join(", "))
    }
}

impl Error {
    fn database<E: Into<db::Error>>(place: &Place) -> impl FnOnce(E) -> Error {
        let place = place.to_string();
        move |source| Error::Database {
            place,
            source: source.into(),
        }
    }
}

/// Where a store's data lives.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Place {
    /// A SQLite file.
    File(PathBuf),
    /// A PostgreSQL database, named without its password.
    Server(String),
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Place::File(path) => write!(f, "{}", path.display()),
            Place::Server(name) => f.write_str(name),
        }
    }
}

/// The database, one connection shared behind a lock (every statement is short).
pub struct Store {
    connection: Mutex<Connection>,
    place: Place,
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
        let place = Place::File(path.clone());
        let connection = rusqlite::Connection::open(&path).map_err(Error::database(&place))?;
        connection
            .busy_timeout(BUSY_TIMEOUT)
            .map_err(Error::database(&place))?;
        connection
            .execute_batch(
                "PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON;",
            )
            .map_err(Error::database(&place))?;
        Store::over(Connection::Sqlite(connection), place)
    }

    /// Connects to the PostgreSQL database a URL names (`postgres://user@host/name`, or
    /// `postgresql:///name?host=/run/postgresql` over a Unix socket), creating the schema
    /// as needed and migrating an older one forward.
    pub fn connect(url: &str) -> Result<Store, Error> {
        let config: postgres::Config = url.parse().map_err(|e: postgres::Error| {
            Error::Conflict(format!(
                "the database URL (--database or ESTLAB_DATABASE; not repeated here, as it may \
                 hold a password) is not one PostgreSQL reads: {e}"
            ))
        })?;
        let place = Place::Server(server_name(&config));
        let server = db::Postgres::connect(config).map_err(Error::database(&place))?;
        Store::over(Connection::Postgres(server), place)
    }

    fn over(connection: Connection, place: Place) -> Result<Store, Error> {
        schema::migrate(&connection).map_err(Error::database(&place))?;
        Ok(Store {
            connection: Mutex::new(connection),
            place,
        })
    }

    fn connection(&self) -> MutexGuard<'_, Connection> {
        // A panic while holding the lock leaves the connection usable: SQLite rolls back.
        self.connection.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `work` in one transaction, committed when it returns `Ok`.
    fn transaction<T>(
        &self,
        work: impl FnMut(&Connection) -> Result<T, Error>,
    ) -> Result<T, Error> {
        self.transaction_then(true, work)
    }

    /// Runs `work` in one transaction, committed when `commit` and it returns `Ok`, rolled
    /// back otherwise. On PostgreSQL, where transactions are serializable, a transaction
    /// that lost a race with another process's is run again from the start (SQLite's
    /// writers wait for each other instead).
    fn transaction_then<T>(
        &self,
        commit: bool,
        mut work: impl FnMut(&Connection) -> Result<T, Error>,
    ) -> Result<T, Error> {
        let connection = self.connection();
        let mut tries = 1;
        loop {
            let transaction = connection.transaction()?;
            let done = work(&transaction).and_then(|value| {
                if commit {
                    transaction.commit()?;
                }
                Ok(value)
            });
            match done {
                Err(Error::Sql(e)) if e.is_retryable() && tries < TRIES => {
                    // The other transaction is given a moment to end before this one's
                    // next try.
                    std::thread::sleep(std::time::Duration::from_millis(5 * u64::from(tries)));
                    tries += 1;
                }
                done => return done,
            }
        }
    }

    /// Writes a consistent copy of the database to `target` with SQLite's online backup,
    /// while others go on reading and writing.
    pub fn backup(&self, target: &Path) -> Result<(), Error> {
        let connection = self.connection();
        let Connection::Sqlite(connection) = &*connection else {
            return Err(Error::Conflict(format!(
                "{} is a PostgreSQL database: back it up with PostgreSQL's pg_dump",
                self.place
            )));
        };
        connection
            .backup(
                rusqlite::MAIN_DB,
                target,
                None::<fn(rusqlite::backup::Progress)>,
            )
            .map_err(Error::database(&Place::File(target.to_path_buf())))
    }

    /// Checks a copy of the database (read only): SQLite's integrity check passes, and
    /// it holds this many submissions.
    pub fn check_copy(path: &Path) -> Result<i64, Error> {
        let place = Place::File(path.to_path_buf());
        let failed = Error::database::<rusqlite::Error>(&place);
        let copy =
            rusqlite::Connection::open_with_flags(path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
                .map_err(Error::database(&place))?;
        let verdict: String = copy
            .query_row("PRAGMA integrity_check", [], |row| row.get(0))
            .map_err(Error::database(&place))?;
        if verdict != "ok" {
            return Err(Error::Conflict(format!(
                "the copy {} fails SQLite's integrity check: {verdict}",
                path.display()
            )));
        }
        copy.query_row("SELECT count(*) FROM submissions", [], |row| row.get(0))
            .map_err(failed)
    }

    /// Where the data lives.
    pub fn place(&self) -> &Place {
        &self.place
    }
}

/// A store for a unit test: in `dir` on SQLite, or in a new database of the test server
/// when the tests run on PostgreSQL (`ESTLAB_TEST_DATABASE=postgres`).
#[cfg(test)]
pub(crate) fn test_store(dir: &Path) -> Store {
    if pgtest::wanted() {
        Store::connect(&pgtest::database()).unwrap()
    } else {
        Store::open(dir).unwrap()
    }
}

/// A lease of 30 s from `from`, for a unit test.
#[cfg(test)]
pub(crate) fn test_lease(holder: &Holder, from: jiff::Timestamp) -> Lease<'_> {
    Lease {
        holder,
        from,
        length: std::time::Duration::from_secs(30),
    }
}
