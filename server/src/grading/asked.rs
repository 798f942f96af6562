//! Phases asked for interactively: one phase of an exercise's shown job run with a
//! student's file on the server (the workbench's Run tests, for a language the browser
//! cannot run), queued with the gradings in the one fair order of `fair` (the highest
//! lane, the student's share counted with their gradings') and answered to the request
//! that waits for it. A phase that has not started within the asker's patience leaves
//! the line, and the asker is told their place in it, rather than kept hanging.

use super::Grader;
use super::fair::{Tenant, Work};
use crate::sandbox::{Code, Failure, Tried};
use labs::grading::Outputs;
use labs::{Exercise, Language};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::oneshot;

/// A phase to run: the file, the variant and the phase (a function's name, or a run's).
pub struct PhaseAsked {
    pub exercise: Exercise,
    pub language: Language,
    pub source: String,
    pub seed: u64,
    pub phase: String,
}

/// A phase that did not start within its asker's patience: its place in line then (1:
/// it was next).
#[derive(Debug, PartialEq, Eq)]
pub struct Busy {
    pub place: usize,
}

/// A phase waiting for its turn, and where its start and its outcome go.
struct Pending {
    asked: PhaseAsked,
    started: oneshot::Sender<()>,
    outcome: oneshot::Sender<Result<Outputs, Tried>>,
}

/// The phases asked for and not started yet, by their number.
#[derive(Default)]
pub(super) struct Asked {
    next: AtomicU64,
    pending: Mutex<HashMap<u64, Pending>>,
}

impl Asked {
    fn pending(&self) -> MutexGuard<'_, HashMap<u64, Pending>> {
        // Inserts and removes never panic halfway; a poisoned map is still whole.
        self.pending.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Takes a phase out of the line when its asker stops waiting before it started (a
/// request given up, or past its patience).
struct Waiting<'a> {
    grader: &'a Grader,
    number: u64,
}

impl Waiting<'_> {
    /// Takes the phase out of the line if it has not started; its place when it had not.
    fn give_up(&self) -> Option<usize> {
        let work = Work::Phase(self.number);
        let mut queue = self.grader.queue();
        let place = queue.place(work, Instant::now());
        let cancelled = queue.cancel(work);
        drop(queue);
        self.grader.asked.pending().remove(&self.number);
        cancelled.then(|| place.unwrap_or(1))
    }
}

impl Drop for Waiting<'_> {
    fn drop(&mut self) {
        self.give_up();
    }
}

impl Grader {
    /// Runs `asked` for `tenant` in its turn, and gives its outcome; or, when it has not
    /// started within `patience`, its place in line (it leaves the line).
    pub async fn phase(
        self: &Arc<Self>,
        tenant: Tenant,
        asked: PhaseAsked,
        patience: Duration,
    ) -> Result<Result<Outputs, Tried>, Busy> {
        let number = self.asked.next.fetch_add(1, Ordering::SeqCst);
        let (started, start) = oneshot::channel();
        let (outcome, answer) = oneshot::channel();
        self.asked.pending().insert(
            number,
            Pending {
                asked,
                started,
                outcome,
            },
        );
        let waiting = Waiting {
            grader: self,
            number,
        };
        self.start_dispatching();
        self.enqueue(Work::Phase(number), tenant);
        if tokio::time::timeout(patience, start).await.is_err()
            && let Some(place) = waiting.give_up()
        {
            return Err(Busy { place });
        }
        // It started (or has just started): it runs to its end.
        Ok(answer
            .await
            .unwrap_or(Err(Tried::Failed(Failure::Panicked))))
    }

    /// Runs the phase numbered `number`, on the thread that takes its turn, unless its
    /// asker gave up.
    pub(super) fn run_asked(&self, number: u64) {
        let Some(pending) = self.asked.pending().remove(&number) else {
            return;
        };
        // The asker may have given up since: the outcome then goes unread.
        let _ = pending.started.send(());
        let asked = pending.asked;
        let code = Code {
            language: asked.language,
            text: &asked.source,
        };
        let outcome = self
            .sandbox()
            .phase(asked.exercise, code, asked.seed, &asked.phase);
        let _ = pending.outcome.send(outcome);
    }
}
