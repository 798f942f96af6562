//! The submissions: each written before it is graded, its result written when grading
//! ends. A signed-in student's submission names them (`member`). How late it is and the
//! penalty that costs are judged whenever it is read, from its `submitted_at` and the
//! dates in force for its student (the assignment's, or their extension's), unless staff
//! waived the penalty; what was judged when it was taken is stored too, for the record.

use super::courses::policy_in_force;
use super::db::{self, OptionalExtension, Row, params};
use super::leases::Holder;
use super::staff::{Waiver, waiver_at};
use super::{Error, Store, exercise, named};
use crate::courses::deadline::Lateness;
use jiff::Timestamp;
use labs::grading::GradeResult;
use labs::{Exercise, Language};
use serde::Serialize;
use std::collections::HashMap;
use ts_rs::TS;

/// Where a submission is on its way to a result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, TS)]
#[serde(rename_all = "snake_case")]
#[ts(rename = "SubmissionStatus")]
pub enum Status {
    Queued,
    Grading,
    Graded,
}

impl Status {
    pub(super) fn as_str(self) -> &'static str {
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
    /// The signed-in student, on a server with courses.
    pub member: Option<i64>,
    pub lab: Exercise,
    pub seed: u64,
    pub language: Language,
    pub source: &'a str,
    pub submitted_at: Timestamp,
    /// After the due date by this much when taken (0: on time), for the record: what
    /// counts is judged from `submitted_at` by the dates in force when read.
    pub late_seconds: i64,
    /// The share of the score the lateness cost when taken, for the record too.
    pub penalty: f64,
    /// The grader the web process taking it grades with (`grading::grader_version`): a
    /// grader of another release leaves it to one of this.
    pub grader: &'a str,
}

/// What grading a submission needs (and names in the log).
pub struct ToGrade {
    pub exercise: Exercise,
    pub language: Language,
    pub source: String,
    pub seed: u64,
    pub course: String,
    pub student: String,
}

/// A submission waiting to be graded, and whose it is.
#[derive(Debug, PartialEq)]
pub struct Unfinished {
    pub id: i64,
    pub course: String,
    pub student: String,
}

/// A submission in a list: when, how late, how it did; no source, no result.
#[derive(Debug, Serialize, TS)]
pub struct SubmissionSummary {
    pub id: i64,
    pub course: String,
    pub student: String,
    pub lab: Exercise,
    /// The language of the file.
    pub language: Language,
    pub status: Status,
    pub submitted_at: String,
    /// After the student's due date in force by this much (0: on time).
    pub late_seconds: i64,
    /// The share of the score that costs (0 when waived).
    pub penalty: f64,
    /// The grader's score, once graded (none when not gradable).
    pub score: Option<f64>,
    /// The score after the late penalty: what counts.
    pub final_score: Option<f64>,
    /// The late penalty waived by staff, and why.
    pub waiver: Option<Waiver>,
    /// Its figure in the class challenge (lower the better), where the exercise has one
    /// and its run gave one.
    pub challenge: Option<f64>,
    /// How much that figure varies between the runs it is a mean of.
    pub challenge_spread: Option<f64>,
}

/// A stored submission with its result; its source only for those who may read it.
#[derive(Debug, Serialize, TS)]
pub struct Submission {
    #[serde(flatten)]
    pub summary: SubmissionSummary,
    pub seed: u64,
    pub graded_at: Option<String>,
    /// The grader that produced the result.
    pub grader: Option<String>,
    /// Results regrades replaced, oldest first (filled by whoever reads them).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub earlier: Vec<super::EarlierResult>,
    #[serde(skip)]
    pub member: Option<i64>,
    pub result: Option<GradeResult>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// While it waits: that no running grader grades its language, and so it waits for
    /// one (filled by whoever reads it).
    pub waiting_for: Option<String>,
}

/// The figure of a result's class challenge and its spread, as the submission keeps them.
pub(super) fn challenge_figure(result: &GradeResult) -> (Option<f64>, Option<f64>) {
    result
        .challenge
        .as_ref()
        .map_or((None, None), |c| (c.figure, c.spread))
}

/// How submission times are written: UTC to the millisecond, as estlab 0.1.0 wrote them.
pub(super) fn moment(at: Timestamp) -> String {
    at.strftime("%Y-%m-%dT%H:%M:%S%.3fZ").to_string()
}

