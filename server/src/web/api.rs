//! The JSON API: submitting code for grading and reading the result.

use super::{AppState, Error};
use crate::sandbox::check_size;
use crate::submissions::NewSubmission;
use axum::Json;
use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use labs::grading::{DEFAULT_COURSE, LAB, student_seed};
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// The longest student or course id accepted.
const MAX_ID: usize = 100;

/// The body of `POST /api/submissions`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Submit {
    student: String,
    #[serde(default = "default_course")]
    course: String,
    #[serde(default = "default_lab")]
    lab: String,
    source: String,
}

fn default_course() -> String {
    DEFAULT_COURSE.into()
}

fn default_lab() -> String {
    LAB.into()
}

/// `POST /api/submissions`: stores the submission, queues its grading and answers at once
/// with 202 and where to find the result.
pub async fn submit(State(state): State<Arc<AppState>>, body: Bytes) -> Result<Response, Error> {
    let submit: Submit = serde_json::from_slice(&body)
        .map_err(|e| Error::BadRequest(format!("the submission body: {e}")))?;
    let student = id_field("student", &submit.student)?;
    let course = id_field("course", &submit.course)?;
    if submit.lab != LAB {
        return Err(Error::BadRequest(format!(
            "field `lab`: unknown exercise {:?}; the exercise graded here is {LAB:?}",
            submit.lab
        )));
    }
    check_size(&submit.source)
        .map_err(|problem| Error::TooLarge(format!("field `source`: {problem}")))?;
    let seed = student_seed(course, student);
    let new = NewSubmission {
        course,
        student,
        lab: LAB,
        seed,
        source: &submit.source,
    };
    let id = state.grader.submit(&new).map_err(|error| match error {
        busy @ crate::submissions::Error::Busy(_) => Error::Conflict(busy.to_string()),
        other => other.into(),
    })?;
    let location = format!("/api/submissions/{id}");
    Ok((
        StatusCode::ACCEPTED,
        [(axum::http::header::LOCATION, location.clone())],
        Json(json!({ "id": id, "seed": seed, "status": "queued", "url": location })),
    )
        .into_response())
}

/// `GET /api/submissions/{id}`: the submission's status and, once graded, its result.
pub async fn submission(
    State(state): State<Arc<AppState>>,
    Path(id): Path<String>,
) -> Result<Response, Error> {
    let missing = || Error::NotFound(format!("there is no submission {id:?}"));
    let number: i64 = id.parse().map_err(|_| missing())?;
    // Off the async executor: a stored result is read and parsed on a blocking thread.
    let grader = Arc::clone(&state.grader);
    let submission = tokio::task::spawn_blocking(move || grader.store().get(number))
        .await
        .map_err(|e| crate::submissions::Error::Task(e.to_string()))??
        .ok_or_else(missing)?;
    Ok(Json(submission).into_response())
}

/// A student or course id: trimmed, not empty, short, printable.
fn id_field<'a>(field: &str, value: &'a str) -> Result<&'a str, Error> {
    let value = value.trim();
    if value.is_empty() {
        return Err(Error::BadRequest(format!("field `{field}` is empty")));
    }
    if value.chars().count() > MAX_ID || value.chars().any(char::is_control) {
        return Err(Error::BadRequest(format!(
            "field `{field}`: at most {MAX_ID} printable characters"
        )));
    }
    Ok(value)
}
