//! What staff do to a course besides reading it: extensions for one student, and the
//! audit log of every staff action (regrades, extensions, roster and set-up changes).

use super::timestamp;
use super::{Error, Store};
use crate::courses::deadline::Policy;
use jiff::Timestamp;
use rusqlite::{OptionalExtension, params};
use serde::Serialize;

/// New dates for one student's assignment, and who granted them.
#[derive(Debug, Serialize)]
pub struct Extension {
    pub lab: String,
    pub student: String,
    pub due: Timestamp,
    pub cutoff: Timestamp,
    pub granted_by: String,
    pub granted_at: Timestamp,
}

/// An extension about to be granted.
#[derive(Clone, Copy)]
pub struct NewExtension<'a> {
    pub lab: &'a str,
    pub student: &'a str,
    pub due: Timestamp,
    pub cutoff: Timestamp,
}

/// One staff action.
#[derive(Debug, Serialize)]
pub struct AuditEntry {
    pub id: i64,
    pub at: Timestamp,
    pub actor: String,
    pub action: String,
    pub detail: String,
}
impl Store {
    /// Records a staff action in the course's audit log.
    pub fn audit(
        &self,
        course: &str,
        actor: &str,
        action: &str,
        detail: &str,
        now: Timestamp,
    ) -> Result<(), Error> {
        self.connection().execute(
            "INSERT INTO audit (course, at, actor, action, detail) VALUES (?1, ?2, ?3, ?4, ?5)",
            params![course, now.as_second(), actor, action, detail],
        )?;
        Ok(())
    }

    /// A course's audit log, newest first.
    pub fn audit_log(&self, course: &str) -> Result<Vec<AuditEntry>, Error> {
        let connection = self.connection();
        let mut statement = connection.prepare(
            "SELECT id, at, actor, action, detail FROM audit WHERE course = ?1 ORDER BY id DESC",
        )?;
        let entries = statement
            .query_map([course], |row| {
                Ok(AuditEntry {
                    id: row.get(0)?,
                    at: timestamp(row.get(1)?),
                    actor: row.get(2)?,
                    action: row.get(3)?,
                    detail: row.get(4)?,
                })
            })?
            .collect::<Result<_, _>>()?;
        Ok(entries)
    }

    /// Gives one student of a course new dates for an exercise (replacing an earlier
    /// extension), and logs it.
    pub fn grant_extension(
        &self,
        course: &str,
        grant: &NewExtension,
        granted_by: &str,
        now: Timestamp,
    ) -> Result<Extension, Error> {
        let NewExtension {
            lab,
            student,
            due,
            cutoff,
        } = *grant;
        let member = self.member(course, student)?;
        if member.role.is_staff() {
            return Err(Error::Conflict(format!(
                "{student} is {} of {course}: extensions are for students",
                member.role.as_str()
            )));
        }
        if self.assignment(course, lab)?.is_none() {
            return Err(Error::Conflict(format!(
                "{course} has not opened {lab}: there is no deadline to extend"
            )));
        }
        self.connection().execute(
            "INSERT INTO extensions (course, lab, member, due, cutoff, granted_by, granted_at)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)
             ON CONFLICT (course, lab, member) DO UPDATE SET due = ?4, cutoff = ?5,
                 granted_by = ?6, granted_at = ?7",
            params![
                course,
                lab,
                member.id,
                due.as_second(),
                cutoff.as_second(),
                granted_by,
                now.as_second()
            ],
        )?;
        self.audit(
            course,
            granted_by,
            "extension",
            &format!("{student}, {lab}: due {due}, cutoff {cutoff}"),
            now,
        )?;
        Ok(Extension {
            lab: lab.to_string(),
            student: student.to_string(),
            due,
            cutoff,
            granted_by: granted_by.to_string(),
            granted_at: now,
        })
    }

    /// The extensions of a course's exercise.
    pub fn extensions(&self, course: &str, lab: &str) -> Result<Vec<Extension>, Error> {
        let connection = self.connection();
        let mut statement = connection.prepare(
            "SELECT e.lab, m.login, e.due, e.cutoff, e.granted_by, e.granted_at
             FROM extensions e JOIN members m ON m.id = e.member
             WHERE e.course = ?1 AND e.lab = ?2 ORDER BY m.login",
        )?;
        let extensions = statement
            .query_map(params![course, lab], |row| {
                Ok(Extension {
                    lab: row.get(0)?,
                    student: row.get(1)?,
                    due: timestamp(row.get(2)?),
                    cutoff: timestamp(row.get(3)?),
                    granted_by: row.get(4)?,
                    granted_at: timestamp(row.get(5)?),
                })
            })?
            .collect::<Result<_, _>>()?;
        Ok(extensions)
    }

    /// The dates that hold for one member: the assignment's, or their extension's.
    pub fn policy_for(
        &self,
        course: &str,
        lab: &str,
        member: i64,
    ) -> Result<Option<Policy>, Error> {
        let Some(assignment) = self.assignment(course, lab)? else {
            return Ok(None);
        };
        let extended: Option<(i64, i64)> = self
            .connection()
            .query_row(
                "SELECT due, cutoff FROM extensions WHERE course = ?1 AND lab = ?2 AND member = ?3",
                params![course, lab, member],
                |row| Ok((row.get(0)?, row.get(1)?)),
            )
            .optional()?;
        Ok(Some(match extended {
            Some((due, cutoff)) => Policy {
                due: timestamp(due),
                cutoff: timestamp(cutoff),
                ..assignment.policy
            },
            None => assignment.policy,
        }))
    }
}