/// A submission with what judges its lateness now: its assignment (a student's only: an
/// open server's submissions belong to no course's people), its student's extension and
/// its waiver.
pub(super) const SUMMARY_FROM: &str = "submissions s
    LEFT JOIN assignments a ON s.member IS NOT NULL AND a.course = s.course AND a.lab = s.lab
    LEFT JOIN extensions e ON e.course = s.course AND e.lab = s.lab AND e.member = s.member
    LEFT JOIN waivers w ON w.submission = s.id";

/// The columns of a summary (from `SUMMARY_FROM`), `SUMMARY_WIDTH` of them.
pub(super) const SUMMARY_COLUMNS: &str = "s.id, s.course, s.student, s.lab, s.status,
    s.submitted_at, s.late_seconds, s.penalty, s.score,
    a.due, a.cutoff, a.late_penalty, a.counts, e.due, e.cutoff,
    w.reason, w.waived_by, w.waived_at, s.challenge, s.language, s.challenge_spread";
pub(super) const SUMMARY_WIDTH: usize = 21;

pub(super) fn summary(row: &Row) -> db::Result<SubmissionSummary> {
    let score: Option<f64> = row.get(8)?;
    let submitted_at: String = row.get(5)?;
    let lateness = match (policy_in_force(row, 9)?, submitted_at.parse::<Timestamp>()) {
        (Some(policy), Ok(at)) => policy.lateness(at),
        // No assignment judges it (an open server's): as it was taken.
        _ => Lateness {
            seconds: row.get(6)?,
            penalty: row.get(7)?,
        },
    };
    let waiver = waiver_at(row, 15)?;
    let penalty = if waiver.is_some() {
        0.0
    } else {
        lateness.penalty
    };
    Ok(SubmissionSummary {
        id: row.get(0)?,
        course: row.get(1)?,
        student: row.get(2)?,
        lab: exercise(row, 3)?,
        status: Status::parse(&row.get::<_, String>(4)?),
        submitted_at,
        late_seconds: lateness.seconds,
        penalty,
        score,
        final_score: score.map(|s| s * (1.0 - penalty)),
        waiver,
        challenge: row.get(18)?,
        language: named(row, 19)?,
        challenge_spread: row.get(20)?,
    })
}

