//! Courses, their people (students of the roster and staff) and their assignments.

use super::db::{self, Connection, OptionalExtension, Row, params};
use super::timestamp;
use super::{Error, Store, exercise, known_exercises};
use crate::courses::deadline::{Counts, Policy};
use crate::courses::roster;
use jiff::Timestamp;
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// A course as set up with `estlab course create`.
#[derive(Clone, Debug, Serialize, TS)]
pub struct Course {
    pub name: String,
    pub title: String,
}

/// What someone is in a course.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, clap::ValueEnum, TS,
)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    Student,
    Assistant,
    Instructor,
}

impl Role {
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Student => "student",
            Role::Assistant => "assistant",
            Role::Instructor => "instructor",
        }
    }

    pub(super) fn parse(text: &str) -> Role {
        match text {
            "instructor" => Role::Instructor,
            "assistant" => Role::Assistant,
            _ => Role::Student,
        }
    }

    /// Assistants and instructors: they read everything in their course.
    pub fn is_staff(self) -> bool {
        self != Role::Student
    }
}

/// Someone in a course: a student of the roster (`login` is their id there) or a member
/// of staff (`login` is their email).
#[derive(Clone, Debug, Serialize, TS)]
pub struct Member {
    pub id: i64,
    pub course: String,
    pub login: String,
    pub name: String,
    pub email: String,
    pub role: Role,
    /// No longer on the roster: their submissions stay, they may not submit.
    pub dropped: bool,
}

/// Someone about to be added to a course.
pub struct NewMember<'a> {
    pub login: &'a str,
    pub name: &'a str,
    pub email: &'a str,
    pub role: Role,
}

/// What an import of the roster changed.
#[derive(Debug, Default)]
pub struct RosterChange {
    /// Students new to the course (they need a code).
    pub added: Vec<Member>,
    /// The ids of students whose name or email changed, or who were dropped and are back.
    pub updated: Vec<String>,
    pub unchanged: usize,
    /// Students on the course's roster but not in the file: marked dropped.
    pub dropped: Vec<String>,
}

/// An exercise opened for a course.
#[derive(Clone, Debug, Serialize, TS)]
pub struct Assignment {
    pub course: String,
    pub lab: Exercise,
    #[serde(flatten)]
    pub policy: Policy,
    /// Whether its students see their rank in the class challenge (an exercise with
    /// one); on unless staff switch it off.
    pub ranked: bool,
    /// The languages its files may be written in: every one unless staff restrict them.
    pub languages: Vec<Language>,
}

const MEMBER_COLUMNS: &str = "id, course, login, name, email, role, dropped";

fn member(row: &Row) -> db::Result<Member> {
    Ok(Member {
        id: row.get(0)?,
        course: row.get(1)?,
        login: row.get(2)?,
        name: row.get(3)?,
        email: row.get(4)?,
        role: Role::parse(&row.get::<_, String>(5)?),
        dropped: row.get(6)?,
    })
}
fn assignment(row: &Row) -> db::Result<Assignment> {
    Ok(Assignment {
        course: row.get(0)?,
        lab: exercise(row, 1)?,
        policy: Policy {
            due: timestamp(row.get(2)?),
            cutoff: timestamp(row.get(3)?),
            penalty_per_day: row.get(4)?,
            counts: Counts::parse(&row.get::<_, String>(5)?),
        },
        ranked: row.get(6)?,
        languages: languages(row.get(7)?),
    })
}

const ASSIGNMENT_COLUMNS: &str =
    "course, lab, due, cutoff, late_penalty, counts, ranked, languages";

/// The languages stored as names (every one when none are): a name this release does
/// not know is left out.
fn languages(stored: Option<String>) -> Vec<Language> {
    match stored {
        None => Language::ALL.to_vec(),
        Some(names) => names
            .split(',')
            .filter_map(|name| name.parse().ok())
            .collect(),
    }
}

/// The dates in force for one student, from the columns `a.due, a.cutoff, a.late_penalty,
/// a.counts, e.due, e.cutoff` from `first` on (an assignment and, left-joined, the
/// student's extension): the assignment's policy with the extension's dates when there
/// is one; `None` when no assignment was joined.
pub(super) fn policy_in_force(row: &Row, first: usize) -> db::Result<Option<Policy>> {
    let Some(due) = row.get::<_, Option<i64>>(first)? else {
        return Ok(None);
    };
    let policy = Policy {
        due: timestamp(due),
        cutoff: timestamp(row.get(first + 1)?),
        penalty_per_day: row.get(first + 2)?,
        counts: Counts::parse(&row.get::<_, String>(first + 3)?),
    };
    let extended: (Option<i64>, Option<i64>) = (row.get(first + 4)?, row.get(first + 5)?);
    Ok(Some(match extended {
        (Some(due), Some(cutoff)) => Policy {
            due: timestamp(due),
            cutoff: timestamp(cutoff),
            ..policy
        },
        _ => policy,
    }))
}

