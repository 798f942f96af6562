//! What staff do to a course besides reading it: extensions for one student, waivers of
//! one submission's late penalty, and the audit log of every staff action (regrades,
//! extensions, waivers, roster and set-up changes). Both extensions and waivers change
//! what submissions already made count: each lists the scores it changed.

use super::courses::policy_in_force;
use super::db::{self, OptionalExtension, Row, params};
use super::submissions::SubmissionSummary;
use super::timestamp;
use super::{Error, Store, exercise};
use crate::courses::deadline::Policy;
use jiff::Timestamp;
use labs::Exercise;
use serde::Serialize;
use ts_rs::TS;

/// New dates for one student's assignment, and who granted them.
#[derive(Debug, Serialize, TS)]
pub struct Extension {
    pub lab: Exercise,
    pub student: String,
    #[ts(as = "String")]
    pub due: Timestamp,
    #[ts(as = "String")]
    pub cutoff: Timestamp,
    pub granted_by: String,
    #[ts(as = "String")]
    pub granted_at: Timestamp,
}

/// An extension about to be granted.
#[derive(Clone, Copy)]
pub struct NewExtension<'a> {
    pub lab: Exercise,
    pub student: &'a str,
    pub due: Timestamp,
    pub cutoff: Timestamp,
}

/// Staff's waiver of one submission's late penalty, and why.
#[derive(Clone, Debug, PartialEq, Serialize, TS)]
pub struct Waiver {
    pub reason: String,
    pub waived_by: String,
    #[ts(as = "String")]
    pub waived_at: Timestamp,
}

/// A waiver from the columns `reason, waived_by, waived_at` from `first` on (left-joined:
/// all null for a submission without one).
pub(super) fn waiver_at(row: &Row, first: usize) -> db::Result<Option<Waiver>> {
    let Some(reason) = row.get::<_, Option<String>>(first)? else {
        return Ok(None);
    };
    Ok(Some(Waiver {
        reason,
        waived_by: row.get(first + 1)?,
        waived_at: timestamp(row.get(first + 2)?),
    }))
}

/// A submission whose late penalty an extension or a waiver changed, before and after
/// (the final scores: the score after the penalty; none while it is not graded).
#[derive(Debug, PartialEq, Serialize, TS)]
pub struct Rejudged {
    pub submission: i64,
    pub student: String,
    pub old_penalty: f64,
    pub new_penalty: f64,
    pub old_final: Option<f64>,
    pub new_final: Option<f64>,
}

/// Penalties within this are the same penalty.
const SAME: f64 = 1e-9;

/// The submissions whose penalty differs between two readings of the same submissions,
/// both finals taken with the later reading's score (a grading that ended between the two
/// is not the change's doing).
fn rejudged(before: &[SubmissionSummary], after: &[SubmissionSummary]) -> Vec<Rejudged> {
    after
        .iter()
        .filter_map(|now| {
            let then = before.iter().find(|s| s.id == now.id)?;
            ((then.penalty - now.penalty).abs() > SAME).then(|| Rejudged {
                submission: now.id,
                student: now.student.clone(),
                old_penalty: then.penalty,
                new_penalty: now.penalty,
                old_final: now.score.map(|s| s * (1.0 - then.penalty)),
                new_final: now.final_score,
            })
        })
        .collect()
}

/// The changes in words, for the audit log.
fn describe(changed: &[Rejudged]) -> String {
    if changed.is_empty() {
        return "no score changed".into();
    }
    let percent = |share: f64| format!("{:.0} %", share * 100.0);
    let each: Vec<String> = changed
        .iter()
        .map(|c| match (c.old_final, c.new_final) {
            (Some(old), Some(new)) => {
                format!(
                    "submission {} {} → {}",
                    c.submission,
                    percent(old),
                    percent(new)
                )
            }
            _ => format!(
                "submission {} penalty {} → {}",
                c.submission,
                percent(c.old_penalty),
                percent(c.new_penalty)
            ),
        })
        .collect();
    format!("re-judged {}", each.join(", "))
}