impl Store {
    /// Stores a new submission as queued and returns its id; refuses it when the student
    /// already has one waiting or being graded in the same course and exercise, in the
    /// same language or in one that a grader seen since `graders_since` grades (judged in
    /// the same transaction, so that two web processes cannot both take one). A file in a
    /// language no running grader grades waits for one, and holds back no file in another.
    pub fn insert(&self, new: &NewSubmission, graders_since: Timestamp) -> Result<i64, Error> {
        self.transaction(|connection| {
            // `graders.languages` is a JSON array of names, `["javascript","python"]`.
            let busy: Option<i64> = connection
                .query_row(
                    "SELECT id FROM submissions s WHERE course = ?1 AND student = ?2 AND lab = ?3
                 AND status != 'graded'
                 AND (language = ?4 OR EXISTS (SELECT 1 FROM graders g WHERE g.seen >= ?5
                      AND g.languages LIKE '%\"' || s.language || '\"%'))
                 ORDER BY id LIMIT 1",
                    params![
                        new.course,
                        new.student,
                        new.lab.name(),
                        new.language.name(),
                        super::leases::millis(graders_since)
                    ],
                    |row| row.get(0),
                )
                .optional()?;
            if let Some(id) = busy {
                return Err(Error::Busy(id));
            }
            Ok(connection.query_row(
                "INSERT INTO submissions (course, student, member, lab, seed, source, status,
                 submitted_at, late_seconds, penalty, language, wanted_grader)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, 'queued', ?7, ?8, ?9, ?10, ?11) RETURNING id",
                params![
                    new.course,
                    new.student,
                    new.member,
                    new.lab.name(),
                    new.seed as i64,
                    new.source,
                    moment(new.submitted_at),
                    new.late_seconds,
                    new.penalty,
                    new.language.name(),
                    new.grader
                ],
                |row| row.get(0),
            )?)
        })
    }

    /// What grading a submission needs, its status left as it is.
    pub fn to_grade(&self, id: i64) -> Result<ToGrade, Error> {
        Ok(self.connection().query_row(
            "SELECT source, seed, course, student, lab, language FROM submissions WHERE id = ?1",
            [id],
            |row| {
                Ok(ToGrade {
                    exercise: exercise(row, 4)?,
                    language: named(row, 5)?,
                    source: row.get(0)?,
                    seed: row.get::<_, i64>(1)? as u64,
                    course: row.get(2)?,
                    student: row.get(3)?,
                })
            },
        )?)
    }

    /// Stores the result of a grading, with the grader that produced it, if `holder` still
    /// holds its lease (`leases`): a result is written once.
    pub fn finish_grading(
        &self,
        id: i64,
        result: &GradeResult,
        grader: Option<&str>,
        holder: &Holder,
    ) -> Result<(), Error> {
        let text = serde_json::to_string(result).expect("results serialise");
        let (figure, spread) = challenge_figure(result);
        let written = self.connection().execute(
            "UPDATE submissions SET status = 'graded', result = ?2, score = ?3, grader = ?4,
             challenge = ?5, challenge_spread = ?8, graded_at = ?6, leased_by = NULL,
             lease_until = 0
             WHERE id = ?1 AND status = 'grading' AND leased_by = ?7",
            params![
                id,
                text,
                result.gradable.then_some(result.score),
                grader,
                figure,
                moment(Timestamp::now()),
                holder.as_str(),
                spread
            ],
        )?;
        if written == 0 {
            return Err(Error::LeaseLost(format!("submission {id}")));
        }
        Ok(())
    }

    /// Ends a submission whose grading `holder` holds, and which failed, as not gradable,
    /// with the reason.
    pub fn give_up(&self, id: i64, reason: &str, holder: &Holder) -> Result<(), Error> {
        let (exercise, seed): (Exercise, i64) = self.connection().query_row(
            "SELECT lab, seed FROM submissions WHERE id = ?1",
            [id],
            |row| Ok((exercise(row, 0)?, row.get(1)?)),
        )?;
        self.finish_grading(
            id,
            &GradeResult::not_gradable(exercise, seed as u64, reason),
            None,
            holder,
        )
    }

    /// A submission whose grading `holder` began but whose sandbox did not start: queued
    /// again, for any grader.
    pub fn back_to_queue(&self, id: i64, holder: &Holder) -> Result<(), Error> {
        self.connection().execute(
            "UPDATE submissions SET status = ?2, leased_by = NULL, lease_until = 0
             WHERE id = ?1 AND status = ?3 AND leased_by = ?4",
            params![
                id,
                Status::Queued.as_str(),
                Status::Grading.as_str(),
                holder.as_str()
            ],
        )?;
        Ok(())
    }

    /// One submission, if it exists, with its source when `with_source`. The result is
    /// parsed after the lock is released.
    pub fn get(&self, id: i64, with_source: bool) -> Result<Option<Submission>, Error> {
        let row = self
            .connection()
            .query_row(
                &format!(
                    "SELECT {SUMMARY_COLUMNS}, s.seed, s.graded_at, s.member, s.result,
                     CASE WHEN ?2 THEN s.source END, s.grader FROM {SUMMARY_FROM} WHERE s.id = ?1"
                ),
                params![id, with_source],
                |row| {
                    Ok((
                        Submission {
                            summary: summary(row)?,
                            seed: row.get::<_, i64>(SUMMARY_WIDTH)? as u64,
                            graded_at: row.get(SUMMARY_WIDTH + 1)?,
                            member: row.get(SUMMARY_WIDTH + 2)?,
                            result: None,
                            source: row.get(SUMMARY_WIDTH + 4)?,
                            grader: row.get(SUMMARY_WIDTH + 5)?,
                            earlier: Vec::new(),
                            waiting_for: None,
                        },
                        row.get::<_, Option<String>>(SUMMARY_WIDTH + 3)?,
                    ))
                },
            )
            .optional()?;
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

    /// Whose a submission is, if it exists: its course and member. One small lookup, so
    /// that refusing someone else's submission costs what refusing a missing one does.
    pub fn owner(&self, id: i64) -> Result<Option<(String, Option<i64>)>, Error> {
        let owner = self
            .connection()
            .query_row(
                "SELECT course, member FROM submissions WHERE id = ?1",
                [id],
                |row| Ok((row.get(0)?, row.get(1)?)),
            )
            .optional()?;
        Ok(owner)
    }

    /// How many submissions a student has made to an exercise since `since`.
    pub fn submitted_since(
        &self,
        member: i64,
        lab: Exercise,
        since: Timestamp,
    ) -> Result<usize, Error> {
        let count: i64 = self.connection().query_row(
            "SELECT count(*) FROM submissions WHERE member = ?1 AND lab = ?2 AND submitted_at >= ?3",
            params![member, lab.name(), moment(since)],
            |row| row.get(0),
        )?;
        Ok(count as usize)
    }

    /// A student's own submissions to an exercise, oldest first.
    pub fn history(&self, member: i64, lab: Exercise) -> Result<Vec<SubmissionSummary>, Error> {
        let connection = self.connection();
        let list = connection.query_map(
            &format!(
                "SELECT {SUMMARY_COLUMNS} FROM {SUMMARY_FROM} WHERE s.member = ?1 AND s.lab = ?2
             ORDER BY s.id"
            ),
            params![member, lab.name()],
            summary,
        )?;
        Ok(list)
    }

    /// Every submission of a course's people to an exercise, by student then oldest first.
    pub fn course_submissions(
        &self,
        course: &str,
        lab: Exercise,
    ) -> Result<Vec<SubmissionSummary>, Error> {
        let connection = self.connection();
        let list = connection.query_map(
            &format!(
                "SELECT {SUMMARY_COLUMNS} FROM {SUMMARY_FROM}
             WHERE s.member IN (SELECT id FROM members WHERE course = ?1) AND s.lab = ?2
             ORDER BY s.student, s.id"
            ),
            params![course, lab.name()],
            summary,
        )?;
        Ok(list)
    }

    /// The stored results of some submissions (those graded), by id.
    pub fn results(&self, ids: &[i64]) -> Result<HashMap<i64, GradeResult>, Error> {
        let texts: Vec<(i64, String)> = {
            let connection = self.connection();
            let mut texts = Vec::with_capacity(ids.len());
            for &id in ids {
                let text = connection
                    .query_row(
                        "SELECT result FROM submissions WHERE id = ?1 AND result IS NOT NULL",
                        [id],
                        |row| row.get(0),
                    )
                    .optional()?;
                if let Some(text) = text {
                    texts.push((id, text));
                }
            }
            texts
        };
        texts
            .into_iter()
            .map(|(id, text)| {
                Ok((
                    id,
                    serde_json::from_str(&text).map_err(Error::StoredResult)?,
                ))
            })
            .collect()
    }

    /// Every submission in the database, oldest first (for the checks after a migration
    /// or a restart).
    pub fn all_submissions(&self) -> Result<Vec<SubmissionSummary>, Error> {
        let connection = self.connection();
        let list = connection.query_map(
            &format!("SELECT {SUMMARY_COLUMNS} FROM {SUMMARY_FROM} ORDER BY s.id"),
            (),
            summary,
        )?;
        Ok(list)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Since when graders count as running: none does.
    const NO_GRADER: Timestamp = Timestamp::MAX;

    fn new<'a>(student: &'a str, source: &'a str) -> NewSubmission<'a> {
        NewSubmission {
            course: "el2320",
            student,
            member: None,
            lab: Exercise::EkfLocalization,
            seed: 7,
            language: Language::JavaScript,
            source,
            submitted_at: Timestamp::UNIX_EPOCH,
            late_seconds: 0,
            penalty: 0.0,
            grader: "estlab test plan 0",
        }
    }

    /// A file in a language no running grader grades waits for one, and holds back no
    /// file in another language; one that a grader grades holds back the next as ever.
    #[test]
    fn a_file_no_grader_can_grade_holds_back_none_in_another_language() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let now = Timestamp::from_second(1_800_000_000).unwrap();
        let holder = Holder::this_process();
        let versions: &[&str] = &["estlab test plan 0"];
        store
            .heartbeat(&holder, (versions, &[Language::JavaScript]), now)
            .unwrap();
        let in_language = |language, source| NewSubmission {
            language,
            ..new("ada", source)
        };
        let matlab = store
            .insert(&in_language(Language::Matlab, "% one"), now)
            .unwrap();
        assert!(matches!(
            store.insert(&in_language(Language::Matlab, "% two"), now),
            Err(Error::Busy(id)) if id == matlab
        ));
        let javascript = store
            .insert(&in_language(Language::JavaScript, "// one"), now)
            .unwrap();
        assert!(matches!(
            store.insert(&in_language(Language::Python, "# one"), now),
            Err(Error::Busy(id)) if id == javascript
        ));
        // Once a grader of Octave runs, the MATLAB file holds back the rest too.
        store
            .heartbeat(&holder, (versions, &[Language::Matlab]), now)
            .unwrap();
        assert!(matches!(
            store.insert(&in_language(Language::Python, "# one"), now),
            Err(Error::Busy(id)) if id == matlab
        ));
        assert_eq!(
            store.live_languages(now).unwrap(),
            std::collections::HashSet::from([Language::Matlab])
        );
    }

    #[test]
    fn a_student_has_one_submission_waiting_and_a_failed_grading_frees_the_next() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let first = store.insert(&new("ada", "// one"), NO_GRADER).unwrap();
        // Another student is not held up; the same student is, while the first waits.
        store.insert(&new("grace", "// other"), NO_GRADER).unwrap();
        assert!(
            matches!(store.insert(&new("ada", "// two"), NO_GRADER), Err(Error::Busy(id)) if id == first)
        );
        let me = Holder::this_process();
        let lease = crate::store::Lease {
            holder: &me,
            from: Timestamp::now(),
            length: std::time::Duration::from_secs(30),
        };
        store.claim_submission(first, &lease).unwrap();
        assert!(matches!(
            store.insert(&new("ada", "// two"), NO_GRADER),
            Err(Error::Busy(_))
        ));

        // Grading failed on the server's side: the submission ends not gradable, the
        // student may submit again, and nothing is lost.
        store
            .give_up(first, "the server could not grade it", &me)
            .unwrap();
        let ended = store.get(first, false).unwrap().unwrap();
        assert_eq!(ended.summary.status, Status::Graded);
        assert_eq!(ended.source, None);
        let result = ended.result.unwrap();
        assert!(!result.gradable);
        assert_eq!(
            result.reason.as_deref(),
            Some("the server could not grade it")
        );
        assert_eq!(result.seed, 7);
        let second = store.insert(&new("ada", "// two"), NO_GRADER).unwrap();
        assert!(second > first);
        assert_eq!(store.to_grade(first).unwrap().source, "// one");
        assert_eq!(
            store.get(first, true).unwrap().unwrap().source.as_deref(),
            Some("// one")
        );
    }

    /// A database a later release wrote may hold an exercise this one does not grade: its
    /// submissions are left waiting for that release, and its assignments and regrades
    /// are left out, while the rest reads as before.
    #[test]
    fn an_exercise_of_a_later_release_is_left_alone() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        store
            .create_course("el2320", "Applied Estimation", Timestamp::UNIX_EPOCH)
            .unwrap();
        let known = store.insert(&new("ada", "// known"), NO_GRADER).unwrap();
        store
            .connection()
            .execute_batch(
                "INSERT INTO submissions (course, student, lab, seed, source, status, submitted_at,
                     late_seconds, penalty)
                 VALUES ('el2320', 'grace', 'particle-filter', 1, '// later', 'queued',
                     '1970-01-01T00:00:00.000Z', 0, 0);
                 INSERT INTO assignments (course, lab, due, cutoff, late_penalty, counts)
                 VALUES ('el2320', 'particle-filter', 0, 0, 0, 'best');
                 INSERT INTO regrades (course, lab, scope, requested_by, grader, created_at)
                 VALUES ('el2320', 'particle-filter', 'all', 'teacher', 'estlab 9', 0);",
            )
            .unwrap();
        let waiting: Vec<i64> = store
            .claimable(Timestamp::now())
            .unwrap()
            .iter()
            .map(|c| c.submission.id)
            .collect();
        assert_eq!(waiting, [known]);
        assert!(store.assignments("el2320").unwrap().is_empty());
        assert!(store.regrades("el2320").unwrap().is_empty());
    }
}
