//! The submissions, kept in an embedded SQLite database in the data directory. A
//! submission is written before it is graded; its result is written when grading ends.

use super::Error;
use labs::grading::GradeResult;
use rusqlite::{Connection, OptionalExtension, params};
use serde::Serialize;
use std::path::Path;
use std::sync::Mutex;

/// The database file inside the data directory.
const FILE: &str = "estlab.sqlite3";

/// Each migration takes the schema from version `i` to `i + 1` (`PRAGMA user_version`).
const MIGRATIONS: &[&str] = &["CREATE TABLE submissions (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL,
        student TEXT NOT NULL,
        lab TEXT NOT NULL,
        seed INTEGER NOT NULL,
        source TEXT NOT NULL,
        status TEXT NOT NULL CHECK (status IN ('queued', 'grading', 'graded')),
        submitted_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
        graded_at TEXT,
        score REAL,
        result TEXT
    );
    CREATE INDEX submissions_by_student ON submissions (course, student, id);"];

/// Where a submission is on its way to a result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
enum Status {
    Queued,
    Grading,
    Graded,
}

impl Status {
    fn as_str(self) -> &'static str {
        match self {
            Status::Queued => "queued",
            Status::Grading => "grading",
            Status::Graded => "graded",
        }
    }

    fn parse(text: &str) -> Status {
        match text {
            "queued" => Status::Queued,
            "grading" => Status::Grading,
            _ => Status::Graded,
        }
    }
}

/// A submission as it is about to be stored.
pub struct NewSubmission<'a> {
    pub course: &'a str,
    pub student: &'a str,
    pub lab: &'a str,
    pub seed: u64,
    pub source: &'a str,
}

/// A stored submission, without its source.
#[derive(Debug, Serialize)]
pub struct Submission {
    id: i64,
    course: String,
    student: String,
    lab: String,
    seed: u64,
    status: Status,
    submitted_at: String,
    graded_at: Option<String>,
    result: Option<GradeResult>,
}

/// The database, one connection shared behind a lock (every statement is short).
pub struct Store {
    connection: Mutex<Connection>,
}

impl Store {
    /// Opens the database in `dir`, creating the directory and the schema as needed.
    pub fn open(dir: &Path) -> Result<Store, Error> {
        std::fs::create_dir_all(dir).map_err(|source| Error::DataDir {
            path: dir.to_path_buf(),
            source,
        })?;
        let path = dir.join(FILE);
        let connection = Connection::open(&path).map_err(Error::database(&path))?;
        connection
            .execute_batch("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;")
            .map_err(Error::database(&path))?;
        migrate(&connection).map_err(Error::database(&path))?;
        Ok(Store {
            connection: Mutex::new(connection),
        })
    }

    fn connection(&self) -> std::sync::MutexGuard<'_, Connection> {
        // A panic while holding the lock leaves the connection usable: SQLite rolls back.
        self.connection.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Stores a new submission as queued and returns its id; refuses it when the student
    /// already has one waiting or being graded in the same course and exercise.
    pub fn insert(&self, new: &NewSubmission) -> Result<i64, Error> {
        let connection = self.connection();
        let busy: Option<i64> = connection
            .query_row(
                "SELECT id FROM submissions WHERE course = ?1 AND student = ?2 AND lab = ?3
                 AND status != 'graded' ORDER BY id LIMIT 1",
                params![new.course, new.student, new.lab],
                |row| row.get(0),
            )
            .optional()
            .map_err(Error::Sql)?;
        if let Some(id) = busy {
            return Err(Error::Busy(id));
        }
        connection
            .execute(
                "INSERT INTO submissions (course, student, lab, seed, source, status)
                 VALUES (?1, ?2, ?3, ?4, ?5, 'queued')",
                params![
                    new.course,
                    new.student,
                    new.lab,
                    new.seed as i64,
                    new.source
                ],
            )
            .map_err(Error::Sql)?;
        Ok(connection.last_insert_rowid())
    }

    /// Marks a submission as being graded and returns its source and seed.
    pub fn start_grading(&self, id: i64) -> Result<(String, u64), Error> {
        let connection = self.connection();
        connection
            .execute(
                "UPDATE submissions SET status = ?2 WHERE id = ?1",
                params![id, Status::Grading.as_str()],
            )
            .map_err(Error::Sql)?;
        connection
            .query_row(
                "SELECT source, seed FROM submissions WHERE id = ?1",
                [id],
                |row| Ok((row.get(0)?, row.get::<_, i64>(1)? as u64)),
            )
            .map_err(Error::Sql)
    }

