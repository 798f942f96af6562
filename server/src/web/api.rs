//! The JSON API: submitting code for grading, reading a submission, and (for a course's
//! staff) its people and their submissions.
//!
//! On a server without courses anyone may submit under any student id and read any
//! submission's result (a quick demo; the pages say so). Once a course exists, only a
//! signed-in student submits, as themselves, to an exercise their course has opened; a
//! submission is read by its student and their course's staff, and by nobody else:
//! someone else's submission answers 404 exactly as one that does not exist.

use super::extract::{Body, Query};
use super::submit::{Submit, accept};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::store::{Member, Status};
use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use jiff::Timestamp;
use labs::Language;
use serde::Deserialize;
use std::sync::Arc;

/// `POST /api/submissions`: stores the submission, queues its grading and answers at once
/// with 202 and where to find the result.
pub async fn submit(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    body: Body,
) -> Result<Response, Error> {
    let courses = blocking(&state, |store| store.any_course()).await?;
    // Who asks is checked before what they send.
    let member = if courses {
        Some(signed_in_student(&viewer)?)
    } else {
        None
    };
    let submission: Submit = body.json(&viewer, "the submission body").await?;
    let accepted = accept(&state, member, submission).await?;
    Ok((
        StatusCode::ACCEPTED,
        [(axum::http::header::LOCATION, accepted.url.clone())],
        Json(accepted),
    )
        .into_response())
}

/// The signed-in student who may submit, or why not.
fn signed_in_student(viewer: &Viewer) -> Result<&Member, Error> {
    let member = match viewer {
        Viewer::Anonymous => {
            return Err(Error::Unauthorized(
                "sign in to submit: this server runs courses, and a submission counts for the signed-in student".into(),
            ));
        }
        Viewer::Token(_) => {
            return Err(Error::Forbidden(
                "an API token reads a course; students submit for themselves".into(),
            ));
        }
        Viewer::Member(member) => member,
    };
    if member.role.is_staff() {
        return Err(Error::Forbidden(format!(
            "you are signed in as {} of {}: staff do not submit (try a file with Run tests, or estlab grade)",
            member.role.as_str(),
            member.course
        )));
    }
    if member.dropped {
        return Err(Error::Forbidden(format!(
            "you are no longer on the roster of {}: ask your teacher",
            member.course
        )));
    }
    Ok(member)
}

/// `GET /api/submissions/{id}`: the submission's status and, once graded, its result;
/// with courses, its source too (for its student and their course's staff).
pub async fn submission(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(id): Path<String>,
) -> Result<Response, Error> {
    let missing = || Error::NotFound(format!("there is no submission {id:?}"));
    let number: i64 = id.parse().map_err(|_| missing())?;
    let (courses, owner) = blocking(&state, move |store| {
        Ok((store.any_course()?, store.owner(number)?))
    })
    .await?;
    let (course, member) = owner.ok_or_else(missing)?;
    // Someone else's answers as a missing one does, after the same lookups.
    if courses {
        let own = viewer
            .member()
            .is_some_and(|viewer| Some(viewer.id) == member);
        let staff = member.is_some() && viewer.is_staff_of(&course);
        if !(own || staff) {
            return Err(missing());
        }
    }
    // Without courses, open to anyone: the result, nobody's code.
    let graders_since = state.grader.live_since(Timestamp::now());
    let submission = blocking(&state, move |store| {
        store
            .get(number, courses)?
            .map(|submission| {
                let language = submission.summary.language;
                let waiting_for = (submission.summary.status == Status::Queued
                    && !store.live_languages(graders_since)?.contains(&language))
                .then(|| waiting_for_a_grader(language));
                Ok::<_, crate::store::Error>(crate::store::Submission {
                    earlier: store.earlier_results(number)?,
                    waiting_for,
                    ..submission
                })
            })
            .transpose()
    })
    .await?;
    let submission = submission.ok_or_else(missing)?;
    Ok(Json(submission).into_response())
}

/// What a submission waits for when no running grader grades its language.
fn waiting_for_a_grader(language: Language) -> String {
    format!(
        "No grader of {} files runs now: it waits for one. A file of yours in another language is taken meanwhile.",
        language.title()
    )
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabQuery {
    #[serde(default = "super::default_lab")]
    lab: String,
}

/// `GET /api/courses/{course}/submissions?lab=...`: for its staff, every submission of
/// the course's people to an exercise (no sources; each is read on its own).
pub async fn course_submissions(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(name): Path<String>,
    Query(query): Query<LabQuery>,
) -> Result<Response, Error> {
    viewer.staff_of(&name)?;
    let lab = lab_field(&query.lab)?;
    let list = blocking(&state, move |store| store.course_submissions(&name, lab)).await?;
    Ok(Json(list).into_response())
}
