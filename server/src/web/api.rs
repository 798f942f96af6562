//! The JSON API: submitting code for grading, reading a submission, and (for a course's
//! staff) its people and their submissions.
//!
//! On a server without courses anyone may submit under any student id and read any
//! submission's result (a quick demo; the pages say so). Once a course exists, only a
//! signed-in student submits, as themselves, to an exercise their course has opened; a
//! submission is read by its student and their course's staff, and by nobody else:
//! someone else's submission answers 404 exactly as one that does not exist.

use super::extract::{Body, Query};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::courses::deadline::Timing;
use crate::sandbox::check_size;
use crate::store::{Member, NewSubmission};
use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use labs::grading::{DEFAULT_COURSE, student_seed};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Submissions a student may make to an exercise in an hour: plenty for work (tests run
/// in the browser for free), and a bound on what one student takes of the grading and
/// the disk.
const PER_HOUR: usize = 20;

/// The longest student or course id accepted.
const MAX_ID: usize = 100;

/// The body of `POST /api/submissions`. `student` and `course` are for a server without
/// courses only: with courses, the signed-in student is who submits.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Submit {
    student: Option<String>,
    course: Option<String>,
    #[serde(default = "super::default_lab")]
    lab: String,
    source: String,
}

/// The answer to a submission taken.
#[derive(Serialize)]
struct Accepted {
    id: i64,
    seed: u64,
    status: &'static str,
    url: String,
    /// Late by this much (0: on time), and the share of the score that costs.
    late_seconds: i64,
    penalty: f64,
}

/// Who submits, once the request and the viewer are checked.
struct Submitter {
    course: String,
    student: String,
    member: Option<i64>,
    late_seconds: i64,
    penalty: f64,
}

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
    let submit: Submit = body.json(&viewer, "the submission body").await?;
    let exercise = lab_field(&submit.lab)?;
    check_size(&submit.source)
        .map_err(|problem| Error::TooLarge(format!("field `source`: {problem}")))?;
    let now = state.clock.now();
    let submitter = if let Some(member) = member {
        for (field, given) in [("student", &submit.student), ("course", &submit.course)] {
            if given.is_some() {
                return Err(Error::BadRequest(format!(
                    "field `{field}`: you submit as the signed-in student; leave it out"
                )));
            }
        }
        let lab = exercise.name();
        let course = member.course.clone();
        let id = member.id;
        let hour_ago = now - jiff::SignedDuration::from_hours(1);
        let (recent, policy) = blocking(&state, move |store| {
            Ok((
                store.submitted_since(id, lab, hour_ago)?,
                store.policy_for(&course, lab, id)?,
            ))
        })
        .await?;
        if recent >= PER_HOUR {
            return Err(Error::TooManyRequests(format!(
                "you have submitted {recent} times in the last hour, the most this server takes: submit again later (Run tests checks your file in the browser meanwhile)"
            )));
        }
        let policy = policy.ok_or_else(|| {
            Error::Forbidden(format!(
                "your course has not opened the exercise {exercise}"
            ))
        })?;
        let (late_seconds, penalty) = match policy.timing(now) {
            Timing::OnTime => (0, 0.0),
            Timing::Late { seconds, penalty } => (seconds, penalty),
            Timing::Closed => {
                return Err(Error::Forbidden(format!(
                    "the cutoff of this exercise was {}: no more submissions are taken. Your file is still in the editor; keep a copy with Download.",
                    policy.cutoff.strftime("%Y-%m-%d %H:%M UTC")
                )));
            }
        };
        Submitter {
            course: member.course.clone(),
            student: member.login.clone(),
            member: Some(member.id),
            late_seconds,
            penalty,
        }
    } else {
        let student = submit.student.as_deref().ok_or_else(|| {
            Error::BadRequest(
                "missing field `student` (this server has no courses: say who submits)".into(),
            )
        })?;
        Submitter {
            course: id_field("course", submit.course.as_deref().unwrap_or(DEFAULT_COURSE))?
                .to_string(),
            student: id_field("student", student)?.to_string(),
            member: None,
            late_seconds: 0,
            penalty: 0.0,
        }
    };
    let seed = student_seed(&submitter.course, &submitter.student);
    let grader = Arc::clone(&state.grader);
    let source = submit.source;
    let (late_seconds, penalty) = (submitter.late_seconds, submitter.penalty);
    let id = tokio::task::spawn_blocking(move || {
        grader.submit(&NewSubmission {
            course: &submitter.course,
            student: &submitter.student,
            member: submitter.member,
            lab: exercise.name(),
            seed,
            source: &source,
            submitted_at: now,
            late_seconds,
            penalty,
        })
    })
    .await
    .map_err(|e| crate::store::Error::Task(e.to_string()))??;
    tracing::info!(submission = id, late_seconds, "submitted");
    let url = format!("/api/submissions/{id}");
    Ok((
        StatusCode::ACCEPTED,
        [(axum::http::header::LOCATION, url.clone())],
        Json(Accepted {
            id,
            seed,
            status: "queued",
            url,
            late_seconds,
            penalty,
        }),
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
    let submission = blocking(&state, move |store| {
        store
            .get(number, courses)?
            .map(|submission| {
                Ok::<_, crate::store::Error>(crate::store::Submission {
                    earlier: store.earlier_results(number)?,
                    ..submission
                })
            })
            .transpose()
    })
    .await?;
    let submission = submission.ok_or_else(missing)?;
    Ok(Json(submission).into_response())
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
    let list = blocking(&state, move |store| {
        store.course_submissions(&name, lab.name())
    })
    .await?;
    Ok(Json(list).into_response())
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