    /// Stores the result of a grading.
    pub fn finish_grading(&self, id: i64, result: &GradeResult) -> Result<(), Error> {
        let text = serde_json::to_string(result).expect("results serialise");
        self.connection()
            .execute(
                "UPDATE submissions SET status = 'graded', result = ?2, score = ?3,
                 graded_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE id = ?1",
                params![id, text, result.gradable.then_some(result.score)],
            )
            .map_err(Error::Sql)?;
        Ok(())
    }

    /// Ends a submission whose grading failed as not gradable, with the reason.
    pub fn give_up(&self, id: i64, reason: &str) -> Result<(), Error> {
        let (lab, seed): (String, i64) = self
            .connection()
            .query_row(
                "SELECT lab, seed FROM submissions WHERE id = ?1",
                [id],
                |row| Ok((row.get(0)?, row.get(1)?)),
            )
            .map_err(Error::Sql)?;
        self.finish_grading(id, &GradeResult::not_gradable(&lab, seed as u64, reason))
    }

    /// The submissions whose grading has not finished (queued, or cut off by a stop), oldest first.
    pub fn unfinished(&self) -> Result<Vec<i64>, Error> {
        let connection = self.connection();
        let mut statement = connection
            .prepare("SELECT id FROM submissions WHERE status != 'graded' ORDER BY id")
            .map_err(Error::Sql)?;
        let ids = statement
            .query_map([], |row| row.get(0))
            .map_err(Error::Sql)?
            .collect::<Result<_, _>>()
            .map_err(Error::Sql)?;
        Ok(ids)
    }

    /// One submission, if it exists. The result is read after the lock is released.
    pub fn get(&self, id: i64) -> Result<Option<Submission>, Error> {
        let row = self
            .connection()
            .query_row(
                "SELECT id, course, student, lab, seed, status, submitted_at, graded_at, result
                 FROM submissions WHERE id = ?1",
                [id],
                |row| {
                    Ok((
                        Submission {
                            id: row.get(0)?,
                            course: row.get(1)?,
                            student: row.get(2)?,
                            lab: row.get(3)?,
                            seed: row.get::<_, i64>(4)? as u64,
                            status: Status::parse(&row.get::<_, String>(5)?),
                            submitted_at: row.get(6)?,
                            graded_at: row.get(7)?,
                            result: None,
                        },
                        row.get::<_, Option<String>>(8)?,
                    ))
                },
            )
            .optional()
            .map_err(Error::Sql)?;
        row.map(|(submission, result)| {
            let result = result
                .map(|text| serde_json::from_str(&text).map_err(Error::StoredResult))
                .transpose()?;
            Ok(Submission {
                result,
                ..submission
            })
        })
        .transpose()
    }
}

/// Brings the schema up to the newest version, one migration per transaction.
fn migrate(connection: &Connection) -> rusqlite::Result<()> {
    let version: i64 = connection.query_row("PRAGMA user_version", [], |row| row.get(0))?;
    for (i, migration) in MIGRATIONS.iter().enumerate().skip(version as usize) {
        connection.execute_batch(&format!(
            "BEGIN; {migration}; PRAGMA user_version = {}; COMMIT;",
            i + 1
        ))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn new<'a>(student: &'a str, source: &'a str) -> NewSubmission<'a> {
        NewSubmission {
            course: "el2320",
            student,
            lab: "ekf-localization",
            seed: 7,
            source,
        }
    }

    #[test]
    fn a_student_has_one_submission_waiting_and_a_failed_grading_frees_the_next() {
        let dir = tempfile::tempdir().unwrap();
        let store = Store::open(dir.path()).unwrap();
        let first = store.insert(&new("ada", "// one")).unwrap();
        // Another student is not held up; the same student is, while the first waits.
        store.insert(&new("grace", "// other")).unwrap();
        assert!(matches!(store.insert(&new("ada", "// two")), Err(Error::Busy(id)) if id == first));
        store.start_grading(first).unwrap();
        assert!(matches!(
            store.insert(&new("ada", "// two")),
            Err(Error::Busy(_))
        ));

        // Grading failed on the server's side: the submission ends not gradable, the
        // student may submit again, and nothing is lost.
        store
            .give_up(first, "the server could not grade it")
            .unwrap();
        let ended = store.get(first).unwrap().unwrap();
        assert_eq!(ended.status, Status::Graded);
        let result = ended.result.unwrap();
        assert!(!result.gradable);
        assert_eq!(
            result.reason.as_deref(),
            Some("the server could not grade it")
        );
        assert_eq!(result.seed, 7);
        let second = store.insert(&new("ada", "// two")).unwrap();
        assert!(second > first);
        assert_eq!(store.start_grading(first).unwrap().0, "// one");
    }
}