fn find_member(connection: &Connection, course: &str, login: &str) -> db::Result<Option<Member>> {
    connection
        .query_row(
            &format!("SELECT {MEMBER_COLUMNS} FROM members WHERE course = ?1 AND login = ?2"),
            params![course, login],
            member,
        )
        .optional()
}

/// The setting that keeps the fingerprint of the server's secret.
const SECRET_FINGERPRINT: &str = "secret_fingerprint";

impl Store {
    /// Whether any course is set up: until one is, the server is open to anyone.
    pub fn any_course(&self) -> Result<bool, Error> {
        Ok(self
            .connection()
            .query_row("SELECT EXISTS (SELECT 1 FROM courses)", (), |row| {
                row.get(0)
            })?)
    }

    /// Creates a course, or gives an existing one a new title; true when it is new.
    pub fn create_course(&self, name: &str, title: &str, now: Timestamp) -> Result<bool, Error> {
        self.transaction(|connection| {
            let updated = connection.execute(
                "UPDATE courses SET title = ?2 WHERE name = ?1",
                params![name, title],
            )?;
            if updated == 0 {
                connection.execute(
                    "INSERT INTO courses (name, title, created_at) VALUES (?1, ?2, ?3)",
                    params![name, title, now.as_second()],
                )?;
            }
            Ok(updated == 0)
        })
    }

    pub fn courses(&self) -> Result<Vec<Course>, Error> {
        let connection = self.connection();
        let courses =
            connection.query_map("SELECT name, title FROM courses ORDER BY name", (), |row| {
                Ok(Course {
                    name: row.get(0)?,
                    title: row.get(1)?,
                })
            })?;
        Ok(courses)
    }

    /// The course of that name, or an error listing those there are.
    pub fn course(&self, name: &str) -> Result<Course, Error> {
        let courses = self.courses()?;
        let known = courses.iter().map(|c| c.name.clone()).collect();
        courses
            .into_iter()
            .find(|c| c.name == name)
            .ok_or_else(|| Error::UnknownCourse {
                name: name.to_string(),
                known,
            })
    }

    /// Adds someone to a course, or updates their name, email and role; staff are never
    /// marked dropped. Refuses to turn a student into staff or back: their submissions
    /// would change hands.
    pub fn add_member(&self, course: &str, new: &NewMember) -> Result<Member, Error> {
        self.transaction(|connection| {
            if let Some(existing) = find_member(connection, course, new.login)? {
                if existing.role.is_staff() != new.role.is_staff() {
                    return Err(Error::Conflict(format!(
                        "{:?} is already a {} of {course}; staff and students need different ids",
                        new.login,
                        existing.role.as_str()
                    )));
                }
                connection.execute(
                    "UPDATE members SET name = ?2, email = ?3, role = ?4, dropped = 0
                     WHERE id = ?1",
                    params![existing.id, new.name, new.email, new.role.as_str()],
                )?;
            } else {
                connection.execute(
                    "INSERT INTO members (course, login, name, email, role)
                     VALUES (?1, ?2, ?3, ?4, ?5)",
                    params![course, new.login, new.name, new.email, new.role.as_str()],
                )?;
            }
            Ok(find_member(connection, course, new.login)?.expect("just written"))
        })
    }

    /// Imports a roster in one transaction: new students are added, known ones updated
    /// (and back if they had been dropped), those missing from the file marked dropped.
    /// Nobody and no submission is deleted.
    pub fn import_roster(
        &self,
        course: &str,
        students: &[roster::Student],
    ) -> Result<RosterChange, Error> {
        self.roster_change(course, students, true)
    }

    /// What `import_roster` would change, changing nothing.
    pub fn preview_roster(
        &self,
        course: &str,
        students: &[roster::Student],
    ) -> Result<RosterChange, Error> {
        self.roster_change(course, students, false)
    }

