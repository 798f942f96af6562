//! Grading of stored submissions in the background: each in a blocking task that waits
//! for its sandbox worker process, at most `parallel` at once, so that the server's
//! other requests are answered meanwhile. Regrades go through the same permits, one item
//! at a time, so that a regrade of a whole class never holds up a student's submission
//! by more than one grading.

use super::{Secret, grader_version};
use crate::clock::Clock;
use crate::sandbox::Sandbox;
use crate::store::{Error, NewSubmission, Store};
use labs::Exercise;
use std::sync::Arc;
use std::time::Instant;
use tokio::sync::{Notify, Semaphore};

/// Stores submissions and grades them.
pub struct Grader {
    store: Store,
    sandbox: Sandbox,
    /// Draws every submission's hidden cases.
    secret: Secret,
    permits: Semaphore,
    /// Which grader grades each exercise (in the order of `Exercise::ALL`): the release and
    /// a hash of what it grades (see `version`).
    versions: [String; Exercise::ALL.len()],
    /// Wakes the regrade loop when a regrade starts.
    regrades: Notify,
    clock: Arc<dyn Clock>,
}

impl Grader {
    /// A grader over `store` running at most `parallel` sandboxes at once.
    pub fn new(
        store: Store,
        sandbox: Sandbox,
        secret: Secret,
        parallel: usize,
        clock: Arc<dyn Clock>,
    ) -> Arc<Grader> {
        Arc::new(Grader {
            versions: Exercise::ALL.map(|exercise| grader_version(exercise, Some(&secret))),
            store,
            sandbox,
            secret,
            permits: Semaphore::new(parallel.max(1)),
            regrades: Notify::new(),
            clock,
        })
    }

    pub fn store(&self) -> &Store {
        &self.store
    }

    /// The version of an exercise's grader, which its results name.
    pub fn version(&self, exercise: Exercise) -> &str {
        let index = Exercise::ALL
            .iter()
            .position(|e| *e == exercise)
            .expect("every exercise is in Exercise::ALL");
        &self.versions[index]
    }

    /// Stores a submission, then queues its grading; returns its id once it is stored.
    pub fn submit(self: &Arc<Self>, new: &NewSubmission) -> Result<i64, Error> {
        let id = self.store.insert(new)?;
        self.queue(id);
        Ok(id)
    }

    /// Queues every submission whose grading a stop cut off and starts the regrade loop
    /// (which resumes any regrade a stop cut off); returns how many submissions.
    pub fn resume(self: &Arc<Self>) -> Result<usize, Error> {
        let ids = self.store.unfinished()?;
        for &id in &ids {
            self.queue(id);
        }
        let grader = Arc::clone(self);
        tokio::spawn(async move { grader.regrade_loop().await });
        Ok(ids.len())
    }

    /// Tells the regrade loop that a regrade has started.
    pub fn regrade_started(&self) {
        self.regrades.notify_one();
    }

    fn queue(self: &Arc<Self>, id: i64) {
        let grader = Arc::clone(self);
        tokio::spawn(async move {
            let _permit = grader
                .permits
                .acquire()
                .await
                .expect("the semaphore stays open");
            let worker = Arc::clone(&grader);
            let graded = tokio::task::spawn_blocking(move || worker.grade(id)).await;
            let failure = match graded {
                Ok(Ok(())) => return,
                Ok(Err(err)) => format!("grading submission {id}: {err}"),
                Err(err) => format!("grading submission {id} stopped: {err}"),
            };
            tracing::error!("{failure}");
            // The submission is not left waiting, which would refuse the student's next
            // one: it ends "not gradable", which costs them nothing.
            let store = Arc::clone(&grader);
            let ended = tokio::task::spawn_blocking(move || {
                store
                    .store
                    .give_up(id, "the server could not grade it; submit again")
            })
            .await;
            if let Ok(Err(err)) = ended {
                tracing::error!("submission {id} could not be marked as not gradable: {err}");
            }
        });
    }

    fn grade(&self, id: i64) -> Result<(), Error> {
        let started = Instant::now();
        let job = self.store.start_grading(id)?;
        let hidden = self.secret.hidden_seed(id);
        let result = self
            .sandbox
            .grade(job.exercise, &job.source, job.seed, Some(hidden));
        let score = result.gradable.then_some(result.score);
        self.store
            .finish_grading(id, &result.stored(), Some(self.version(job.exercise)))?;
        tracing::info!(
            submission = id,
            course = job.course,
            student = job.student,
            duration_ms = started.elapsed().as_millis() as u64,
            score,
            "graded"
        );
        Ok(())
    }

    /// Regrades item after item, oldest regrade first, for as long as the server runs.
    async fn regrade_loop(self: Arc<Self>) {
        loop {
            let store = Arc::clone(&self);
            let next = tokio::task::spawn_blocking(move || store.store.next_regrade_item()).await;
            let (regrade, submission) = match next {
                Ok(Ok(Some(item))) => item,
                Ok(Ok(None)) => {
                    self.regrades.notified().await;
                    continue;
                }
                Ok(Err(err)) => {
                    tracing::error!("regrading: {err}");
                    self.regrades.notified().await;
                    continue;
                }
                Err(err) => {
                    tracing::error!("regrading stopped: {err}");
                    return;
                }
            };
            let _permit = self
                .permits
                .acquire()
                .await
                .expect("the semaphore stays open");
            let worker = Arc::clone(&self);
            let done =
                tokio::task::spawn_blocking(move || worker.regrade(regrade, submission)).await;
            if let Ok(Err(err)) | Err(err) = done.map_err(|e| Error::Task(e.to_string())) {
                // The database failed (the sandbox's failures are results): the item stays
                // waiting, tried again at the next regrade or start rather than in a spin.
                tracing::error!("regrading submission {submission}: {err}");
                self.regrades.notified().await;
            }
        }
    }

    fn regrade(&self, regrade: i64, submission: i64) -> Result<(), Error> {
        let started = Instant::now();
        // Its status stays graded: the student may go on submitting meanwhile.
        let job = self.store.to_grade(submission)?;
        let hidden = self.secret.hidden_seed(submission);
        let result = self
            .sandbox
            .grade(job.exercise, &job.source, job.seed, Some(hidden));
        let score = result.gradable.then_some(result.score);
        self.store.finish_regrade_item(
            regrade,
            submission,
            &result.stored(),
            self.version(job.exercise),
            self.clock.now(),
        )?;
        tracing::info!(
            regrade,
            submission,
            course = job.course,
            student = job.student,
            duration_ms = started.elapsed().as_millis() as u64,
            score,
            "regraded"
        );
        Ok(())
    }
}
