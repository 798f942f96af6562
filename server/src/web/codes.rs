//! Sign-in codes made in the background (`store::codes_jobs`): each is hashed with
//! Argon2id, about 0.1 s of CPU, so a large class's codes take minutes, longer than a
//! request may. Importing a roster and asking for new codes answer at once with where to
//! follow the job (`CodesStarted`); the job, on a blocking thread of the web process
//! asked, makes the codes under that process's lease and counts them; the instructor's
//! page reads how far it got and gets the codes file once, when it is made.

use super::viewer::Viewer;
use super::{AppState, Error, blocking};
use crate::courses::setup::{self, Setup};
use crate::store::Member;
use axum::Json;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use std::sync::Arc;
use ts_rs::TS;

/// How many codes are made between two counts (and renewals of the job's lease): about
/// 2.5 s of Argon2id, well within the lease.
const COUNTED_EVERY: usize = 25;

/// New sign-in codes, as the CSV a mail merge reads: handed over once, never stored
/// afterwards.
#[derive(Serialize, serde::Deserialize, TS)]
pub struct CodesFile {
    file_name: String,
    count: usize,
    csv: String,
}

/// Where to follow the making of new codes.
#[derive(Serialize, TS)]
pub struct CodesStarted {
    /// `GET` it for how far the making got, and the codes file once it is made.
    url: String,
    total: usize,
}

/// How far the making of codes got (`GET /api/courses/{course}/codes/{id}`).
#[derive(Serialize, TS)]
pub struct CodesProgress {
    total: usize,
    done: usize,
    /// The codes file, the first time it is asked for once they are made.
    file: Option<CodesFile>,
    /// Handed over before: the codes are not shown again (new ones can be made).
    fetched: bool,
    /// Why the making stopped before its end.
    failed: Option<String>,
}

/// Starts making codes for `students` of `course` (`reissued` of them had one before,
/// which stops working), as `viewer` asked; where to follow it.
pub(super) async fn start(
    state: &AppState,
    viewer: &Viewer,
    course: String,
    (students, reissued): (Vec<Member>, Vec<String>),
) -> Result<CodesStarted, Error> {
    viewer.instructor_of(&course)?;
    let grader = Arc::clone(&state.grader);
    let (actor, now, total) = (viewer.actor(), state.clock.now(), students.len());
    let job_course = course.clone();
    let id = blocking(state, move |store| {
        store.start_codes_job(&job_course, total, &grader.lease())
    })
    .await?;
    let grader = Arc::clone(&state.grader);
    let url = format!("/api/courses/{course}/codes/{id}");
    tokio::task::spawn_blocking(move || {
        let setup = Setup {
            store: grader.store(),
            course: &course,
            actor: &actor,
            now,
        };
        let mut made = |done: usize| {
            if done > 0
                && done.is_multiple_of(COUNTED_EVERY)
                && !grader.store().codes_job_made(id, done, &grader.lease())?
            {
                return Err(setup::Error::Invalid(
                    "this process's lease of the job was lost".to_owned(),
                ));
            }
            Ok(())
        };
        let file = codes_file(&setup, (&students, &reissued), &mut made)
            .map(|file| serde_json::to_string(&file).expect("a codes file serialises"));
        let ended = file.as_deref().map_err(ToString::to_string);
        if let Err(why) = &ended {
            tracing::error!(course, job = id, "making sign-in codes: {why}");
        }
        let ended = ended.as_deref().map_err(String::as_str);
        if let Err(err) = grader
            .store()
            .end_codes_job(id, ended, grader.lease().holder)
        {
            tracing::error!(course, job = id, "ending the job of sign-in codes: {err}");
        }
    });
    Ok(CodesStarted { url, total })
}

/// The codes of `students`, as a file named for the course and the moment.
fn codes_file(
    setup: &Setup,
    (students, reissued): (&[Member], &[String]),
    made: &mut dyn FnMut(usize) -> Result<(), setup::Error>,
) -> Result<CodesFile, setup::Error> {
    let url = setup::public_url(setup.store)?;
    let bytes = setup.codes(students, reissued, &url, made)?;
    Ok(CodesFile {
        file_name: format!(
            "{}-codes-{}.csv",
            setup.course,
            setup.now.strftime("%Y%m%dT%H%M%SZ")
        ),
        count: students.len(),
        csv: String::from_utf8(bytes).expect("the codes file is written from text"),
    })
}

/// `GET /api/courses/{course}/codes/{id}`: for the course's instructors, how far the
/// making of codes got, and the codes file the first time it is asked for once made.
pub async fn progress(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, id)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let missing = || Error::NotFound(format!("{course} has no job of codes {id:?}"));
    let number: i64 = id.parse().map_err(|_| missing())?;
    let now = jiff::Timestamp::now();
    let of = course.clone();
    let job = blocking(&state, move |store| store.take_codes_job(&of, number, now)).await?;
    let job = job.ok_or_else(missing)?;
    let file = job
        .file
        .map(|file| serde_json::from_str(&file))
        .transpose()
        .map_err(|e| crate::store::Error::Task(format!("a stored codes file: {e}")))?;
    Ok(Json(CodesProgress {
        total: job.total,
        done: job.done,
        file,
        fetched: job.fetched,
        failed: job.failed,
    })
    .into_response())
}
