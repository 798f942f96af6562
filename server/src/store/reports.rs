//! The students' reports: their analyses, their hand-ins and staff's rubric of each
//! (`courses::report` says what they mean), and the runs of a submission's report, kept
//! once made, and being made: one student's at a time, under the lease of the web process
//! making them (`leases`).

use super::SavedAnswer;
use super::db::{Connection, OptionalExtension, params};
use super::leases::{Holder, Lease, millis};
use super::{Error, Store, timestamp};
use crate::courses::report::{PartMark, State, Stored};
use jiff::Timestamp;
use labs::Exercise;
use labs::grading::Outputs;
use serde_json::value::RawValue;

/// Why a change of a report was refused: it is handed in and not sent back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Closed(pub State);

impl Store {
    /// A student's report of an exercise, as stored; none before they wrote anything.
    pub fn report(&self, member: i64, lab: Exercise) -> Result<Option<Stored>, Error> {
        read_report(&self.connection(), member, lab)
    }

    /// Keeps `text` as the student's analysis of `run`, unless the report is handed in and
    /// not sent back for revision (judged under the same lock as the write).
    pub fn save_analysis(
        &self,
        member: i64,
        lab: Exercise,
        run: &str,
        text: &str,
        now: Timestamp,
    ) -> Result<Result<(), Closed>, Error> {
        self.transaction(|transaction| {
            let mut report = read_report(transaction, member, lab)?.unwrap_or_default();
            if !report.state().open_to_student() {
                return Ok(Err(Closed(report.state())));
            }
            report.analyses.insert(run.to_owned(), text.to_owned());
            let analyses = serde_json::to_string(&report.analyses).expect("texts serialise");
            transaction.execute(
                "INSERT INTO reports (member, lab, analyses, saved_at) VALUES (?1, ?2, ?3, ?4)
                 ON CONFLICT (member, lab) DO UPDATE SET analyses = ?3, saved_at = ?4",
                params![member, lab.name(), analyses, now.as_second()],
            )?;
            Ok(Ok(()))
        })
    }

    /// Hands the report in with the runs of `submission` and the student's `answers` as
    /// they stand, keeping its analyses as they are, unless it is handed in already and
    /// not sent back; the new state.
    pub fn hand_in_report(
        &self,
        member: i64,
        lab: Exercise,
        (submission, answers): (i64, &[SavedAnswer]),
        now: Timestamp,
    ) -> Result<Result<Stored, Closed>, Error> {
        self.transaction(|transaction| {
            let report = read_report(transaction, member, lab)?.unwrap_or_default();
            if !report.state().open_to_student() {
                return Ok(Err(Closed(report.state())));
            }
            let analyses = serde_json::to_string(&report.analyses).expect("texts serialise");
            let answers = serde_json::to_string(answers).expect("answers serialise");
            transaction.execute(
                "INSERT INTO reports (member, lab, analyses, saved_at, handed_in, submission,
                                      handed_in_at, handed_analyses, handed_answers)
                 VALUES (?1, ?2, ?5, ?4, 1, ?3, ?4, ?5, ?6)
                 ON CONFLICT (member, lab) DO UPDATE
                 SET handed_in = reports.handed_in + 1, submission = ?3, handed_in_at = ?4,
                     handed_analyses = ?5, handed_answers = ?6",
                params![
                    member,
                    lab.name(),
                    submission,
                    now.as_second(),
                    analyses,
                    answers
                ],
            )?;
            let report = read_report(transaction, member, lab)?.expect("the report just written");
            Ok(Ok(report))
        })
    }

    /// Staff's rubric of the hand-in counted `handed_in` (the one they read); refused
    /// with the state when that is no longer the latest hand-in, or there is none.
    pub fn review_report(
        &self,
        member: i64,
        lab: Exercise,
        (handed_in, rubric): (u32, &[PartMark]),
        (by, now): (&str, Timestamp),
    ) -> Result<Result<Stored, Closed>, Error> {
        self.transaction(|transaction| {
            let report = read_report(transaction, member, lab)?.unwrap_or_default();
            if report.handed_in == 0 || report.handed_in != handed_in {
                return Ok(Err(Closed(report.state())));
            }
            transaction.execute(
                "UPDATE reports SET rubric = ?3, reviewed = ?4, reviewed_by = ?5, reviewed_at = ?6
                 WHERE member = ?1 AND lab = ?2",
                params![
                    member,
                    lab.name(),
                    serde_json::to_string(rubric).expect("marks serialise"),
                    handed_in,
                    by,
                    now.as_second()
                ],
            )?;
            let report = read_report(transaction, member, lab)?.expect("the report just written");
            Ok(Ok(report))
        })
    }

    /// The state of every report of a course's exercise that was written, by member.
    pub fn report_states(&self, course: &str, lab: Exercise) -> Result<Vec<(i64, State)>, Error> {
        let connection = self.connection();
        let members = connection.query_map(
            "SELECT r.member FROM reports r JOIN members m ON m.id = r.member
             WHERE m.course = ?1 AND r.lab = ?2 ORDER BY r.member",
            params![course, lab.name()],
            |row| row.get::<_, i64>(0),
        )?;
        members
            .into_iter()
            .map(|member| {
                let report = read_report(&connection, member, lab)?.unwrap_or_default();
                Ok((member, report.state()))
            })
            .collect()
    }

    /// The runs of a submission's report, if `grader` made them: the outputs' JSON as
    /// kept, to be sent as it is.
    pub fn report_runs(
        &self,
        submission: i64,
        grader: &str,
    ) -> Result<Option<Box<RawValue>>, Error> {
        let stored: Option<String> = self
            .connection()
            .query_row(
                "SELECT outputs FROM report_runs WHERE submission = ?1 AND grader = ?2",
                params![submission, grader],
                |row| row.get(0),
            )
            .optional()?;
        stored
            .map(|json| RawValue::from_string(json).map_err(Error::StoredResult))
            .transpose()
    }

    /// Keeps the runs `grader` made of a submission's report, in place of another
    /// grader's.
    pub fn keep_report_runs(
        &self,
        submission: i64,
        grader: &str,
        outputs: &Outputs,
    ) -> Result<(), Error> {
        let json = serde_json::to_string(outputs).expect("outputs serialise");
        self.connection().execute(
            "INSERT INTO report_runs (submission, grader, outputs) VALUES (?1, ?2, ?3)
             ON CONFLICT (submission) DO UPDATE SET grader = ?2, outputs = ?3",
            params![submission, grader, json],
        )?;
        Ok(())
    }
}

