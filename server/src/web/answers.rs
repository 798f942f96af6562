//! The written part of an assignment: its question sets, for its students to answer (the
//! answers they are checked against and the model answers left out) and for its staff
//! in full; the students' answers, saved as they type until their cutoff; and the
//! instructors' import of other sets.
//!
//! - `GET /courses/{course}/{lab}/questions`: the page students answer on (staff read it)
//! - `GET /api/courses/{course}/labs/{lab}/questions`
//! - `POST /api/courses/{course}/labs/{lab}/questions` (instructors)
//! - `POST /api/courses/{course}/labs/{lab}/answers` (students)
//!
//! Anyone outside the course gets the 404 of a course that does not exist.

use super::extract::Body;
use super::pages::{Nav, html};
use super::setup::change;
use super::viewer::Viewer;
use super::{AppState, Error, blocking, known_lab};
use crate::courses::questions::{self, Answer, QuestionSet};
use crate::courses::report;
use crate::store::SavedAnswer;
use askama::Template;
use axum::Json;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Redirect, Response};
use jiff::Timestamp;
use labs::Exercise;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use ts_rs::TS;

/// What `GET .../questions` answers.
#[derive(Serialize, TS)]
pub struct Written {
    pub lab: Exercise,
    /// Whether staff read it (the sets in full, no answers of their own).
    pub staff: bool,
    /// Whether the sets are the exercise's own (none imported).
    pub own: bool,
    /// For staff in full; for a student without what they are checked against.
    pub sets: Vec<QuestionSet>,
    /// For staff, the sets as written (TOML), to edit; none for a student.
    pub sources: Vec<String>,
    /// Whether the reader may give the assignment other sets (its instructors).
    pub instructor: bool,
    /// The student's answers (none for staff).
    pub answers: Vec<SavedAnswer>,
    /// The last moment a student's answers are taken (their cutoff, extensions counted);
    /// none for staff.
    #[ts(as = "Option<String>")]
    pub cutoff: Option<Timestamp>,
    /// Whether the student's answers are taken now: before their cutoff, or after it
    /// while staff have sent their report back for revision. False for staff.
    pub open: bool,
}

impl Written {
    /// An assignment's sets in full and as written, as staff read them (`instructor`: one
    /// who may change them).
    fn for_staff(
        store: &crate::store::Store,
        course: &str,
        lab: Exercise,
        instructor: bool,
    ) -> Result<Written, crate::store::Error> {
        Ok(Written {
            lab,
            staff: true,
            own: store.questions(course, lab)?.is_none(),
            sets: questions::of_assignment(store, course, lab)?,
            sources: questions::sources(store, course, lab)?,
            instructor,
            answers: Vec::new(),
            cutoff: None,
            open: false,
        })
    }
}

pub async fn questions(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    let exercise = known_lab(&lab)?;
    let staff = viewer.is_staff_of(&course);
    let instructor = viewer.instructor_of(&course).is_ok();
    let student = match viewer.member() {
        Some(member) if !staff && member.course == course => Some((member.id, member.dropped)),
        _ if staff => None,
        _ => return Err(Error::NotFound(format!("there is no course {course:?}"))),
    };
    let now = state.clock.now();
    let written = blocking(&state, move |store| {
        if store.assignment(&course, exercise)?.is_none() {
            return Ok(None);
        }
        let full = Written::for_staff(store, &course, exercise, instructor)?;
        Ok(Some(match student {
            None => full,
            Some((member, dropped)) => {
                let cutoff = store
                    .policy_for(&course, exercise, member)?
                    .map(|p| p.cutoff);
                let in_time = cutoff.is_some_and(|c| now <= c);
                Written {
                    staff: false,
                    sets: full.sets.iter().map(QuestionSet::for_students).collect(),
                    sources: Vec::new(),
                    answers: store.answers(member, exercise)?,
                    open: !dropped && (in_time || revising(store, member, exercise)?),
                    cutoff,
                    ..full
                }
            }
        }))
    })
    .await?
    .ok_or_else(|| Error::NotFound("the course has not opened this exercise".into()))?;
    Ok(Json(written).into_response())
}

/// Whether staff have sent the student's report back for revision (their answers are
/// part of it, and taken after the cutoff then).
fn revising(
    store: &crate::store::Store,
    member: i64,
    lab: Exercise,
) -> Result<bool, crate::store::Error> {
    let report = store.report(member, lab)?;
    Ok(report.is_some_and(|r| r.state() == report::State::Revise))
}