    /// Imports a roster in a transaction, committed when `apply`, rolled back otherwise.
    fn roster_change(
        &self,
        course: &str,
        students: &[roster::Student],
        apply: bool,
    ) -> Result<RosterChange, Error> {
        self.transaction_then(apply, |transaction| {
            let mut change = RosterChange::default();
            for student in students {
                match find_member(transaction, course, &student.id)? {
                    Some(existing) if existing.role.is_staff() => {
                        return Err(Error::Conflict(format!(
                            "the roster's id {:?} is a {} of {course}; \
                             staff and students need different ids",
                            student.id,
                            existing.role.as_str()
                        )));
                    }
                    Some(existing) => {
                        if existing.name == student.name
                            && existing.email == student.email
                            && !existing.dropped
                        {
                            change.unchanged += 1;
                        } else {
                            transaction.execute(
                                "UPDATE members SET name = ?2, email = ?3, dropped = 0
                                 WHERE id = ?1",
                                params![existing.id, student.name, student.email],
                            )?;
                            change.updated.push(existing.login);
                        }
                    }
                    None => {
                        transaction.execute(
                            "INSERT INTO members (course, login, name, email, role)
                             VALUES (?1, ?2, ?3, ?4, 'student')",
                            params![course, student.id, student.name, student.email],
                        )?;
                        change.added.push(
                            find_member(transaction, course, &student.id)?.expect("just written"),
                        );
                    }
                }
            }
            let listed: std::collections::HashSet<&str> =
                students.iter().map(|s| s.id.as_str()).collect();
            let current: Vec<(i64, String)> = {
                transaction.query_map(
                    "SELECT id, login FROM members
                     WHERE course = ?1 AND role = 'student' AND dropped = 0",
                    params![course],
                    |row| Ok((row.get(0)?, row.get(1)?)),
                )?
            };
            for (id, login) in current {
                if !listed.contains(login.as_str()) {
                    transaction
                        .execute("UPDATE members SET dropped = 1 WHERE id = ?1", params![id])?;
                    change.dropped.push(login);
                }
            }
            Ok(change)
        })
    }

    /// Everyone in a course: staff first, then students by id.
    pub fn members(&self, course: &str) -> Result<Vec<Member>, Error> {
        let connection = self.connection();
        let members = connection.query_map(
            &format!(
                "SELECT {MEMBER_COLUMNS} FROM members WHERE course = ?1
             ORDER BY role = 'student', login"
            ),
            params![course],
            member,
        )?;
        Ok(members)
    }

    /// Someone in a course by their id (students) or email (staff).
    pub fn member(&self, course: &str, login: &str) -> Result<Member, Error> {
        find_member(&self.connection(), course, login)?.ok_or_else(|| Error::UnknownMember {
            course: course.to_string(),
            login: login.to_string(),
        })
    }

    /// The student `login` of `course`; none for nobody of that login, and for staff.
    pub fn student(&self, course: &str, login: &str) -> Result<Option<Member>, Error> {
        let member = find_member(&self.connection(), course, login)?;
        Ok(member.filter(|m| m.role == Role::Student))
    }

    pub(super) fn member_by_id(connection: &Connection, id: i64) -> db::Result<Member> {
        connection.query_row(
            &format!("SELECT {MEMBER_COLUMNS} FROM members WHERE id = ?1"),
            [id],
            member,
        )
    }

    /// Opens an exercise for a course, or changes its dates and policy.
    pub fn assign(&self, course: &str, lab: Exercise, policy: &Policy) -> Result<(), Error> {
        self.connection().execute(
            "INSERT INTO assignments (course, lab, due, cutoff, late_penalty, counts)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6)
             ON CONFLICT (course, lab) DO UPDATE SET due = ?3, cutoff = ?4, late_penalty = ?5, counts = ?6",
            params![
                course,
                lab.name(),
                policy.due.as_second(),
                policy.cutoff.as_second(),
                policy.penalty_per_day,
                policy.counts.as_str()
            ],
        )?;
        Ok(())
    }

    /// Shows an assignment's students their rank in the class challenge, or stops; false
    /// when the course has not opened the exercise.
    pub fn set_ranked(&self, course: &str, lab: Exercise, ranked: bool) -> Result<bool, Error> {
        let changed = self.connection().execute(
            "UPDATE assignments SET ranked = ?3 WHERE course = ?1 AND lab = ?2",
            params![course, lab.name(), ranked],
        )?;
        Ok(changed == 1)
    }

    /// Restricts an assignment to `languages` (every one of them: no restriction); false
    /// when the course has not opened the exercise.
    pub fn set_languages(
        &self,
        course: &str,
        lab: Exercise,
        languages: &[Language],
    ) -> Result<bool, Error> {
        let every = Language::ALL.iter().all(|l| languages.contains(l));
        let stored = (!every).then(|| {
            let names: Vec<&str> = languages.iter().map(|l| l.name()).collect();
            names.join(",")
        });
        let changed = self.connection().execute(
            "UPDATE assignments SET languages = ?3 WHERE course = ?1 AND lab = ?2",
            params![course, lab.name(), stored],
        )?;
        Ok(changed == 1)
    }