fn read_report(
    connection: &Connection,
    member: i64,
    lab: Exercise,
) -> Result<Option<Stored>, Error> {
    let row = connection
        .query_row(
            "SELECT analyses, handed_in, submission, handed_in_at, rubric, reviewed, reviewed_by,
                    reviewed_at, handed_analyses, handed_answers
             FROM reports WHERE member = ?1 AND lab = ?2",
            params![member, lab.name()],
            |row| {
                Ok((
                    row.get::<_, String>(0)?,
                    row.get::<_, u32>(1)?,
                    row.get::<_, Option<i64>>(2)?,
                    row.get::<_, Option<i64>>(3)?,
                    row.get::<_, Option<String>>(4)?,
                    row.get::<_, Option<u32>>(5)?,
                    row.get::<_, Option<String>>(6)?,
                    row.get::<_, Option<i64>>(7)?,
                    row.get::<_, Option<String>>(8)?,
                    row.get::<_, Option<String>>(9)?,
                ))
            },
        )
        .optional()?;
    let Some((analyses, handed_in, submission, handed_in_at, rubric, reviewed, by, at, ha, hs)) =
        row
    else {
        return Ok(None);
    };
    Ok(Some(Stored {
        analyses: serde_json::from_str(&analyses).map_err(Error::StoredAnswer)?,
        handed_in,
        submission,
        handed_in_at: handed_in_at.map(timestamp),
        handed_analyses: stored_json(ha)?,
        handed_answers: stored_json(hs)?,
        rubric: stored_json(rubric)?,
        reviewed,
        reviewed_by: by,
        reviewed_at: at.map(timestamp),
    }))
}

/// A JSON column read as `T`; its default when empty.
fn stored_json<T: serde::de::DeserializeOwned + Default>(json: Option<String>) -> Result<T, Error> {
    json.map(|json| serde_json::from_str(&json).map_err(Error::StoredAnswer))
        .transpose()
        .map(Option::unwrap_or_default)
}

/// Where the making of a student's report's runs stands, as a web process asks for them.
#[derive(Debug, PartialEq)]
pub enum ReportMaking {
    /// This process is to make them, under the lease it was given.
    Yours,
    /// Another process (or this one) is making a submission's runs of the student's.
    Running { submission: i64 },
    /// The last try at this submission's runs failed: the reason, told once (the next
    /// ask tries again).
    Failed(String),
}