/// The body of `POST .../answers`: one answer.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct AnswerRequest {
    /// The set's place in the assignment, from 0.
    #[ts(type = "number")]
    pub part: usize,
    /// The question's id.
    pub question: String,
    pub answer: Answer,
}

/// `POST .../answers`: a student's answer to one question, kept as their latest until
/// their cutoff.
pub async fn save(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    let exercise = known_lab(&lab)?;
    let member = match viewer.member() {
        Some(member) if member.course == course && !member.role.is_staff() && member.dropped => {
            return Err(Error::Forbidden(format!(
                "you are no longer on the roster of {course}: your answers are kept as they are"
            )));
        }
        Some(member) if member.course == course && !member.role.is_staff() => member.clone(),
        _ if viewer.is_staff_of(&course) => {
            return Err(Error::Forbidden(
                "only the course's students answer its questions".into(),
            ));
        }
        _ => return Err(Error::NotFound(format!("there is no course {course:?}"))),
    };
    let request: AnswerRequest = body.json(&viewer, "the answer").await?;
    let now = state.clock.now();
    let saved = blocking(&state, move |store| {
        let Some(policy) = store.policy_for(&course, exercise, member.id)? else {
            return Ok(Err(Error::NotFound(
                "the course has not opened this exercise".into(),
            )));
        };
        // After the cutoff, only to revise a report staff sent back.
        if now > policy.cutoff && !revising(store, member.id, exercise)? {
            return Ok(Err(Error::Forbidden(format!(
                "the cutoff of this exercise was {}: answers are no longer taken",
                policy.cutoff.strftime("%Y-%m-%d %H:%M UTC")
            ))));
        }
        let sets = questions::of_assignment(store, &course, exercise)?;
        let Some(set) = sets.get(request.part) else {
            return Ok(Err(Error::BadRequest(format!(
                "field `part`: the assignment has {} question sets, counted from 0",
                sets.len()
            ))));
        };
        let Some(question) = set.questions.iter().find(|q| q.id == request.question) else {
            return Ok(Err(Error::BadRequest(format!(
                "field `question`: {:?} has no question {:?}",
                set.title, request.question
            ))));
        };
        if let Err(problem) = question.accepts(&request.answer) {
            return Ok(Err(Error::BadRequest(format!("field `answer`: {problem}"))));
        }
        let place = (request.part, request.question.as_str());
        store.save_answer(member.id, exercise, place, &request.answer, now)?;
        Ok(Ok(SavedAnswer {
            part: request.part,
            question: request.question,
            answer: request.answer,
            saved_at: now,
        }))
    })
    .await??;
    Ok(Json(saved).into_response())
}

/// The body of `POST .../questions`: the sets, as TOML, or none for the exercise's own.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct QuestionsRequest {
    pub sets: Option<Vec<String>>,
}

/// `POST .../questions`: an instructor gives the assignment other question sets (each
/// read and checked, a problem naming its set, line, question and field), or its
/// exercise's own again; logged. Answers are kept by question id across such changes.
pub async fn import(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let exercise = known_lab(&lab)?;
    let request: QuestionsRequest = body.json(&viewer, "the question sets").await?;
    let at = course.clone();
    change(&state, &viewer, course, move |setup| {
        setup.set_questions(exercise, request.sets)
    })
    .await
    .map_err(|error| match error {
        Error::BadRequest(problem) => Error::BadRequest(format!("field `sets`: {problem}")),
        other => other,
    })?;
    let written = blocking(&state, move |store| {
        Written::for_staff(store, &at, exercise, true)
    })
    .await?;
    Ok(Json(written).into_response())
}

#[derive(Template)]
#[template(path = "questions.html")]
struct QuestionsPage<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    course: String,
    lab: Exercise,
    title: &'static str,
}

/// `GET /courses/{course}/{lab}/questions`: the page of the written questions, for the
/// course's people (a student answers there; staff read the sets in full); anyone
/// signed out is sent to sign in, anyone else gets the 404 of a course that does not
/// exist.
pub async fn page(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    if matches!(viewer, Viewer::Anonymous) {
        return Ok(Redirect::to("/signin").into_response());
    }
    if !viewer.of_course(&course) {
        return Err(Error::NotFound(format!("there is no course {course:?}")));
    }
    let exercise = known_lab(&lab)?;
    html(&QuestionsPage {
        page: "questions",
        assets: state.assets.page("questions"),
        nav: Nav::of(&state, &viewer).await?,
        course,
        lab: exercise,
        title: exercise.declaration().title,
    })
}
