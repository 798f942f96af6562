//! The sandbox's work in the order `fair` keeps: phases students asked for on the
//! workbench (`asked`), gradings of stored submissions, and regrades, which take their
//! turn as one more student, item by item. Students take turns, and a student whose work
//! runs long goes behind the others and in the background lane. One dispatcher task
//! starts each in a blocking task that waits for its sandbox worker process, so that the
//! server's other requests are answered meanwhile. A grading whose sandbox did not start,
//! or that the machine starved of time, waits and is tried again: a fault of the server's
//! own never becomes a student's result.
//!
//! Several graders (each a process: `estlab serve`, `estlab grader`) may share one
//! database: each claims a grading before it starts it and renews the lease while it
//! runs (`store::leases`), and looks at the database every `Policy::poll` for work that
//! other processes queued or left when they died. A submission taken by a web process of
//! another release (another `grader_version`) is left for a grader of that release.

use super::asked::Asked;
use super::fair::{FairQueue, Lane, Policy, Tenant, Ticket, Waiting, Work};
use super::metrics::{Metrics, Outcome};
use super::{Secret, grader_version, priority};
use crate::clock::Clock;
use crate::sandbox::{self, Code, NotNow, Sandbox};
use crate::store::{Claimable, Error, Holder, Lease, NewSubmission, Store, ToGrade};
use jiff::Timestamp;
use labs::{Exercise, Language};
use std::collections::HashSet;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::Notify;

/// How often a running grading's worker is looked at: in the foreground, for the CPU time
/// it has used (past `demote_after`, it asks for a place in the background); in the
/// background, to lower its priority.
const SWEEP: Duration = Duration::from_millis(100);

/// How many times a grading is tried whose sandbox runs out of time by the clock, its CPU
/// time not used up, before it ends "not gradable" (which costs the student nothing): a
/// machine too busy once or twice is the machine's doing; every time, it may be the
/// file's, in a way its CPU time does not show.
const STARVED_TRIES: u32 = 3;

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
    pub(super) wake: Notify,
    /// Whether the dispatcher runs: from the first phase asked or from `resume`.
    dispatching: AtomicBool,
    /// The phases asked for, until they start.
    pub(super) asked: Asked,
    /// Whether the regrades may have an item for the queue (set when a regrade starts,
    /// when an item is done, and at each look at the database).
    regrades_pending: AtomicBool,
    /// This process, as the holder of the leases it takes.
    holder: Holder,
    /// Whether this process grades (`resume` was called): a web process that leaves the
    /// grading to graders only stores submissions.
    grading: AtomicBool,
    /// The submissions left for a grader of another release, said once each in the log.
    left: Mutex<HashSet<i64>>,
    clock: Arc<dyn Clock>,
    metrics: Metrics,
}

/// Why a grading ended without a result stored.
enum Failure {
    /// The sandbox could not grade it now (it did not start, or the machine gave it too
    /// little time): the grading waits and is tried again.
    NotNow(NotNow),
    Store(Error),
}

/// How a grading's turn ended, when nothing failed.
#[derive(Debug, PartialEq)]
enum Graded {
    /// Its result is stored.
    Here,
    /// Another grader held it (or had graded it already): nothing was done.
    Elsewhere,
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
                .map(|&exercise| {
                    grader_version(exercise, Some(&secret), sandbox.reach(Language::JavaScript))
                })
                .collect(),
            store,
            sandbox,
            secret,
            queue: Mutex::new(FairQueue::new(policy)),
            wake: Notify::new(),
            dispatching: AtomicBool::new(false),
            asked: Asked::default(),
            regrades_pending: AtomicBool::new(false),
            holder: Holder::this_process(),
            grading: AtomicBool::new(false),
            left: Mutex::new(HashSet::new()),
            clock,
            metrics: Metrics::new(),
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

    /// This process, as the holder of the leases it takes.
    pub fn holder(&self) -> &str {
        self.holder.as_str()
    }

    /// The versions of the graders of every exercise, as this process grades them.
    pub fn versions(&self) -> Vec<&str> {
        self.versions.iter().map(String::as_str).collect()
    }