impl Store {
    /// Begins the making of the runs of `member`'s report of `submission` under `lease`,
    /// unless a making of the student's runs is under way (one student's at a time) or
    /// the last try at these failed (told now, once).
    pub fn begin_report_making(
        &self,
        member: i64,
        submission: i64,
        lease: &Lease,
    ) -> Result<ReportMaking, Error> {
        self.transaction(|connection| {
            let row: Option<(i64, i64, Option<String>)> = connection
                .query_row(
                    "SELECT submission, lease_until, failed FROM report_makings WHERE member = ?1",
                    [member],
                    |row| Ok((row.get(0)?, row.get(1)?, row.get(2)?)),
                )
                .optional()?;
            match row {
                Some((of, _, Some(reason))) if of == submission => {
                    connection.execute("DELETE FROM report_makings WHERE member = ?1", [member])?;
                    return Ok(ReportMaking::Failed(reason));
                }
                Some((of, until, None)) if until >= millis(lease.from) => {
                    return Ok(ReportMaking::Running { submission: of });
                }
                _ => {}
            }
            connection.execute(
                "INSERT INTO report_makings (member, submission, leased_by, lease_until, failed)
                 VALUES (?1, ?2, ?3, ?4, NULL)
                 ON CONFLICT (member) DO UPDATE SET submission = excluded.submission,
                 leased_by = excluded.leased_by, lease_until = excluded.lease_until, failed = NULL",
                params![member, submission, lease.holder.as_str(), lease.until()],
            )?;
            Ok(ReportMaking::Yours)
        })
    }

    /// Renews the lease of a making of `member`'s runs; false when its holder lost it.
    pub fn renew_report_making(&self, member: i64, lease: &Lease) -> Result<bool, Error> {
        let renewed = self.connection().execute(
            "UPDATE report_makings SET lease_until = ?3
             WHERE member = ?1 AND leased_by = ?2 AND failed IS NULL",
            params![member, lease.holder.as_str(), lease.until()],
        )?;
        Ok(renewed == 1)
    }

    /// Ends `holder`'s making of `member`'s runs: done (the runs are kept), or failed
    /// for a reason to tell the student at their next ask.
    pub fn end_report_making(
        &self,
        member: i64,
        holder: &Holder,
        failed: Option<&str>,
    ) -> Result<(), Error> {
        let connection = self.connection();
        match failed {
            None => connection.execute(
                "DELETE FROM report_makings WHERE member = ?1 AND leased_by = ?2",
                params![member, holder.as_str()],
            )?,
            Some(reason) => connection.execute(
                "UPDATE report_makings SET failed = ?3, leased_by = NULL, lease_until = 0
                 WHERE member = ?1 AND leased_by = ?2",
                params![member, holder.as_str(), reason],
            )?,
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::test_store;

    fn holder(name: &str) -> Holder {
        Holder::named(name)
    }

    use crate::store::test_lease as lease;

    /// One making of a student's runs at a time, by whoever holds its lease; another
    /// process takes over a making whose lease ran out; a failure is told once, and only
    /// for the submission that failed.
    #[test]
    fn a_students_runs_are_made_by_one_process_at_a_time() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        store
            .create_course("el2320", "Applied Estimation", Timestamp::UNIX_EPOCH)
            .unwrap();
        let member = store
            .add_member(
                "el2320",
                &crate::store::NewMember {
                    login: "ada",
                    name: "Ada",
                    email: "ada@example.org",
                    role: crate::store::Role::Student,
                },
            )
            .unwrap()
            .id;
        let (web_a, web_b) = (holder("a/1/x"), holder("b/1/y"));
        let t0 = Timestamp::from_second(1_800_000_000).unwrap();
        let later = |seconds| t0 + jiff::SignedDuration::from_secs(seconds);
        assert_eq!(
            store
                .begin_report_making(member, 7, &lease(&web_a, t0))
                .unwrap(),
            ReportMaking::Yours
        );
        assert_eq!(
            store
                .begin_report_making(member, 8, &lease(&web_b, later(1)))
                .unwrap(),
            ReportMaking::Running { submission: 7 }
        );
        assert!(
            store
                .renew_report_making(member, &lease(&web_a, later(20)))
                .unwrap()
        );
        assert!(
            !store
                .renew_report_making(member, &lease(&web_b, later(20)))
                .unwrap()
        );
        // Web process a died: after its lease, b makes them.
        assert_eq!(
            store
                .begin_report_making(member, 7, &lease(&web_b, later(51)))
                .unwrap(),
            ReportMaking::Yours
        );
        store
            .end_report_making(member, &web_a, Some("not a's to end"))
            .unwrap();
        store
            .end_report_making(member, &web_b, Some("the sandbox failed"))
            .unwrap();
        // Told once, for that submission; then tried again.
        assert_eq!(
            store
                .begin_report_making(member, 7, &lease(&web_a, later(52)))
                .unwrap(),
            ReportMaking::Failed("the sandbox failed".into())
        );
        assert_eq!(
            store
                .begin_report_making(member, 7, &lease(&web_a, later(53)))
                .unwrap(),
            ReportMaking::Yours
        );
        store.end_report_making(member, &web_a, None).unwrap();
        assert_eq!(
            store
                .begin_report_making(member, 9, &lease(&web_b, later(54)))
                .unwrap(),
            ReportMaking::Yours
        );
    }
}
