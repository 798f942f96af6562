//! `POST /api/phases`: one phase of an exercise's shown job (a function's tests, a run of
//! its loop) carried out on the server with the student's file, for the workbench of a
//! language the browser cannot run (Python): the answer is the phase's output, which the
//! browser grades and shows exactly as it does the outputs of its own Web Worker. Nothing
//! is stored and nothing is graded here, and only the shown cases run (the variant's
//! seed is the asker's to say; the hidden cases are the submission's).
//!
//! Who may: on a server with courses, whoever is signed in (staff try files too) but a
//! student dropped from the roster; on a server without, anyone. Each asker (a member, or an address's block when nobody is
//! signed in) may run [`PER_MINUTE`] phases a minute, and the server runs at most as many
//! at once as it grades in the foreground, so that trying files never starves grading.

use super::address::block;
use super::extract::{Body, ClientAddress};
use super::submit::language_field;
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::sandbox::{Code, Tried, check_size};
use crate::store::Window;
use axum::Json;
use axum::extract::State;
use jiff::{SignedDuration, Timestamp};
use labs::grading::Outputs;
use serde::Deserialize;
use std::sync::Arc;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};

/// Phases one asker may run in a minute: a whole run of the tests and of the loop, four
/// times (the CPU they take is held by `--parallel` besides).
pub const PER_MINUTE: usize = 60;
const PHASES: Window = Window {
    scope: "phase",
    share: PER_MINUTE,
    length: SignedDuration::from_mins(1),
};

/// The body of `POST /api/phases`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ask {
    lab: String,
    #[serde(default)]
    language: Option<String>,
    /// The variant whose shown cases run.
    seed: u64,
    /// The function whose tests run, or the run's name (`o3/sequential`).
    phase: String,
    source: String,
}

/// The phases running at once, as this process bounds them (the CPU is its machine's).
pub struct Trials {
    running: Arc<Semaphore>,
}

impl Trials {
    /// At most `parallel` phases at once.
    pub fn new(parallel: usize) -> Trials {
        Trials {
            running: Arc::new(Semaphore::new(parallel.max(1))),
        }
    }

    /// A place among the phases running at once, held until it is dropped: waits for one.
    pub async fn slot(&self) -> Result<OwnedSemaphorePermit, Error> {
        Arc::clone(&self.running)
            .acquire_owned()
            .await
            .map_err(|e| crate::store::Error::Task(e.to_string()).into())
    }
}

/// Counts a phase of `asker` at `now` (in the database: every web process counts the
/// same), or says when the next one is let.
async fn admit(state: &Arc<AppState>, asker: String, now: Timestamp) -> Result<(), Error> {
    let counted = blocking(state, move |store| store.count_event(&PHASES, &asker, now)).await?;
    counted.map_err(|free_at| {
        Error::TooManyRequests(format!(
            "you have run {PER_MINUTE} tests or runs on the server in the last minute, the most it takes: try again in {} s",
            free_at.duration_since(now).as_secs().max(1)
        ))
    })?;
    Ok(())
}

pub async fn run(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    ClientAddress(address): ClientAddress,
    body: Body,
) -> Result<Json<Outputs>, Error> {
    let courses = blocking(&state, |store| store.any_course()).await?;
    let asker = match &viewer {
        Viewer::Member(member) if member.dropped && !member.role.is_staff() => {
            return Err(Error::Forbidden(format!(
                "you are no longer on the roster of {}: your files run on the server no more \
                 (Run tests in JavaScript runs in your browser); ask your teacher",
                member.course
            )));
        }
        Viewer::Member(member) => format!("member {}", member.id),
        Viewer::Token(_) => {
            return Err(Error::Forbidden(
                "an API token reads a course; it runs no student's file".into(),
            ));
        }
        Viewer::Anonymous if courses => {
            return Err(Error::Unauthorized(
                "sign in to run your file on the server: this server runs courses".into(),
            ));
        }
        Viewer::Anonymous => format!("address {}", block(address)),
    };
    let ask: Ask = body.json(&viewer, "the body").await?;
    let exercise = lab_field(&ask.lab)?;
    let language = language_field(ask.language.as_deref())?;
    check_size(&ask.source)
        .map_err(|problem| Error::TooLarge(format!("field `source`: {problem}")))?;
    admit(&state, asker, state.clock.now()).await?;
    let _running = state.trials.slot().await?;
    let grader = Arc::clone(&state.grader);
    let tried = tokio::task::spawn_blocking(move || {
        let code = Code {
            language,
            text: &ask.source,
        };
        grader.sandbox().phase(exercise, code, ask.seed, &ask.phase)
    })
    .await
    .map_err(|e| crate::store::Error::Task(e.to_string()))?;
    tried.map(Json).map_err(|tried| match tried {
        Tried::NoSuchPhase(_) => Error::BadRequest(format!("field `phase`: {tried}")),
        Tried::Unavailable(_) => Error::Unavailable(format!(
            "field `language`: {} files cannot be run on this server: its sandbox for them does not start on this machine (the server's log says why)",
            language.title()
        )),
        Tried::DidNotStart(_) | Tried::Failed(_) => {
            tracing::warn!(%tried, "a phase tried on the server failed");
            Error::Unavailable(format!(
                "the server's sandbox failed ({tried}): not your code's doing; try again"
            ))
        }
    })
}
