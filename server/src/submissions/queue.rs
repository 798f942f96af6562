//! Grading of stored submissions in the background: each in a blocking task that waits
//! for its sandbox worker process, at most `parallel` at once, so that the server's
//! other requests are answered meanwhile.

use super::Secret;
use crate::sandbox::Sandbox;
use crate::store::{Error, NewSubmission, Store};
use std::sync::Arc;
use std::time::Instant;
use tokio::sync::Semaphore;

/// Stores submissions and grades them.
pub struct Grader {
    store: Store,
    sandbox: Sandbox,
    /// Draws every submission's hidden cases.
    secret: Secret,
    permits: Semaphore,
}

impl Grader {
    /// A grader over `store` running at most `parallel` sandboxes at once.
    pub fn new(store: Store, sandbox: Sandbox, secret: Secret, parallel: usize) -> Arc<Grader> {
        Arc::new(Grader {
            store,
            sandbox,
            secret,
            permits: Semaphore::new(parallel.max(1)),
        })
    }

    pub fn store(&self) -> &Store {
        &self.store
    }

    /// Stores a submission, then queues its grading; returns its id once it is stored.
    pub fn submit(self: &Arc<Self>, new: &NewSubmission) -> Result<i64, Error> {
        let id = self.store.insert(new)?;
        self.queue(id);
        Ok(id)
    }

    /// Queues every submission whose grading a stop cut off; returns how many.
    pub fn resume(self: &Arc<Self>) -> Result<usize, Error> {
        let ids = self.store.unfinished()?;
        for &id in &ids {
            self.queue(id);
        }
        Ok(ids.len())
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
        let result = self.sandbox.grade(&job.source, job.seed, Some(hidden));
        let score = result.gradable.then_some(result.score);
        self.store.finish_grading(id, &result.stored())?;
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
}
