//! Grading of stored submissions in the background, in the order `fair` keeps: students
//! take turns, a student whose gradings run long is graded behind the others and in the
//! background lane, and regrades take their turn as one more student, item by item. One
//! dispatcher task starts each grading in a blocking task that waits for its sandbox
//! worker process, so that the server's other requests are answered meanwhile. A grading
//! whose sandbox did not start waits and is tried again: a fault of the server's own
//! never becomes a student's result.

use super::fair::{FairQueue, Lane, Policy, Tenant, Ticket, Waiting, Work};
use super::{Secret, grader_version, priority};
use crate::clock::Clock;
use crate::sandbox::{Code, DidNotStart, Sandbox};
use crate::store::{Error, NewSubmission, Store, ToGrade};
use labs::Exercise;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::Notify;

/// How often a background grading's worker is looked for and lowered in priority.
const SWEEP: Duration = Duration::from_millis(100);

/// Stores submissions and grades them.
pub struct Grader {
    store: Store,
    sandbox: Sandbox,
    /// Draws every submission's hidden cases.
    secret: Secret,
    /// Which grader grades each exercise (in the order of `Exercise::ALL`): the release and
    /// a hash of what it grades (see `version`).
    versions: Vec<String>,
    queue: Mutex<FairQueue>,
    /// Wakes the dispatcher: a grading arrived, ended or moved to the background, or a
    /// regrade started.
    wake: Notify,
    /// Whether the regrades may have an item for the queue (set when a regrade starts and
    /// when an item is done).
    regrades_pending: AtomicBool,
    clock: Arc<dyn Clock>,
}

/// Why a grading ended without a result stored.
enum Failure {
    /// The sandbox did not start: the grading waits and is tried again.
    DidNotStart(DidNotStart),
    Store(Error),
}

impl From<Error> for Failure {
    fn from(err: Error) -> Failure {
        Failure::Store(err)
    }
}

impl Grader {
    /// A grader over `store` running at most `parallel` sandboxes at once in the
    /// foreground (`Policy::new`).
    pub fn new(
        store: Store,
        sandbox: Sandbox,
        secret: Secret,
        parallel: usize,
        clock: Arc<dyn Clock>,
    ) -> Arc<Grader> {
        Grader::with_policy(store, sandbox, secret, Policy::new(parallel), clock)
    }

    /// A grader whose order follows `policy` (the tests set its thresholds).
    pub fn with_policy(
        store: Store,
        sandbox: Sandbox,
        secret: Secret,
        policy: Policy,
        clock: Arc<dyn Clock>,
    ) -> Arc<Grader> {
        Arc::new(Grader {
            versions: Exercise::ALL
                .iter()
                .map(|&exercise| grader_version(exercise, Some(&secret)))
                .collect(),
            store,
            sandbox,
            secret,
            queue: Mutex::new(FairQueue::new(policy)),
            wake: Notify::new(),
            regrades_pending: AtomicBool::new(false),
            clock,
        })
    }

    pub fn store(&self) -> &Store {
        &self.store
    }

