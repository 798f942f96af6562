//! Work asked of the sandbox by a request rather than stored: a phase of an exercise's
//! shown job run with a student's file (the workbench's Run tests, for a language the
//! browser cannot run), and the whole runs of a student's report. Each is queued with the
//! gradings in the one fair order of `fair` (a phase in the highest lane, report runs
//! below gradings; the student's share counted with their gradings') and its outcome
//! handed to whoever waits for it. A phase that has not started within its asker's
//! patience leaves the line, and the asker is told their place in it, rather than kept
//! hanging.

use super::Grader;
use super::fair::{Tenant, Work};
use crate::sandbox::{Code, Failure, Sandbox, Tried};
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

/// What a job does with the sandbox once its turn comes, handing its outcome on itself.
type Job = Box<dyn FnOnce(&Sandbox) + Send>;

/// A job waiting for its turn, and where its start is said.
struct Pending {
    job: Job,
    started: oneshot::Sender<()>,
}

/// The jobs asked for and not started yet, by their number.
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

/// Takes a job out of the line when whoever waits for it stops before it started (a
/// request given up, or past its patience).
struct Waiting<'a> {
    grader: &'a Grader,
    work: Work,
    number: u64,
}

impl Waiting<'_> {
    /// Takes the job out of the line if it has not started; its place when it had not.
    fn give_up(&self) -> Option<usize> {
        let mut queue = self.grader.queue();
        let place = queue.place(self.work, Instant::now());
        let cancelled = queue.cancel(self.work);
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
        let job = move |sandbox: &Sandbox| {
            let code = Code {
                language: asked.language,
                text: &asked.source,
            };
            sandbox.phase(asked.exercise, code, asked.seed, &asked.phase)
        };
        self.in_turn(Work::Phase, tenant, Some(patience), job).await
    }

    /// Runs the runs `runs` of `exercise` (by name) on the whole of their data sets with
    /// `source` for `tenant`, in its turn: what a student's report draws.
    pub async fn report_runs(
        self: &Arc<Self>,
        tenant: Tenant,
        exercise: Exercise,
        (language, source): (Language, String),
        seed: u64,
        runs: Vec<&'static str>,
    ) -> Result<Outputs, Tried> {
        let job = move |sandbox: &Sandbox| {
            let code = Code {
                language,
                text: &source,
            };
            sandbox.whole_runs(exercise, code, seed, &runs)
        };
        match self.in_turn(Work::ReportRuns, tenant, None, job).await {
            Ok(outcome) => outcome,
            Err(Busy { .. }) => unreachable!("a job without patience waits its turn"),
        }
    }

    /// Queues `job` as the work `kind` of a new number for `tenant`, and gives its outcome
    /// once it has run; or, when it has not started within `patience`, its place in line.
    async fn in_turn<T: Send + 'static>(
        self: &Arc<Self>,
        kind: fn(u64) -> Work,
        tenant: Tenant,
        patience: Option<Duration>,
        job: impl FnOnce(&Sandbox) -> Result<T, Tried> + Send + 'static,
    ) -> Result<Result<T, Tried>, Busy> {
        let number = self.asked.next.fetch_add(1, Ordering::SeqCst);
        let work = kind(number);
        let (started, start) = oneshot::channel();
        let (outcome, answer) = oneshot::channel();
        let job: Job = Box::new(move |sandbox| {
            // Whoever waited may have gone since: the outcome then goes unread.
            let _ = outcome.send(job(sandbox));
        });
        self.asked
            .pending()
            .insert(number, Pending { job, started });
        let waiting = Waiting {
            grader: self,
            work,
            number,
        };
        self.start_dispatching();
        self.enqueue(work, tenant);
        if let Some(patience) = patience
            && tokio::time::timeout(patience, start).await.is_err()
            && let Some(place) = waiting.give_up()
        {
            return Err(Busy { place });
        }
        // It started, or will: it runs to its end.
        Ok(answer
            .await
            .unwrap_or(Err(Tried::Failed(Failure::Panicked))))
    }

    /// Runs the job numbered `number`, on the thread that takes its turn, unless whoever
    /// waited for it gave up.
    pub(super) fn run_asked(&self, number: u64) {
        let Some(pending) = self.asked.pending().remove(&number) else {
            return;
        };
        let _ = pending.started.send(());
        (pending.job)(self.sandbox());
    }
}
