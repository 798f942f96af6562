//! Regrading: a job over some graded submissions of a course's exercise, item by item,
//! each result replacing the current one while the replaced one is kept, so that nobody's
//! score changes silently and a stop resumes the job where it was.

use super::db::{OptionalExtension, Value, params};
use super::leases::Holder;
use super::submissions::{
    SUMMARY_COLUMNS, SUMMARY_FROM, SUMMARY_WIDTH, challenge_figure, moment, summary,
};
use super::timestamp;
use super::{Error, Store, exercise, known_exercises};
use jiff::Timestamp;
use labs::Exercise;
use labs::grading::GradeResult;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use ts_rs::TS;

/// What a regrade covers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[serde(
    rename_all = "snake_case",
    tag = "kind",
    content = "of",
    deny_unknown_fields
)]
pub enum Scope {
    /// One submission, by id.
    Submission(i64),
    /// Every graded submission of one student, by their id.
    Student(String),
    /// Every graded submission of these students (a selection of the class), by id.
    Students(Vec<String>),
    /// Every graded submission of the course's people to the exercise.
    Assignment,
}

impl Scope {
    fn describe(&self) -> String {
        match self {
            Scope::Submission(id) => format!("submission {id}"),
            Scope::Student(login) => format!("student {login}"),
            Scope::Students(logins) => format!("students {}", logins.join(", ")),
            Scope::Assignment => "assignment".into(),
        }
    }
}

/// A score a regrade changed (or not yet: `new_score` is none until the item is done).
#[derive(Debug, Serialize, TS)]
pub struct Change {
    pub submission: i64,
    pub student: String,
    pub old_score: Option<f64>,
    pub new_score: Option<f64>,
    /// The same after the submission's late penalty as judged now (a regrade leaves it
    /// alone).
    pub old_final: Option<f64>,
    pub new_final: Option<f64>,
}

/// A regrade job and how far it has come.
#[derive(Debug, Serialize, TS)]
pub struct Regrade {
    pub id: i64,
    pub course: String,
    pub lab: Exercise,
    pub scope: String,
    pub requested_by: String,
    /// The grader that regrades.
    pub grader: String,
    #[ts(as = "String")]
    pub created_at: Timestamp,
    #[ts(as = "Option<String>")]
    pub finished_at: Option<Timestamp>,
    pub total: usize,
    pub done: usize,
    /// The submissions whose score went up or down, by how much.
    pub changed: Vec<Change>,
}

/// A result a regrade replaced, kept.
#[derive(Debug, Serialize, TS)]
pub struct EarlierResult {
    #[serde(flatten)]
    pub about: Replaced,
    pub result: GradeResult,
}

/// Which result was replaced, and by which regrade.
#[derive(Debug, Serialize, TS)]
pub struct Replaced {
    pub grader: Option<String>,
    pub score: Option<f64>,
    pub graded_at: Option<String>,
    /// The regrade that replaced it: its id, when it was asked for and by whom.
    pub replaced_by: Option<i64>,
    #[ts(as = "Option<String>")]
    pub replaced_at: Option<Timestamp>,
    pub replaced_on_request_of: Option<String>,
}
/// A replaced result as stored: what it was and what replaced it, and its JSON.
type EarlierRow = (Replaced, String);

/// Scores within this are the same score.
const SAME: f64 = 1e-9;

impl Store {
    /// Starts a regrade of the graded submissions in `scope`; returns its id and how
    /// many submissions it covers (none is an error: nothing to regrade).
    pub fn start_regrade(
        &self,
        course: &str,
        lab: Exercise,
        scope: &Scope,
        requested_by: &str,
        grader: &str,
        now: Timestamp,
    ) -> Result<(i64, usize), Error> {
        self.transaction(|transaction| {
            let listed;
            let (filter, value) = match scope {
                Scope::Submission(id) => ("AND s.id = ?3", Value::Integer(*id)),
                Scope::Student(login) => ("AND m.login = ?3", Value::Text(login)),
                Scope::Students(logins) => {
                    listed = serde_json::to_string(logins).expect("ids serialise");
                    (
                        "AND m.login IN (SELECT value FROM json_each(?3))",
                        Value::Text(&listed),
                    )
                }
                Scope::Assignment => ("AND CAST(?3 AS TEXT) IS NULL", Value::Null),
            };
            let ids: Vec<i64> = {
                transaction.query_map(
                    &format!(
                        "SELECT s.id FROM submissions s JOIN members m ON m.id = s.member
                     WHERE m.course = ?1 AND s.lab = ?2 AND s.status = 'graded' {filter}
                     ORDER BY s.id"
                    ),
                    params![course, lab.name(), value],
                    |row| row.get(0),
                )?
            };
            if ids.is_empty() {
                return Err(Error::Conflict(format!(
                    "nothing to regrade: no graded submission of {} in {course}'s {lab}",
                    scope.describe()
                )));
            }
            let regrade = transaction.query_row(
                "INSERT INTO regrades (course, lab, scope, requested_by, grader, created_at)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6) RETURNING id",
                params![
                    course,
                    lab.name(),
                    scope.describe(),
                    requested_by,
                    grader,
                    now.as_second()
                ],
                |row| row.get(0),
            )?;
            for id in &ids {
                transaction.execute(
                    "INSERT INTO regrade_items (regrade, submission, old_score)
                     SELECT ?1, id, score FROM submissions WHERE id = ?2",
                    params![regrade, id],
                )?;
            }
            Ok((regrade, ids.len()))
        })
    }

