//! `POST /api/phases`: one phase of an exercise's shown job (a function's tests, a run of
//! its loop) carried out on the server with the student's file, for the workbench of a
//! language the browser cannot run (Python): the answer is the phase's output, which the
//! browser grades and shows exactly as it does the outputs of its own Web Worker. Nothing
//! is stored and nothing is graded here, and only the shown cases run (the variant's
//! seed is the asker's to say; the hidden cases are the submission's).
//!
//! Who may: on a server with courses, whoever is signed in (staff try files too) but a
//! student dropped from the roster; on a server without, anyone. Each asker (a member,
//! or an address's block when nobody is signed in) may run [`PER_MINUTE`] phases a
//! minute. The phase takes its turn with the process's gradings (`grading::Grader::phase`):
//! the highest lane, its asker's share counted with their gradings', so that neither
//! trying files nor one student's endless loops starve anybody; one that has not started
//! within [`PATIENCE`] is taken out of the line and the asker told their place in it.

use super::address::block;
use super::extract::{Body, ClientAddress};
use super::submit::language_field;
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::grading::{Busy, PhaseAsked, Tenant};
use crate::sandbox::{Tried, check_size};
use crate::store::Window;
use axum::Json;
use axum::extract::State;
use jiff::{SignedDuration, Timestamp};
use labs::grading::Outputs;
use serde::Deserialize;
use std::sync::Arc;
use std::time::Duration;

/// Phases one asker may run in a minute: a whole run of the tests and of the loop, four
/// times.
pub const PER_MINUTE: usize = 60;
const PHASES: Window = Window {
    scope: "phase",
    share: PER_MINUTE,
    length: SignedDuration::from_mins(1),
};

/// How long a phase waits for its turn before its asker is told the server is busy: long
/// enough for a few gradings ahead of it, short of what a person waits for a button.
pub const PATIENCE: Duration = Duration::from_secs(20);

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
    let (asker, tenant) = match &viewer {
        Viewer::Member(member) if member.dropped && !member.role.is_staff() => {
            return Err(Error::Forbidden(format!(
                "you are no longer on the roster of {}: your files run on the server no more \
                 (Run tests in JavaScript runs in your browser); ask your teacher",
                member.course
            )));
        }
        Viewer::Member(member) => (
            format!("member {}", member.id),
            Tenant::Student {
                course: member.course.clone(),
                student: member.login.clone(),
            },
        ),
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
        Viewer::Anonymous => {
            let block = block(address);
            (
                format!("address {block}"),
                Tenant::Address(block.to_string()),
            )
        }
    };
    let ask: Ask = body.json(&viewer, "the body").await?;
    let exercise = lab_field(&ask.lab)?;
    let language = language_field(ask.language.as_deref())?;
    check_size(&ask.source)
        .map_err(|problem| Error::TooLarge(format!("field `source`: {problem}")))?;
    admit(&state, asker, state.clock.now()).await?;
    let asked = PhaseAsked {
        exercise,
        language,
        source: ask.source,
        seed: ask.seed,
        phase: ask.phase,
    };
    let tried = state
        .grader
        .phase(tenant, asked, PATIENCE)
        .await
        .map_err(|Busy { place }| {
            Error::Unavailable(format!(
                "the server is busy: your run waited {} s and was {} in line for a sandbox; \
                 try again in a minute (your code was not run)",
                PATIENCE.as_secs(),
                ordinal(place)
            ))
        })?;
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

/// 1st, 2nd, 3rd, 4th, ..., 11th, 12th, 13th, 21st.
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

#[cfg(test)]
mod tests {
    use super::ordinal;

    #[test]
    fn places_read_as_english_ordinals() {
        let said: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 102, 111]
            .map(ordinal)
            .into();
        assert_eq!(
            said,
            [
                "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "102nd",
                "111th"
            ]
        );
    }
}