/// An extension granted, with the scores of the submissions already made it changed.
#[derive(Debug, Serialize, TS)]
pub struct Granted {
    #[serde(flatten)]
    pub extension: Extension,
    pub changed: Vec<Rejudged>,
}

/// A penalty waived: the submission as it counts now, and the score it changed (none
/// when it had no penalty).
#[derive(Debug, Serialize, TS)]
pub struct Waived {
    pub submission: SubmissionSummary,
    pub changed: Vec<Rejudged>,
}

/// A waiver about to be made.
#[derive(Clone, Copy)]
pub struct NewWaiver<'a> {
    pub submission: i64,
    pub reason: &'a str,
}

fn extension(row: &Row) -> db::Result<Extension> {
    Ok(Extension {
        lab: exercise(row, 0)?,
        student: row.get(1)?,
        due: timestamp(row.get(2)?),
        cutoff: timestamp(row.get(3)?),
        granted_by: row.get(4)?,
        granted_at: timestamp(row.get(5)?),
    })
}

const EXTENSION_COLUMNS: &str = "e.lab, m.login, e.due, e.cutoff, e.granted_by, e.granted_at";

/// One staff action.
#[derive(Debug, Serialize, TS)]
pub struct AuditEntry {
    pub id: i64,
    #[ts(as = "String")]
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
        let entries = connection.query_map(
            "SELECT id, at, actor, action, detail FROM audit WHERE course = ?1 ORDER BY id DESC",
            params![course],
            |row| {
                Ok(AuditEntry {
                    id: row.get(0)?,
                    at: timestamp(row.get(1)?),
                    actor: row.get(2)?,
                    action: row.get(3)?,
                    detail: row.get(4)?,
                })
            },
        )?;
        Ok(entries)
    }

    /// Gives one student of a course new dates for an exercise (replacing an earlier
    /// extension), and logs it with the scores it changed: their submissions already made
    /// are judged against the new dates (up or down: the list says which).
    pub fn grant_extension(
        &self,
        course: &str,
        grant: &NewExtension,
        granted_by: &str,
        now: Timestamp,
    ) -> Result<Granted, Error> {
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
        let before = self.history(member.id, lab)?;
        self.connection().execute(
            "INSERT INTO extensions (course, lab, member, due, cutoff, granted_by, granted_at)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)
             ON CONFLICT (course, lab, member) DO UPDATE SET due = ?4, cutoff = ?5,
                 granted_by = ?6, granted_at = ?7",
            params![
                course,
                lab.name(),
                member.id,
                due.as_second(),
                cutoff.as_second(),
                granted_by,
                now.as_second()
            ],
        )?;
        let changed = rejudged(&before, &self.history(member.id, lab)?);
        self.audit(
            course,
            granted_by,
            "extension",
            &format!(
                "{student}, {lab}: due {due}, cutoff {cutoff}; {}",
                describe(&changed)
            ),
            now,
        )?;
        Ok(Granted {
            extension: Extension {
                lab,
                student: student.to_string(),
                due,
                cutoff,
                granted_by: granted_by.to_string(),
                granted_at: now,
            },
            changed,
        })
    }

    /// Waives the late penalty of one submission of a course's student (a new reason
    /// replaces an earlier one), and logs it with the score it changed; `None` when the
    /// course has no such submission.
    pub fn waive(
        &self,
        course: &str,
        waiver: &NewWaiver,
        waived_by: &str,
        now: Timestamp,
    ) -> Result<Option<Waived>, Error> {
        let NewWaiver { submission, reason } = *waiver;
        match self.owner(submission)? {
            Some((owner, Some(_))) if owner == course => {}
            _ => return Ok(None),
        }
        let Some(before) = self.get(submission, false)? else {
            return Ok(None);
        };
        self.connection().execute(
            "INSERT INTO waivers (submission, reason, waived_by, waived_at) VALUES (?1, ?2, ?3, ?4)
             ON CONFLICT (submission) DO UPDATE SET reason = ?2, waived_by = ?3, waived_at = ?4",
            params![submission, reason, waived_by, now.as_second()],
        )?;
        let after = self
            .get(submission, false)?
            .expect("a submission is never deleted")
            .summary;
        let changed = rejudged(&[before.summary], std::slice::from_ref(&after));
        self.audit(
            course,
            waived_by,
            "waiver",
            &format!(
                "{}, {}: late penalty of submission {submission} waived ({}): {reason}",
                after.student,
                after.lab,
                describe(&changed)
            ),
            now,
        )?;
        Ok(Some(Waived {
            submission: after,
            changed,
        }))
    }

    /// The extensions of a course's exercise.
    pub fn extensions(&self, course: &str, lab: Exercise) -> Result<Vec<Extension>, Error> {
        let connection = self.connection();
        let extensions = connection.query_map(
            &format!(
                "SELECT {EXTENSION_COLUMNS} FROM extensions e JOIN members m ON m.id = e.member
             WHERE e.course = ?1 AND e.lab = ?2 ORDER BY m.login"
            ),
            params![course, lab.name()],
            extension,
        )?;
        Ok(extensions)
    }

    /// One student's extension of a course's exercise, if they have one.
    pub fn extension_for(
        &self,
        course: &str,
        lab: Exercise,
        member: i64,
    ) -> Result<Option<Extension>, Error> {
        Ok(self
            .connection()
            .query_row(
                &format!(
                    "SELECT {EXTENSION_COLUMNS} FROM extensions e JOIN members m ON m.id = e.member
                     WHERE e.course = ?1 AND e.lab = ?2 AND e.member = ?3"
                ),
                params![course, lab.name(), member],
                extension,
            )
            .optional()?)
    }

    /// The dates that hold for one member: the assignment's, or their extension's.
    /// Submitting and judging the submissions already made both go by them.
    pub fn policy_for(
        &self,
        course: &str,
        lab: Exercise,
        member: i64,
    ) -> Result<Option<Policy>, Error> {
        let policy = self
            .connection()
            .query_row(
                "SELECT a.due, a.cutoff, a.late_penalty, a.counts, e.due, e.cutoff
                 FROM assignments a LEFT JOIN extensions e
                     ON e.course = a.course AND e.lab = a.lab AND e.member = ?3
                 WHERE a.course = ?1 AND a.lab = ?2",
                params![course, lab.name(), member],
                |row| policy_in_force(row, 0),
            )
            .optional()?;
        Ok(policy.flatten())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::Status;

    fn summary(id: i64, score: Option<f64>, penalty: f64) -> SubmissionSummary {
        SubmissionSummary {
            id,
            course: "el2320".into(),
            student: "s1".into(),
            lab: Exercise::EkfLocalization,
            language: labs::Language::JavaScript,
            status: Status::Graded,
            submitted_at: "2026-12-15T23:00:00.000Z".into(),
            late_seconds: 18,
            penalty,
            score,
            final_score: score.map(|s| s * (1.0 - penalty)),
            waiver: None,
            challenge: None,
            challenge_spread: None,
        }
    }

    #[test]
    fn only_the_submissions_whose_penalty_changed_are_listed_and_described() {
        let before = [
            summary(1, Some(1.0), 0.1),
            summary(2, Some(0.5), 0.0),
            summary(3, None, 0.2),
        ];
        let after = [
            summary(1, Some(1.0), 0.0),
            summary(2, Some(0.5), 0.0),
            summary(3, None, 0.0),
        ];
        let changed = rejudged(&before, &after);
        assert_eq!(
            changed.iter().map(|c| c.submission).collect::<Vec<_>>(),
            [1, 3]
        );
        assert_eq!(changed[0].old_final, Some(0.9));
        assert_eq!(changed[0].new_final, Some(1.0));
        assert_eq!(
            describe(&changed),
            "re-judged submission 1 90 % → 100 %, submission 3 penalty 20 % → 0 %"
        );
        assert_eq!(describe(&[]), "no score changed");
    }
}
