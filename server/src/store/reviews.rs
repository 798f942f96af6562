//! Peer review of the written answers: the rounds, the answer sheets as handed out, who
//! reviews which sheet (numbered for the reviewer, who never learns whose it is), and the
//! marks. What a round hands out and how its marks count is `courses::rounds`' to decide.

use super::db::{self, Connection, OptionalExtension, params};
use super::{Error, Store, timestamp};
use crate::courses::questions::Answer;
use crate::courses::review::Pair;
use jiff::Timestamp;
use labs::Exercise;
use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// A round of peer review of one question set of an assignment.
#[derive(Clone, Debug, PartialEq, Serialize, TS)]
pub struct Round {
    pub id: i64,
    /// The question set reviewed: its place in the assignment, from 0.
    #[ts(type = "number")]
    pub part: usize,
    /// How many reviews each sheet gets.
    #[ts(type = "number")]
    pub per_sheet: usize,
    /// The share of correct marks above which a student earns the bonus.
    pub bonus_above: f64,
    pub opened_by: String,
    #[ts(as = "String")]
    pub opened_at: Timestamp,
    #[ts(as = "Option<String>")]
    pub closed_at: Option<Timestamp>,
    #[serde(skip)]
    pub seed: u64,
    /// The set reviewed, as TOML, as it was when the round opened.
    #[serde(skip)]
    pub questions: String,
}

/// One answer of a sheet as it was handed out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct SheetAnswer {
    pub question: String,
    pub answer: Answer,
}

/// A pair of a round as stored: `reviewer` has the sheet of `author` as their sheet
/// `number`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StoredPair {
    pub pair: Pair,
    pub number: usize,
    pub submitted_at: Option<Timestamp>,
}

/// A reviewer's mark of one answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct Mark {
    pub question: String,
    pub correct: bool,
    pub comment: String,
}

const ROUND_COLUMNS: &str =
    "id, part, per_sheet, bonus_above, opened_by, opened_at, closed_at, seed, questions";

fn round(row: &db::Row) -> db::Result<Round> {
    Ok(Round {
        id: row.get(0)?,
        part: row.get::<_, i64>(1)? as usize,
        per_sheet: row.get::<_, i64>(2)? as usize,
        bonus_above: row.get(3)?,
        opened_by: row.get(4)?,
        opened_at: timestamp(row.get(5)?),
        closed_at: row.get::<_, Option<i64>>(6)?.map(timestamp),
        seed: row.get::<_, i64>(7)? as u64,
        questions: row.get(8)?,
    })
}

/// A new round's settings.
pub struct NewRound<'a> {
    pub course: &'a str,
    pub lab: Exercise,
    pub part: usize,
    pub per_sheet: usize,
    pub bonus_above: f64,
    pub seed: u64,
    /// The set reviewed, as TOML.
    pub questions: &'a str,
    pub opened_by: &'a str,
}

fn insert_sheet(
    transaction: &Connection,
    round: i64,
    author: i64,
    sheet: &[SheetAnswer],
) -> db::Result<()> {
    let json = serde_json::to_string(sheet).expect("a sheet serialises");
    transaction.execute(
        "INSERT INTO review_sheets (round, author, answers) VALUES (?1, ?2, ?3)",
        params![round, author, json],
    )?;
    Ok(())
}

/// Adds `pair` as the reviewer's sheet numbered after every number they ever had in the
/// round: a number names one sheet for good, so marks sent for a sheet that went
/// elsewhere meanwhile never land on another.
fn insert_pair(transaction: &Connection, round: i64, pair: Pair) -> db::Result<()> {
    transaction.execute(
        "INSERT INTO review_pairs (round, reviewer, author, number)
         VALUES (?1, ?2, ?3, 1 + (SELECT COALESCE(MAX(number), 0) FROM review_numbers
                                  WHERE round = ?1 AND reviewer = ?2))",
        params![round, pair.reviewer, pair.author],
    )?;
    transaction.execute(
        "INSERT INTO review_numbers (round, reviewer, number)
         SELECT round, reviewer, number FROM review_pairs WHERE round = ?1 AND reviewer = ?2 AND author = ?3",
        params![round, pair.reviewer, pair.author],
    )?;
    Ok(())
}