    /// Stores a submission, then queues its grading if this process grades; returns its
    /// id once it is stored.
    pub fn submit(&self, new: &NewSubmission) -> Result<i64, Error> {
        let id = self.store.insert(new, self.live_since(Timestamp::now()))?;
        if self.grading.load(Ordering::SeqCst) {
            self.enqueue(Work::Submission(id), student(new.course, new.student));
        }
        Ok(id)
    }

    /// Starts grading: ends the leases of this machine's graders that died, queues every
    /// submission waiting (those a stop cut off too), resumes any regrade, and looks at
    /// the database every `Policy::poll` from then on; returns how many submissions it
    /// found waiting.
    pub fn resume(self: &Arc<Self>) -> Result<usize, Error> {
        self.store.end_leases_of_the_dead(&self.holder)?;
        let found = self.find_work()?;
        self.grading.store(true, Ordering::SeqCst);
        self.regrades_pending.store(true, Ordering::SeqCst);
        self.start_dispatching();
        tokio::spawn(Arc::clone(self).watch());
        Ok(found)
    }

    /// Starts the dispatcher, unless it runs: a process that grades starts it at once, one
    /// that leaves grading to graders at the first phase asked of it.
    pub(super) fn start_dispatching(self: &Arc<Self>) {
        if !self.dispatching.swap(true, Ordering::SeqCst) {
            tokio::spawn(Arc::clone(self).dispatch());
        }
    }

    /// Says in the database that this grader runs, then queues the submissions waiting
    /// there that it may grade, unless queued here already; returns how many it queued.
    fn find_work(&self) -> Result<usize, Error> {
        let now = Timestamp::now();
        let languages: Vec<Language> = Language::ALL
            .iter()
            .copied()
            .filter(|&language| self.sandbox.language(language).is_ok())
            .collect();
        self.store
            .heartbeat(&self.holder, (&self.versions(), &languages), now)?;
        let running = self.running_versions(now)?;
        let claimable = self.store.claimable(now)?;
        let mut queue = self.queue();
        let mut found = 0;
        for waiting in claimable {
            let id = waiting.submission.id;
            if let Some(why) = self.leaves(&waiting, &running) {
                let mut left = self.left.lock().unwrap_or_else(|e| e.into_inner());
                if left.insert(id) {
                    tracing::warn!(submission = id, "left to another grader: {why}");
                }
                continue;
            }
            let tenant = student(&waiting.submission.course, &waiting.submission.student);
            if queue.push(Work::Submission(id), tenant, Instant::now()) {
                found += 1;
            }
        }
        Ok(found)
    }

    /// The versions of the graders that run (seen within a lease), this one's among them.
    fn running_versions(&self, now: Timestamp) -> Result<HashSet<String>, Error> {
        self.store.live_versions(self.live_since(now))
    }

    /// Since when a grader seen runs still, as of `now`: a lease ago.
    pub fn live_since(&self, now: Timestamp) -> Timestamp {
        let lease = self.queue().policy().lease;
        now - jiff::SignedDuration::try_from(lease).unwrap_or(jiff::SignedDuration::MAX)
    }

    /// Why this grader leaves a waiting submission to others, if it does: its web process
    /// took it for a grader of another version, one of which runs (when none does, this
    /// one takes it over, its result naming this grader); or this machine cannot run its
    /// language.
    fn leaves(&self, waiting: &Claimable, running: &HashSet<String>) -> Option<String> {
        if let Some(wanted) = &waiting.wanted_grader
            && !self.versions.contains(wanted)
            && running.contains(wanted)
        {
            return Some(format!(
                "taken for {wanted}, which a grader runs: this one would grade it differently"
            ));
        }
        self.sandbox.language(waiting.language).err().map(|why| {
            format!(
                "{} files cannot be graded on this machine: {why}",
                waiting.language.title()
            )
        })
    }

