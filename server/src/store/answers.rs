//! The written hand-in: an assignment's question sets as its instructors imported them,
//! and each student's answers (the latest to each question; saved as they type).

use super::db::{OptionalExtension, params};
use super::{Error, Store, timestamp};
use crate::courses::questions::Answer;
use jiff::Timestamp;
use labs::Exercise;

/// A student's answer to one question, as last saved.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, ts_rs::TS)]
pub struct SavedAnswer {
    /// The question set's place in the assignment, from 0.
    #[ts(type = "number")]
    pub part: usize,
    /// The question's id in its set.
    pub question: String,
    pub answer: Answer,
    #[ts(as = "String")]
    pub saved_at: Timestamp,
}

impl Store {
    /// Gives an assignment the question sets `sources` (TOML, in order; `None`: the
    /// exercise's own); false when the course has not opened the exercise.
    pub fn set_questions(
        &self,
        course: &str,
        lab: Exercise,
        sources: Option<&[String]>,
    ) -> Result<bool, Error> {
        let stored = sources.map(|s| serde_json::to_string(s).expect("texts serialise"));
        let changed = self.connection().execute(
            "UPDATE assignments SET questions = ?3 WHERE course = ?1 AND lab = ?2",
            params![course, lab.name(), stored],
        )?;
        Ok(changed == 1)
    }

    /// The question sets an assignment was given, as TOML; `None` when it takes the
    /// exercise's own (or the course has not opened it).
    pub fn questions(&self, course: &str, lab: Exercise) -> Result<Option<Vec<String>>, Error> {
        let stored: Option<String> = self
            .connection()
            .query_row(
                "SELECT questions FROM assignments WHERE course = ?1 AND lab = ?2",
                params![course, lab.name()],
                |row| row.get(0),
            )
            .optional()?
            .flatten();
        stored
            .map(|json| serde_json::from_str(&json).map_err(Error::StoredAnswer))
            .transpose()
    }

    /// Keeps `answer` as the student's latest to `question` of the assignment's set
    /// `part`.
    pub fn save_answer(
        &self,
        member: i64,
        lab: Exercise,
        (part, question): (usize, &str),
        answer: &Answer,
        now: Timestamp,
    ) -> Result<(), Error> {
        let json = serde_json::to_string(answer).expect("an answer serialises");
        self.connection().execute(
            "INSERT INTO answers (member, lab, part, question, answer, saved_at)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6)
             ON CONFLICT (member, lab, part, question) DO UPDATE SET answer = ?5, saved_at = ?6",
            params![
                member,
                lab.name(),
                part as i64,
                question,
                json,
                now.as_second()
            ],
        )?;
        Ok(())
    }

    /// A student's answers to an assignment's questions, set by set.
    pub fn answers(&self, member: i64, lab: Exercise) -> Result<Vec<SavedAnswer>, Error> {
        let connection = self.connection();
        let rows = connection.query_map(
            "SELECT part, question, answer, saved_at FROM answers
             WHERE member = ?1 AND lab = ?2 ORDER BY part, question",
            params![member, lab.name()],
            |row| {
                Ok((
                    row.get::<_, i64>(0)?,
                    row.get::<_, String>(1)?,
                    row.get::<_, String>(2)?,
                    row.get::<_, i64>(3)?,
                ))
            },
        )?;
        rows.into_iter()
            .map(|(part, question, json, saved_at)| {
                Ok(SavedAnswer {
                    part: part as usize,
                    question,
                    answer: serde_json::from_str(&json).map_err(Error::StoredAnswer)?,
                    saved_at: timestamp(saved_at),
                })
            })
            .collect()
    }
}