    /// The next item a grader of the versions `mine` may take at `now` (none held under a
    /// lease that runs on): of the oldest unfinished regrade asked of one of them, or of a
    /// grader none of whose version runs (`running`), if any. A regrade asked of another
    /// release's grader waits for it while one runs.
    pub fn next_regrade_item(
        &self,
        now: Timestamp,
        mine: &[&str],
        running: &HashSet<String>,
    ) -> Result<Option<(i64, i64)>, Error> {
        let mine = serde_json::to_string(mine).expect("names serialise");
        let running = serde_json::to_string(running).expect("names serialise");
        Ok(self
            .connection()
            .query_row(
                "SELECT i.regrade, i.submission FROM regrade_items i
                 JOIN regrades r ON r.id = i.regrade
                 WHERE i.done = 0 AND i.lease_until < ?1
                 AND (r.grader IN (SELECT value FROM json_each(?2))
                    OR r.grader NOT IN (SELECT value FROM json_each(?3)))
                 ORDER BY i.regrade, i.submission LIMIT 1",
                params![now.as_millisecond(), mine, running],
                |row| Ok((row.get(0)?, row.get(1)?)),
            )
            .optional()?)
    }

    /// Records a regrade's result for one submission in one transaction, if `holder`
    /// still holds the item's lease (`leases`): the current result is kept among the
    /// earlier ones, the new one becomes current, the item is done, and the regrade
    /// finished when it was its last item.
    pub fn finish_regrade_item(
        &self,
        regrade: i64,
        submission: i64,
        result: &GradeResult,
        grader: &str,
        holder: &Holder,
        now: Timestamp,
    ) -> Result<(), Error> {
        let text = serde_json::to_string(result).expect("results serialise");
        let score = result.gradable.then_some(result.score);
        self.transaction(|transaction| {
            let waiting: bool = transaction.query_row(
                "SELECT EXISTS (SELECT 1 FROM regrade_items
                 WHERE regrade = ?1 AND submission = ?2 AND done = 0 AND leased_by = ?3)",
                params![regrade, submission, holder.as_str()],
                |row| row.get(0),
            )?;
            if !waiting {
                return Err(Error::LeaseLost(format!(
                    "regrade {regrade}'s item submission {submission}"
                )));
            }
            transaction.execute(
                "INSERT INTO results (submission, grader, score, result, graded_at, replaced_by)
                 SELECT id, grader, score, result, graded_at, ?2 FROM submissions WHERE id = ?1",
                params![submission, regrade],
            )?;
            let (figure, spread) = challenge_figure(result);
            transaction.execute(
                "UPDATE submissions SET result = ?2, score = ?3, grader = ?4, challenge = ?5,
                 challenge_spread = ?7, graded_at = ?6 WHERE id = ?1",
                params![
                    submission,
                    text,
                    score,
                    grader,
                    figure,
                    moment(Timestamp::now()),
                    spread
                ],
            )?;
            transaction.execute(
                "UPDATE regrade_items SET done = 1, new_score = ?3, leased_by = NULL,
                 lease_until = 0 WHERE regrade = ?1 AND submission = ?2",
                params![regrade, submission, score],
            )?;
            transaction.execute(
                "UPDATE regrades SET finished_at = ?2 WHERE id = ?1 AND NOT EXISTS
                 (SELECT 1 FROM regrade_items WHERE regrade = ?1 AND done = 0)",
                params![regrade, now.as_second()],
            )?;
            Ok(())
        })
    }

    /// A course's regrades, newest first, each with its progress and changed scores.
    pub fn regrades(&self, course: &str) -> Result<Vec<Regrade>, Error> {
        let ids: Vec<i64> = {
            let connection = self.connection();
            connection.query_map(
                "SELECT id FROM regrades WHERE course = ?1
                 AND lab IN (SELECT value FROM json_each(?2)) ORDER BY id DESC",
                params![course, known_exercises()],
                |row| row.get(0),
            )?
        };
        ids.into_iter()
            .map(|id| self.regrade(course, id))
            .filter_map(Result::transpose)
            .collect()
    }

    /// One regrade of a course, with its progress and the scores it changed.
    pub fn regrade(&self, course: &str, id: i64) -> Result<Option<Regrade>, Error> {
        let connection = self.connection();
        let Some(mut regrade) = connection
            .query_row(
                "SELECT r.id, r.course, r.lab, r.scope, r.requested_by, r.grader, r.created_at,
                        r.finished_at, count(i.submission), CAST(coalesce(sum(i.done), 0) AS BIGINT)
                 FROM regrades r LEFT JOIN regrade_items i ON i.regrade = r.id
                 WHERE r.id = ?1 AND r.course = ?2 GROUP BY r.id",
                params![id, course],
                |row| {
                    Ok(Regrade {
                        id: row.get(0)?,
                        course: row.get(1)?,
                        lab: exercise(row, 2)?,
                        scope: row.get(3)?,
                        requested_by: row.get(4)?,
                        grader: row.get(5)?,
                        created_at: timestamp(row.get(6)?),
                        finished_at: row.get::<_, Option<i64>>(7)?.map(timestamp),
                        total: row.get::<_, i64>(8)? as usize,
                        done: row.get::<_, i64>(9)? as usize,
                        changed: Vec::new(),
                    })
                },
            )
            .optional()?
        else {
            return Ok(None);
        };
        // The finals with the penalty as it is judged now (by the dates in force and any
        // waiver), which a regrade leaves alone.
        regrade.changed = connection
            .query_map(
                &format!(
                    "SELECT {SUMMARY_COLUMNS}, i.old_score, i.new_score
             FROM {SUMMARY_FROM} JOIN regrade_items i ON i.submission = s.id
             WHERE i.regrade = ?1 AND i.done = 1 ORDER BY s.student, s.id"
                ),
                params![id],
                |row| {
                    let (old_score, new_score): (Option<f64>, Option<f64>) =
                        (row.get(SUMMARY_WIDTH)?, row.get(SUMMARY_WIDTH + 1)?);
                    let submission = summary(row)?;
                    let kept = 1.0 - submission.penalty;
                    Ok(Change {
                        submission: submission.id,
                        student: submission.student,
                        old_score,
                        new_score,
                        old_final: old_score.map(|s| s * kept),
                        new_final: new_score.map(|s| s * kept),
                    })
                },
            )?
            .into_iter()
            .filter(|c| match (c.old_score, c.new_score) {
                (Some(old), Some(new)) => (old - new).abs() > SAME,
                (old, new) => old.is_some() != new.is_some(),
            })
            .collect();
        Ok(Some(regrade))
    }

    /// The results regrades replaced for a submission, oldest first.
    pub fn earlier_results(&self, submission: i64) -> Result<Vec<EarlierResult>, Error> {
        let rows: Vec<EarlierRow> = {
            let connection = self.connection();
            connection.query_map(
                "SELECT r.grader, r.score, r.graded_at, r.replaced_by, g.created_at,
                        g.requested_by, r.result
                 FROM results r LEFT JOIN regrades g ON g.id = r.replaced_by
                 WHERE r.submission = ?1 ORDER BY r.id",
                params![submission],
                |row| {
                    Ok((
                        Replaced {
                            grader: row.get(0)?,
                            score: row.get(1)?,
                            graded_at: row.get(2)?,
                            replaced_by: row.get(3)?,
                            replaced_at: row.get::<_, Option<i64>>(4)?.map(timestamp),
                            replaced_on_request_of: row.get(5)?,
                        },
                        row.get(6)?,
                    ))
                },
            )?
        };
        rows.into_iter()
            .map(|(about, text)| {
                Ok(EarlierResult {
                    about,
                    result: serde_json::from_str(&text).map_err(Error::StoredResult)?,
                })
            })
            .collect()
    }
}