    /// A course's assignments of the exercises this release grades (a database of a later
    /// release may hold others, which are left out), by due date.
    pub fn assignments(&self, course: &str) -> Result<Vec<Assignment>, Error> {
        let connection = self.connection();
        let assignments = connection.query_map(
            &format!(
                "SELECT {ASSIGNMENT_COLUMNS} FROM assignments
             WHERE course = ?1 AND lab IN (SELECT value FROM json_each(?2)) ORDER BY due, lab"
            ),
            params![course, known_exercises()],
            assignment,
        )?;
        Ok(assignments)
    }

    pub fn assignment(&self, course: &str, lab: Exercise) -> Result<Option<Assignment>, Error> {
        Ok(self
            .connection()
            .query_row(
                &format!(
                    "SELECT {ASSIGNMENT_COLUMNS} FROM assignments WHERE course = ?1 AND lab = ?2"
                ),
                params![course, lab.name()],
                assignment,
            )
            .optional()?)
    }

    /// A setting the server keeps for the command line (the address it is reached at).
    pub fn setting(&self, key: &str) -> Result<Option<String>, Error> {
        Ok(self
            .connection()
            .query_row(
                "SELECT value FROM settings WHERE key = ?1",
                params![key],
                |row| row.get(0),
            )
            .optional()?)
    }

    /// Records the fingerprint of the secret the hidden cases are drawn from, at the first
    /// start over this database; refuses another, which would grade every submission on
    /// other hidden cases (a process started with another data directory's secret, or a
    /// database restored beside the wrong one), unless it is taken as `new` (a secret
    /// replaced on purpose): then the fingerprint it replaced.
    pub fn check_secret(&self, fingerprint: &str, new: bool) -> Result<Option<String>, Error> {
        self.transaction(|connection| {
            let kept: Option<String> = connection
                .query_row(
                    "SELECT value FROM settings WHERE key = ?1",
                    params![SECRET_FINGERPRINT],
                    |row| row.get(0),
                )
                .optional()?;
            match kept {
                None => {
                    connection.execute(
                        "INSERT INTO settings (key, value) VALUES (?1, ?2)",
                        params![SECRET_FINGERPRINT, fingerprint],
                    )?;
                    Ok(None)
                }
                Some(kept) if kept == fingerprint => Ok(None),
                Some(kept) if new => {
                    connection.execute(
                        "UPDATE settings SET value = ?2 WHERE key = ?1",
                        params![SECRET_FINGERPRINT, fingerprint],
                    )?;
                    Ok(Some(kept))
                }
                Some(kept) => Err(Error::Conflict(format!(
                    "the data directory's secret (fingerprint {fingerprint}) is not the one this \
                     database's submissions are graded with (fingerprint {kept}): every estlab \
                     process over one database needs the same secret; copy the file `secret` of \
                     the data directory the database began with, or, to replace the secret on \
                     purpose, start once with --new-secret (a regrade then draws other hidden \
                     cases)"
                ))),
            }
        })
    }

    pub fn set_setting(&self, key: &str, value: &str) -> Result<(), Error> {
        self.connection().execute(
            "INSERT INTO settings (key, value) VALUES (?1, ?2)
             ON CONFLICT (key) DO UPDATE SET value = ?2",
            params![key, value],
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first process over a database records its secret's fingerprint; the same is
    /// taken again, another refused, naming both, unless it replaces the first on purpose.
    #[test]
    fn a_database_keeps_to_the_secret_it_began_with() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        assert_eq!(store.check_secret("00aa", false).unwrap(), None);
        assert_eq!(store.check_secret("00aa", false).unwrap(), None);
        let refused = store.check_secret("11bb", false).unwrap_err();
        assert!(matches!(refused, Error::Conflict(_)));
        let message = refused.to_string();
        assert!(
            message.contains("11bb") && message.contains("00aa") && message.contains("secret"),
            "{message}"
        );
        assert_eq!(store.check_secret("00aa", false).unwrap(), None);
        // Replaced on purpose: taken, and kept from then on.
        assert_eq!(
            store.check_secret("11bb", true).unwrap().as_deref(),
            Some("00aa")
        );
        assert_eq!(store.check_secret("11bb", false).unwrap(), None);
        assert!(store.check_secret("00aa", false).is_err());
    }
}