fn delete_pair(transaction: &Connection, round: i64, pair: Pair) -> db::Result<()> {
    let keys = params![round, pair.reviewer, pair.author];
    transaction.execute(
        "DELETE FROM review_marks WHERE round = ?1 AND reviewer = ?2 AND author = ?3",
        keys,
    )?;
    transaction.execute(
        "DELETE FROM review_pairs WHERE round = ?1 AND reviewer = ?2 AND author = ?3",
        keys,
    )?;
    Ok(())
}

impl Store {
    /// Opens a round with its sheets (author, answers) and its pairs; its id.
    pub fn open_round(
        &self,
        new: &NewRound,
        sheets: &[(i64, Vec<SheetAnswer>)],
        pairs: &[Pair],
        now: Timestamp,
    ) -> Result<i64, Error> {
        self.transaction(|transaction| {
            let id = transaction.query_row(
                "INSERT INTO review_rounds (course, lab, part, per_sheet, seed, bonus_above,
                     opened_by, opened_at, questions)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9) RETURNING id",
                params![
                    new.course,
                    new.lab.name(),
                    new.part as i64,
                    new.per_sheet as i64,
                    new.seed as i64,
                    new.bonus_above,
                    new.opened_by,
                    now.as_second(),
                    new.questions
                ],
                |row| row.get(0),
            )?;
            for (author, sheet) in sheets {
                insert_sheet(transaction, id, *author, sheet)?;
            }
            for &pair in pairs {
                insert_pair(transaction, id, pair)?;
            }
            Ok(id)
        })
    }

    /// An assignment's rounds, the latest first.
    pub fn rounds(&self, course: &str, lab: Exercise) -> Result<Vec<Round>, Error> {
        let connection = self.connection();
        let rounds = connection.query_map(&format!(
            "SELECT {ROUND_COLUMNS} FROM review_rounds WHERE course = ?1 AND lab = ?2 ORDER BY id DESC"
        ), params![course, lab.name()], round)?;
        Ok(rounds)
    }

    /// The round `id` of an assignment; `None` when the assignment has no such round.
    pub fn round(&self, course: &str, lab: Exercise, id: i64) -> Result<Option<Round>, Error> {
        Ok(self
            .connection()
            .query_row(
                &format!(
                    "SELECT {ROUND_COLUMNS} FROM review_rounds WHERE course = ?1 AND lab = ?2 AND id = ?3"
                ),
                params![course, lab.name(), id],
                round,
            )
            .optional()?)
    }

    /// Closes a round; false when it was closed already.
    pub fn close_round(&self, id: i64, now: Timestamp) -> Result<bool, Error> {
        let changed = self.connection().execute(
            "UPDATE review_rounds SET closed_at = ?2 WHERE id = ?1 AND closed_at IS NULL",
            params![id, now.as_second()],
        )?;
        Ok(changed == 1)
    }

    /// A round's pairs.
    pub fn pairs(&self, round: i64) -> Result<Vec<StoredPair>, Error> {
        let connection = self.connection();
        let pairs = connection.query_map(
            "SELECT reviewer, author, number, submitted_at FROM review_pairs
             WHERE round = ?1 ORDER BY reviewer, number",
            params![round],
            |row| {
                Ok(StoredPair {
                    pair: Pair {
                        reviewer: row.get(0)?,
                        author: row.get(1)?,
                    },
                    number: row.get::<_, i64>(2)? as usize,
                    submitted_at: row.get::<_, Option<i64>>(3)?.map(timestamp),
                })
            },
        )?;
        Ok(pairs)
    }

    /// A round's sheets, by author.
    pub fn sheets(&self, round: i64) -> Result<Vec<(i64, Vec<SheetAnswer>)>, Error> {
        let connection = self.connection();
        let rows = connection.query_map(
            "SELECT author, answers FROM review_sheets WHERE round = ?1 ORDER BY author",
            params![round],
            |row| Ok((row.get::<_, i64>(0)?, row.get::<_, String>(1)?)),
        )?;
        rows.into_iter()
            .map(|(author, json)| {
                Ok((
                    author,
                    serde_json::from_str(&json).map_err(Error::StoredAnswer)?,
                ))
            })
            .collect()
    }

    /// Every mark of a round: (reviewer, author, mark).
    pub fn marks(&self, round: i64) -> Result<Vec<(Pair, Mark)>, Error> {
        let connection = self.connection();
        let marks = connection.query_map(
            "SELECT reviewer, author, question, correct, comment FROM review_marks
             WHERE round = ?1 ORDER BY reviewer, author, question",
            params![round],
            |row| {
                Ok((
                    Pair {
                        reviewer: row.get(0)?,
                        author: row.get(1)?,
                    },
                    Mark {
                        question: row.get(2)?,
                        correct: row.get(3)?,
                        comment: row.get(4)?,
                    },
                ))
            },
        )?;
        Ok(marks)
    }

    /// Replaces a reviewer's marks of one sheet, and submits them when `submit`; false,
    /// changing nothing, when the round has closed or the review was handed in meanwhile
    /// (both judged within the change).
    pub fn save_marks(
        &self,
        round: i64,
        pair: Pair,
        marks: &[Mark],
        submit: bool,
        now: Timestamp,
    ) -> Result<bool, Error> {
        self.transaction(|transaction| {
            let keys = params![round, pair.reviewer, pair.author];
            let open: bool = transaction.query_row(
                "SELECT EXISTS (SELECT 1 FROM review_rounds r JOIN review_pairs p ON p.round = r.id
                                WHERE r.id = ?1 AND r.closed_at IS NULL AND p.reviewer = ?2
                                  AND p.author = ?3 AND p.submitted_at IS NULL)",
                keys,
                |row| row.get(0),
            )?;
            if !open {
                return Ok(false);
            }
            transaction.execute(
                "DELETE FROM review_marks WHERE round = ?1 AND reviewer = ?2 AND author = ?3",
                keys,
            )?;
            for mark in marks {
                transaction.execute(
                    "INSERT INTO review_marks (round, reviewer, author, question, correct, comment)
                     VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                    params![
                        round,
                        pair.reviewer,
                        pair.author,
                        mark.question,
                        mark.correct,
                        mark.comment
                    ],
                )?;
            }
            if submit {
                transaction.execute(
                    "UPDATE review_pairs SET submitted_at = ?4
                     WHERE round = ?1 AND reviewer = ?2 AND author = ?3",
                    params![round, pair.reviewer, pair.author, now.as_second()],
                )?;
            }
            Ok(true)
        })
    }

    /// A late author joins a round: their sheet, the pairs that make room for them
    /// (`removed`, with any marks) and those that take them in (`added`).
    pub fn join_round(
        &self,
        round: i64,
        (author, sheet): (i64, &[SheetAnswer]),
        removed: &[Pair],
        added: &[Pair],
    ) -> Result<(), Error> {
        self.transaction(|transaction| {
            insert_sheet(transaction, round, author, sheet)?;
            for &pair in removed {
                delete_pair(transaction, round, pair)?;
            }
            for &pair in added {
                insert_pair(transaction, round, pair)?;
            }
            Ok(())
        })
    }

    /// Moves sheets between reviewers: each old pair (with any marks) is removed and its
    /// new one, where there is one, added.
    pub fn move_pairs(&self, round: i64, moves: &[(Pair, Option<Pair>)]) -> Result<(), Error> {
        self.transaction(|transaction| {
            for &(old, new) in moves {
                delete_pair(transaction, round, old)?;
                if let Some(new) = new {
                    insert_pair(transaction, round, new)?;
                }
            }
            Ok(())
        })
    }
}