    /// Looks at the database every `Policy::poll`, for as long as the process runs: for
    /// submissions other processes stored or left, and regrades they started.
    async fn watch(self: Arc<Self>) {
        let poll = self.queue().policy().poll;
        loop {
            tokio::time::sleep(poll).await;
            let grader = Arc::clone(&self);
            match tokio::task::spawn_blocking(move || grader.find_work()).await {
                Ok(Ok(_)) => {}
                Ok(Err(err)) => tracing::error!("looking for work: {err}"),
                Err(err) => tracing::error!("looking for work stopped: {err}"),
            }
            self.regrades_pending.store(true, Ordering::SeqCst);
            self.wake.notify_one();
        }
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

    /// How many works run now, each in a sandbox of its own.
    pub fn running(&self) -> usize {
        self.queue().running()
    }

    /// The token `/metrics` asks for (`Secret::metrics_token`).
    pub fn metrics_token(&self) -> String {
        self.secret.metrics_token()
    }

    /// This process's metrics of its sandbox work now, in Prometheus's text format.
    pub fn metrics(&self) -> String {
        let (waiting, running, cap) = {
            let queue = self.queue();
            let policy = queue.policy();
            (
                queue.waiting().to_vec(),
                queue.running(),
                policy.parallel + policy.background,
            )
        };
        self.metrics
            .render(&waiting, (running, cap), Instant::now())
    }

    /// A tenant's charge now: the CPU time its work's sandboxes used, in seconds, decayed
    /// (`fair`).
    pub fn charge(&self, tenant: &Tenant) -> f64 {
        self.queue().charge(tenant, Instant::now())
    }

    pub(super) fn queue(&self) -> MutexGuard<'_, FairQueue> {
        // The queue's bookkeeping never panics halfway; a poisoned lock is still whole.
        self.queue.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(super) fn enqueue(&self, work: Work, tenant: Tenant) {
        self.queue().push(work, tenant, Instant::now());
        self.wake.notify_one();
    }

    /// Starts every grading the queue lets start, then waits to be woken (or for the next
    /// retry of a grading whose sandbox did not start), for as long as the server runs.
    async fn dispatch(self: Arc<Self>) {
        loop {
            // A process that leaves grading to graders runs only what it was asked.
            if self.grading.load(Ordering::SeqCst)
                && self.regrades_pending.swap(false, Ordering::SeqCst)
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
        let next = tokio::task::spawn_blocking(move || {
            let now = Timestamp::now();
            let running = grader.running_versions(now)?;
            grader
                .store
                .next_regrade_item(now, &grader.versions(), &running)
        })
        .await;
        match next {
            Ok(Ok(Some((regrade, submission)))) => {
                self.queue().push(
                    Work::RegradeItem {
                        regrade,
                        submission,
                    },
                    Tenant::Regrades,
                    Instant::now(),
                );
            }
            Ok(Ok(None)) => {}
            Ok(Err(err)) => tracing::error!("regrading: {err}"),
            Err(err) => tracing::error!("regrading stopped: {err}"),
        }
    }

    /// Grades one ticket's work in a blocking task; moves it to the background once its
    /// sandbox has used `demote_after` of CPU time and the background has a free place,
    /// and there keeps its worker at the background priority; renews its lease at each
    /// third of it; then settles it with the queue, charging its tenant the CPU time its
    /// sandbox used.
    async fn run(self: Arc<Self>, mut ticket: Ticket) {
        // The grading thread's id while it grades (0 before and after), whose child is
        // the worker.
        let thread = Arc::new(AtomicI32::new(0));
        let (grader, grading_thread) = (Arc::clone(&self), Arc::clone(&thread));
        let work = ticket.work;
        let mut grading = tokio::task::spawn_blocking(move || {
            grading_thread.store(priority::current_thread(), Ordering::SeqCst);
            let before = sandbox::workers_spent();
            let outcome = grader.grade(work);
            grading_thread.store(0, Ordering::SeqCst);
            (outcome, sandbox::workers_spent() - before)
        });
        let lease = self.queue().policy().lease;
        let mut renew_at = Instant::now() + lease / 3;
        let outcome = loop {
            let wait = SWEEP.min(renew_at.saturating_duration_since(Instant::now()));
            tokio::select! {
                outcome = &mut grading => break outcome,
                () = tokio::time::sleep(wait) => {}
            }
            if Instant::now() >= renew_at {
                self.renew(work).await;
                renew_at = Instant::now() + lease / 3;
            }
            match thread.load(Ordering::SeqCst) {
                0 => {}
                tid if ticket.lane == Lane::Foreground => {
                    let ran = sandbox::started_by(tid);
                    if self.queue().demote(&mut ticket, ran, Instant::now()) {
                        tracing::info!(?work, "still grading: moved to the background");
                        self.wake.notify_one();
                    }
                }
                tid => priority::lower_children_of(tid),
            }
        };
        let (outcome, spent) = match outcome {
            Ok((outcome, spent)) => (Ok(outcome), spent),
            // A panic: what it used is unknown; what it was charged at a demotion stays.
            Err(err) => (Err(err), Duration::ZERO),
        };
        let now = Instant::now();
        let is_regrade = matches!(work, Work::RegradeItem { .. });
        let ended = |outcome| self.metrics.ended(work, outcome, spent);
        match outcome {
            Ok(Ok(graded)) => {
                ended(match graded {
                    Graded::Here => Outcome::Done,
                    Graded::Elsewhere => Outcome::Elsewhere,
                });
                if graded == Graded::Elsewhere {
                    tracing::debug!(?work, "held or graded by another grader");
                }
                self.queue().finish(ticket, spent, now);
                if is_regrade {
                    self.regrades_pending.store(true, Ordering::SeqCst);
                }
            }
            Ok(Err(Failure::NotNow(err @ NotNow::DidNotStart(_)))) => {
                ended(Outcome::DidNotStart);
                self.put_back(work).await;
                let attempt = ticket.failed_starts + 1;
                let wait = self.queue().retry(ticket, now);
                tracing::warn!(
                    ?work,
                    attempt,
                    retry_in_ms = wait.as_millis() as u64,
                    "{err}: the grading waits and is tried again"
                );
            }
            Ok(Err(Failure::NotNow(err @ NotNow::Starved { .. })))
                if ticket.starved + 1 < STARVED_TRIES =>
            {
                ended(Outcome::Starved);
                self.put_back(work).await;
                let attempt = ticket.starved + 1;
                let wait = self.queue().starved(ticket, spent, now);
                tracing::warn!(
                    ?work,
                    attempt,
                    retry_in_ms = wait.as_millis() as u64,
                    "{err}: the grading waits and is tried again"
                );
            }
            Ok(Err(Failure::NotNow(err @ NotNow::Starved { .. }))) => {
                ended(Outcome::GivenUp);
                self.queue().finish(ticket, spent, now);
                if is_regrade {
                    self.put_back(work).await;
                }
                self.failed(work, format!("{err}, {STARVED_TRIES} times"))
                    .await;
            }
            Ok(Err(Failure::Store(Error::LeaseLost(what)))) => {
                ended(Outcome::LeaseLost);
                self.queue().finish(ticket, spent, now);
                tracing::warn!(
                    ?work,
                    "{what} is no longer this grader's: its result is not written"
                );
                if is_regrade {
                    self.regrades_pending.store(true, Ordering::SeqCst);
                }
            }
            Ok(Err(Failure::Store(err))) => {
                ended(Outcome::GivenUp);
                self.queue().finish(ticket, spent, now);
                self.failed(work, err.to_string()).await;
            }
            Err(err) => {
                ended(Outcome::GivenUp);
                self.queue().finish(ticket, spent, now);
                self.failed(work, format!("stopped: {err}")).await;
            }
        }
        self.wake.notify_one();
    }

    /// Renews the lease of a grading this grader holds; says so when it was lost (the
    /// process stalled past it, or the database was out of reach meanwhile).
    async fn renew(self: &Arc<Self>, work: Work) {
        let grader = Arc::clone(self);
        let renewed = tokio::task::spawn_blocking(move || {
            let lease = grader.lease();
            match work {
                // Asked for, not stored: it holds no lease.
                Work::Phase(_) | Work::ReportRuns(_) => Ok(true),
                Work::Submission(id) => grader.store.renew_submission(id, &lease),
                Work::RegradeItem {
                    regrade,
                    submission,
                } => grader.store.renew_regrade_item(regrade, submission, &lease),
            }
        })
        .await;
        match renewed {
            Ok(Ok(true)) => {}
            Ok(Ok(false)) => {
                self.metrics.lease_lost();
                tracing::warn!(?work, "the lease was lost: another grader may take it")
            }
            Ok(Err(err)) => tracing::warn!(?work, "the lease could not be renewed: {err}"),
            Err(err) => tracing::warn!(?work, "renewing the lease stopped: {err}"),
        }
    }

    /// Gives back the lease of a grading that waits again, for any grader to take.
    async fn put_back(self: &Arc<Self>, work: Work) {
        let grader = Arc::clone(self);
        let released = tokio::task::spawn_blocking(move || match work {
            Work::Phase(_) | Work::ReportRuns(_) => Ok(()),
            Work::Submission(id) => grader.store.back_to_queue(id, &grader.holder),
            Work::RegradeItem {
                regrade,
                submission,
            } => grader
                .store
                .release_regrade_item(regrade, submission, &grader.holder),
        })
        .await;
        match released {
            Ok(Ok(())) => {}
            Ok(Err(err)) => tracing::warn!(?work, "putting it back: {err}"),
            Err(err) => tracing::warn!(?work, "putting it back stopped: {err}"),
        }
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
                grader.store.give_up(
                    id,
                    "the server could not grade it; submit again",
                    &grader.holder,
                )
            })
            .await;
            if let Ok(Err(err)) = ended {
                tracing::error!("submission {id} could not be marked as not gradable: {err}");
            }
        }
    }

    fn grade(&self, work: Work) -> Result<Graded, Failure> {
        match work {
            Work::Phase(number) | Work::ReportRuns(number) => {
                self.run_asked(number);
                Ok(Graded::Here)
            }
            Work::Submission(id) => self.grade_submission(id),
            Work::RegradeItem {
                regrade,
                submission,
            } => self.regrade(regrade, submission),
        }
    }

    /// A lease of this process's from now (a grading's, or a report's runs being made).
    pub fn lease(&self) -> Lease<'_> {
        Lease {
            holder: &self.holder,
            from: Timestamp::now(),
            length: self.queue().policy().lease,
        }
    }

    fn grade_submission(&self, id: i64) -> Result<Graded, Failure> {
        let started = Instant::now();
        let Some(job) = self.store.claim_submission(id, &self.lease())? else {
            return Ok(Graded::Elsewhere);
        };
        let hidden = self.secret.hidden(id, &job.course);
        let result =
            match self
                .sandbox
                .try_grade(job.exercise, code_of(&job), job.seed, Some(hidden))
            {
                Ok(result) => result,
                // Still leased: `run` puts it back, or gives it up.
                Err(err) => return Err(Failure::NotNow(err)),
            };
        let score = result.gradable.then_some(result.score);
        self.store.finish_grading(
            id,
            &result.stored(),
            Some(self.version(job.exercise)),
            &self.holder,
        )?;
        tracing::info!(
            submission = id,
            course = job.course,
            student = job.student,
            duration_ms = started.elapsed().as_millis() as u64,
            score,
            grader = self.holder.as_str(),
            "graded"
        );
        Ok(Graded::Here)
    }

    fn regrade(&self, regrade: i64, submission: i64) -> Result<Graded, Failure> {
        let started = Instant::now();
        if !self
            .store
            .claim_regrade_item(regrade, submission, &self.lease())?
        {
            return Ok(Graded::Elsewhere);
        }
        // Its status stays graded: the student may go on submitting meanwhile.
        let job = self.store.to_grade(submission)?;
        let hidden = self.secret.hidden(submission, &job.course);
        let result =
            match self
                .sandbox
                .try_grade(job.exercise, code_of(&job), job.seed, Some(hidden))
            {
                Ok(result) => result,
                // Still leased: `run` puts it back.
                Err(err) => return Err(Failure::NotNow(err)),
            };
        let score = result.gradable.then_some(result.score);
        self.store.finish_regrade_item(
            regrade,
            submission,
            &result.stored(),
            self.version(job.exercise),
            &self.holder,
            self.clock.now(),
        )?;
        tracing::info!(
            regrade,
            submission,
            course = job.course,
            student = job.student,
            duration_ms = started.elapsed().as_millis() as u64,
            score,
            grader = self.holder.as_str(),
            "regraded"
        );
        Ok(Graded::Here)
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
