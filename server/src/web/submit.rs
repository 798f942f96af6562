//! Taking a submission: who submits (the signed-in student, as their course's policy
//! allows; on a server without courses, whoever the body names), the checks of what is
//! sent, and its storing with its grading queued. `POST /api/submissions` is a thin
//! handler over [`accept`].

use super::{AppState, Error, blocking, lab_field};
use crate::courses::deadline::Timing;
use crate::sandbox::check_size;
use crate::store::{Member, NewSubmission};
use jiff::Timestamp;
use labs::grading::{DEFAULT_COURSE, student_seed};
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use ts_rs::TS;

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
pub struct Submit {
    student: Option<String>,
    course: Option<String>,
    #[serde(default = "super::default_lab")]
    lab: String,
    /// The file's language, by its name: `javascript` (the default) or `python`.
    #[serde(default)]
    language: Option<String>,
    source: String,
}

/// The answer to a submission taken.
#[derive(Serialize, TS)]
pub struct Accepted {
    id: i64,
    seed: u64,
    status: &'static str,
    pub url: String,
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

/// Stores a submission of `member` (or, on a server without courses, of whoever it names)
/// and queues its grading: what it was taken as, or why it was refused.
pub async fn accept(
    state: &Arc<AppState>,
    member: Option<&Member>,
    submit: Submit,
) -> Result<Accepted, Error> {
    let exercise = lab_field(&submit.lab)?;
    let language = language_field(submit.language.as_deref())?;
    check_size(&submit.source)
        .map_err(|problem| Error::TooLarge(format!("field `source`: {problem}")))?;
    let grader = Arc::clone(&state.grader);
    tokio::task::spawn_blocking(move || grader.sandbox().language(language))
        .await
        .map_err(|e| crate::store::Error::Task(e.to_string()))?
        .map_err(|_| {
            Error::Unavailable(format!(
                "field `language`: {} files cannot be graded on this server: its sandbox for them does not start on this machine (the server's log says why)",
                language.title()
            ))
        })?;
    let now = state.clock.now();
    let submitter = match member {
        Some(member) => as_member(state, member, &submit, (exercise, language), now).await?,
        None => as_named(&submit)?,
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
            lab: exercise,
            seed,
            language,
            source: &source,
            submitted_at: now,
            late_seconds,
            penalty,
            grader: grader.version(exercise),
        })
    })
    .await
    .map_err(|e| crate::store::Error::Task(e.to_string()))??;
    tracing::info!(submission = id, late_seconds, "submitted");
    Ok(Accepted {
        id,
        seed,
        status: "queued",
        url: format!("/api/submissions/{id}"),
        late_seconds,
        penalty,
    })
}

/// The signed-in student as the submitter, if their course's policy takes the submission
/// now (opened, in a language it takes, within the cutoff, under the hourly limit), with
/// its lateness.
async fn as_member(
    state: &Arc<AppState>,
    member: &Member,
    submit: &Submit,
    (exercise, language): (Exercise, Language),
    now: Timestamp,
) -> Result<Submitter, Error> {
    for (field, given) in [("student", &submit.student), ("course", &submit.course)] {
        if given.is_some() {
            return Err(Error::BadRequest(format!(
                "field `{field}`: you submit as the signed-in student; leave it out"
            )));
        }
    }
    let lab = exercise;
    let course = member.course.clone();
    let id = member.id;
    let hour_ago = now - jiff::SignedDuration::from_hours(1);
    let (recent, policy, assignment) = blocking(state, move |store| {
        Ok((
            store.submitted_since(id, lab, hour_ago)?,
            store.policy_for(&course, lab, id)?,
            store.assignment(&course, lab)?,
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
    let taken = assignment.map(|a| a.languages).unwrap_or_default();
    if !taken.contains(&language) {
        let names: Vec<&str> = taken.iter().map(|l| l.title()).collect();
        return Err(Error::Forbidden(format!(
            "field `language`: your course takes files of {exercise} in {} only",
            names.join(" and ")
        )));
    }
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
    Ok(Submitter {
        course: member.course.clone(),
        student: member.login.clone(),
        member: Some(member.id),
        late_seconds,
        penalty,
    })
}

/// On a server without courses: whoever the body names, in the course it names (the
/// default one unless it names one), on time.
fn as_named(submit: &Submit) -> Result<Submitter, Error> {
    let student = submit.student.as_deref().ok_or_else(|| {
        Error::BadRequest(
            "missing field `student` (this server has no courses: say who submits)".into(),
        )
    })?;
    Ok(Submitter {
        course: id_field("course", submit.course.as_deref().unwrap_or(DEFAULT_COURSE))?.to_string(),
        student: id_field("student", student)?.to_string(),
        member: None,
        late_seconds: 0,
        penalty: 0.0,
    })
}

/// The language a request's `language` field names (JavaScript when it names none).
pub fn language_field(language: Option<&str>) -> Result<Language, Error> {
    language.map_or(Ok(Language::JavaScript), |name| {
        name.parse()
            .map_err(|unknown| Error::BadRequest(format!("field `language`: {unknown}")))
    })
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