    /// The sandbox it grades in (which also runs the workbench's phases on the server).
    pub fn sandbox(&self) -> &Sandbox {
        &self.sandbox
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
    pub fn submit(&self, new: &NewSubmission) -> Result<i64, Error> {
        let id = self.store.insert(new)?;
        self.enqueue(Work::Submission(id), student(new.course, new.student));
        Ok(id)
    }

    /// Queues every submission whose grading a stop cut off and starts grading (which
    /// resumes any regrade a stop cut off); returns how many submissions.
    pub fn resume(self: &Arc<Self>) -> Result<usize, Error> {
        let unfinished = self.store.unfinished()?;
        {
            let mut queue = self.queue();
            for waiting in &unfinished {
                queue.push(
                    Work::Submission(waiting.id),
                    student(&waiting.course, &waiting.student),
                );
            }
        }
        self.regrades_pending.store(true, Ordering::SeqCst);
        tokio::spawn(Arc::clone(self).dispatch());
        Ok(unfinished.len())
    }

    /// Tells the grader that a regrade has started.
    pub fn regrade_started(&self) {
        self.regrades_pending.store(true, Ordering::SeqCst);
        self.wake.notify_one();
    }

    /// The gradings waiting their turn (or their next try), in arrival order.
    pub fn waiting(&self) -> Vec<Waiting> {
        self.queue().waiting().to_vec()
    }

    fn queue(&self) -> MutexGuard<'_, FairQueue> {
        // The queue's bookkeeping never panics halfway; a poisoned lock is still whole.
        self.queue.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn enqueue(&self, work: Work, tenant: Tenant) {
        self.queue().push(work, tenant);
        self.wake.notify_one();
    }

    /// Starts every grading the queue lets start, then waits to be woken (or for the next
    /// retry of a grading whose sandbox did not start), for as long as the server runs.
    async fn dispatch(self: Arc<Self>) {
        loop {
            if self.regrades_pending.swap(false, Ordering::SeqCst)
                && !self.queue().has(&Tenant::Regrades)
            {
                self.queue_next_regrade_item().await;
            }
            let now = Instant::now();
            let (tickets, retry_at) = {
                let mut queue = self.queue();
                let tickets: Vec<Ticket> = std::iter::from_fn(|| queue.take(now)).collect();
                (tickets, queue.next_retry(now))
            };
            for ticket in tickets {
                tokio::spawn(Arc::clone(&self).run(ticket));
            }
            match retry_at {
                Some(at) => {
                    let _ = tokio::time::timeout_at(at.into(), self.wake.notified()).await;
                }
                None => self.wake.notified().await,
            }
        }
    }

    /// Queues the next item of the oldest unfinished regrade, if any. A failing database
    /// leaves it for the next regrade or start rather than trying again in a spin.
    async fn queue_next_regrade_item(self: &Arc<Self>) {
        let grader = Arc::clone(self);
        let next = tokio::task::spawn_blocking(move || grader.store.next_regrade_item()).await;
        match next {
            Ok(Ok(Some((regrade, submission)))) => self.queue().push(
                Work::RegradeItem {
                    regrade,
                    submission,
                },
                Tenant::Regrades,
            ),
            Ok(Ok(None)) => {}
            Ok(Err(err)) => tracing::error!("regrading: {err}"),
            Err(err) => tracing::error!("regrading stopped: {err}"),
        }
    }

    /// Grades one ticket's work in a blocking task; moves it to the background once it
    /// has run `demote_after`, and there keeps its worker at the background priority; then
    /// settles it with the queue.
    async fn run(self: Arc<Self>, mut ticket: Ticket) {
        let started = Instant::now();
        // The grading thread's id while it grades (0 before and after), whose child is
        // the worker.
        let thread = Arc::new(AtomicI32::new(0));
        let (grader, grading_thread) = (Arc::clone(&self), Arc::clone(&thread));
        let work = ticket.work;
        let mut grading = tokio::task::spawn_blocking(move || {
            grading_thread.store(priority::current_thread(), Ordering::SeqCst);
            let outcome = grader.grade(work);
            grading_thread.store(0, Ordering::SeqCst);
            outcome
        });
        let demote_after = self.queue().policy().demote_after;
        let outcome = loop {
            let wait = match ticket.lane {
                Lane::Foreground => demote_after.saturating_sub(started.elapsed()),
                Lane::Background => SWEEP,
            };
            tokio::select! {
                outcome = &mut grading => break outcome,
                () = tokio::time::sleep(wait) => {}
            }
            if ticket.lane == Lane::Foreground && self.queue().demote(&mut ticket, Instant::now()) {
                tracing::info!(?work, "still grading: moved to the background");
                self.wake.notify_one();
            }
            match thread.load(Ordering::SeqCst) {
                0 => {}
                tid => priority::lower_children_of(tid),
            }
        };
        let now = Instant::now();
        let is_regrade = matches!(work, Work::RegradeItem { .. });
        match outcome {
            Ok(Ok(())) => {
                self.queue().finish(ticket, now - started, now);
                if is_regrade {
                    self.regrades_pending.store(true, Ordering::SeqCst);
                }
            }
            Ok(Err(Failure::DidNotStart(err))) => {
                let attempt = ticket.failed_starts + 1;
                let wait = self.queue().retry(ticket, now);
                tracing::warn!(
                    ?work,
                    attempt,
                    retry_in_ms = wait.as_millis() as u64,
                    "{err}: the grading waits and is tried again"
                );
            }
            Ok(Err(Failure::Store(err))) => {
                self.queue().finish(ticket, now - started, now);
                self.failed(work, err.to_string()).await;
            }
            Err(err) => {
                self.queue().finish(ticket, now - started, now);
                self.failed(work, format!("stopped: {err}")).await;
            }
        }
        self.wake.notify_one();
    }

    /// A grading that failed on the server's side after its sandbox ran (the database, a
    /// panic). A submission is not left waiting, which would refuse the student's next
    /// one: it ends "not gradable", which costs them nothing. A regrade item stays
    /// waiting, for the next regrade or start.
    async fn failed(self: &Arc<Self>, work: Work, why: String) {
        tracing::error!(?work, "grading: {why}");
        if let Work::Submission(id) = work {
            let grader = Arc::clone(self);
            let ended = tokio::task::spawn_blocking(move || {
                grader
                    .store
                    .give_up(id, "the server could not grade it; submit again")
            })
            .await;
            if let Ok(Err(err)) = ended {
                tracing::error!("submission {id} could not be marked as not gradable: {err}");
            }
        }
    }

    fn grade(&self, work: Work) -> Result<(), Failure> {
        match work {
            Work::Submission(id) => self.grade_submission(id),
            Work::RegradeItem {
                regrade,
                submission,
            } => self.regrade(regrade, submission),
        }
    }

    fn grade_submission(&self, id: i64) -> Result<(), Failure> {
        let started = Instant::now();
        let job = self.store.start_grading(id)?;
        let hidden = self.secret.hidden(id, &job.course);
        let result =
            match self
                .sandbox
                .try_grade(job.exercise, code_of(&job), job.seed, Some(hidden))
            {
                Ok(result) => result,
                Err(err) => {
                    self.store.back_to_queue(id)?;
                    return Err(Failure::DidNotStart(err));
                }
            };
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

    fn regrade(&self, regrade: i64, submission: i64) -> Result<(), Failure> {
        let started = Instant::now();
        // Its status stays graded: the student may go on submitting meanwhile.
        let job = self.store.to_grade(submission)?;
        let hidden = self.secret.hidden(submission, &job.course);
        let result = self
            .sandbox
            .try_grade(job.exercise, code_of(&job), job.seed, Some(hidden))
            .map_err(Failure::DidNotStart)?;
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

fn student(course: &str, student: &str) -> Tenant {
    Tenant::Student {
        course: course.to_owned(),
        student: student.to_owned(),
    }
}

/// A stored submission's file, as the sandbox takes it.
fn code_of(job: &ToGrade) -> Code<'_> {
    Code {
        language: job.language,
        text: &job.source,
    }
}
