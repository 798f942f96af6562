//! The order of the work the sandbox does: students take turns, and a student whose work
//! runs long gets a smaller share. This is the bookkeeping only (no clock, no threads:
//! every call is given the moment), so that the order is tested as an order.
//!
//! The work is of four kinds, each a lane of its priority ([`Work::rank`]): a phase a
//! student asked for interactively (Run tests on the server, someone waits for it), then
//! a submission's grading, then the runs of a student's report, then a regrade's item.
//! The share comes first: among tenants alike in what they run and were charged (a
//! student new to the queue, say), the higher lane goes first, and so it does among a
//! tenant's own works; but no lane lets a student who used the sandbox more go before one
//! who used it less.
//!
//! Each student of a course (and the regrades, as one more) is a *tenant*, charged the
//! CPU time its work's sandboxes used (read from the kernel, never the clock: a busy
//! machine makes no one's work longer), decayed by half every `HALF_LIFE`. The next grading is the
//! waiting one whose tenant has the fewest gradings running, then the smallest charge,
//! then the earliest arrival: a student who was just graded goes behind one who was not,
//! however many they keep waiting. A tenant whose long gradings (those that ran at least
//! `Policy::demote_after`) are charged `Policy::heavy`, or who has a grading running in
//! the background, is graded in the background lane (outside the `parallel` slots, at a
//! low CPU priority), and so is a grading that has used `Policy::demote_after` of CPU
//! time and still runs while the background has a free place: a file that runs every
//! phase to its limit holds a slot for a few seconds at most while the background has
//! room. The background's places are a bound, not a start rate: however many gradings
//! overrun, no more than `parallel + background` sandboxes run at once (a demotion that
//! would go over leaves the grading in its slot).

use std::collections::{HashMap, HashSet};
use std::time::{Duration, Instant};

/// A charge halves in this time: a student whose file ran every phase to its limit (about
/// 18 s of grading) is back under the usual threshold after about five minutes.
const HALF_LIFE: Duration = Duration::from_secs(120);
/// A grading whose start failed waits at least this before its next try, at most
/// `MAX_RETRY` (the wait doubles at each failure).
const MAX_RETRY: Duration = Duration::from_secs(60);

/// Whose work it is: the sandbox's time is shared out between these.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Tenant {
    Student {
        course: String,
        student: String,
    },
    /// Whoever asks from an address's block, on a server without courses.
    Address(String),
    /// Every regrade, together: a class's regrade is one more turn-taker.
    Regrades,
}

/// What the sandbox is to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Work {
    /// A phase of a student's file asked for interactively, by its number in this process.
    Phase(u64),
    Submission(i64),
    /// The whole runs of a student's report, by their number in this process.
    ReportRuns(u64),
    RegradeItem {
        regrade: i64,
        submission: i64,
    },
}

impl Work {
    /// Its lane's priority, 0 first: someone waits for a phase; a grading is awaited; a
    /// report's runs are made once a submission, to be read later; a regrade changes what
    /// was graded already.
    pub fn rank(self) -> u8 {
        match self {
            Work::Phase(_) => 0,
            Work::Submission(_) => 1,
            Work::ReportRuns(_) => 2,
            Work::RegradeItem { .. } => 3,
        }
    }
}

/// Where a grading runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lane {
    /// One of the `parallel` slots, at normal CPU priority.
    Foreground,
    /// Outside the slots, at a low CPU priority (nice 10): it gets mostly the CPU others leave.
    Background,
}

/// The numbers of the rule.
#[derive(Clone, Copy, Debug)]
pub struct Policy {
    /// Gradings at once in the foreground.
    pub parallel: usize,
    /// Gradings at once in the background, demoted ones included.
    pub background: usize,
    /// A foreground grading that has used this much CPU time and still runs moves to the
    /// background, when the background has a free place.
    pub demote_after: Duration,
    /// A tenant charged this much CPU time (decayed) for long gradings is graded in the
    /// background.
    pub heavy: Duration,
    /// The wait after a grading's first failed start.
    pub first_retry: Duration,
    /// How long a grading is leased to this grader at each claim or renewal (renewed at
    /// each third of it while it runs): another grader takes over the work of one that
    /// died after at most this.
    pub lease: Duration,
    /// How often the database is looked at for work others queued, or left.
    pub poll: Duration,
}

impl Policy {
    /// The server's rule for `parallel` gradings at once. A correct file grades in 0.6 s
    /// (0.08 s for odometry), so three seconds is five of them.
    pub fn new(parallel: usize) -> Policy {
        let parallel = parallel.max(1);
        Policy {
            parallel,
            // Each background grading takes only CPU the foreground leaves; this bounds
            // their memory (two engines of 64 MB each at most).
            background: 2 * parallel,
            demote_after: Duration::from_secs(3),
            heavy: Duration::from_secs(3),
            first_retry: Duration::from_millis(500),
            lease: Duration::from_secs(30),
            poll: Duration::from_secs(1),
        }
    }

    /// The wait before the next try of a grading whose start failed `failures` times.
    fn retry_after(&self, failures: u32) -> Duration {
        let doublings = failures.saturating_sub(1).min(16);
        self.first_retry
            .saturating_mul(1 << doublings)
            .min(MAX_RETRY)
    }
}

/// A grading waiting its turn.
#[derive(Clone, Debug, PartialEq)]
pub struct Waiting {
    pub work: Work,
    pub tenant: Tenant,
    /// How many times its sandbox did not start.
    pub failed_starts: u32,
    /// How many times its sandbox ran out of time by the clock, its CPU time not used up.
    pub starved: u32,
    /// Not before this (after a failed start).
    pub not_before: Option<Instant>,
    /// When it first arrived (kept when it is put back).
    pub since: Instant,
    /// Its place among arrivals (kept when a failed start puts it back).
    arrival: u64,
}

/// A grading taken from the queue and running.
#[derive(Debug)]
pub struct Ticket {
    pub work: Work,
    pub tenant: Tenant,
    pub lane: Lane,
    pub failed_starts: u32,
    pub starved: u32,
    since: Instant,
    arrival: u64,
    /// Charged already (at a demotion), not to be charged twice.
    charged: Duration,
}

/// A tenant's decayed charge, as of a moment.
#[derive(Clone, Copy, Debug)]
struct Charge {
    seconds: f64,
    at: Instant,
}

impl Charge {
    fn at(self, now: Instant) -> f64 {
        let age = now.saturating_duration_since(self.at).as_secs_f64();
        self.seconds * 0.5f64.powf(age / HALF_LIFE.as_secs_f64())
    }
}

/// The waiting gradings, the running ones per lane and tenant, and every tenant's charge.
#[derive(Debug)]
pub struct FairQueue {
    policy: Policy,
    waiting: Vec<Waiting>,
    running: HashMap<Tenant, usize>,
    foreground: usize,
    background: usize,
    charges: HashMap<Tenant, Charge>,
    /// The same for long gradings only: many quick ones never make a student heavy.
    long: HashMap<Tenant, Charge>,
    /// Per tenant, the gradings running that were moved to the background: while one
    /// runs, the tenant is heavy whatever its charge (so that each of a student's files
    /// does not get a foreground turn of its own before the first one ends).
    overrunning: HashMap<Tenant, usize>,
    /// Every work waiting or running, each held once (the database is polled for work
    /// that may be there already).
    held: HashSet<Work>,
    arrivals: u64,
}

impl FairQueue {
    pub fn new(policy: Policy) -> FairQueue {
        FairQueue {
            policy,
            waiting: Vec::new(),
            running: HashMap::new(),
            foreground: 0,
            background: 0,
            charges: HashMap::new(),
            long: HashMap::new(),
            overrunning: HashMap::new(),
            held: HashSet::new(),
            arrivals: 0,
        }
    }

    pub fn policy(&self) -> &Policy {
        &self.policy
    }

    /// Adds a grading at the end of the arrivals at `now`, unless it is waiting or running
    /// already; returns whether it was added.
    pub fn push(&mut self, work: Work, tenant: Tenant, now: Instant) -> bool {
        if !self.held.insert(work) {
            return false;
        }
        self.arrivals += 1;
        self.waiting.push(Waiting {
            work,
            tenant,
            failed_starts: 0,
            starved: 0,
            not_before: None,
            since: now,
            arrival: self.arrivals,
        });
        true
    }

    /// The waiting gradings, in arrival order.
    pub fn waiting(&self) -> &[Waiting] {
        &self.waiting
    }

    /// How many works run, in both lanes: the sandboxes running.
    pub fn running(&self) -> usize {
        self.foreground + self.background
    }

    /// Whether a tenant has a grading waiting or running.
    pub fn has(&self, tenant: &Tenant) -> bool {
        self.running.get(tenant).is_some_and(|&n| n > 0)
            || self.waiting.iter().any(|w| w.tenant == *tenant)
    }

    /// A tenant's charge at `now`, in seconds of grading.
    pub fn charge(&self, tenant: &Tenant, now: Instant) -> f64 {
        self.charges.get(tenant).map_or(0.0, |c| c.at(now))
    }

    /// The lane a tenant's next grading starts in.
    pub fn lane(&self, tenant: &Tenant, now: Instant) -> Lane {
        let long = self.long.get(tenant).map_or(0.0, |c| c.at(now));
        if long >= self.policy.heavy.as_secs_f64() || self.overrunning.contains_key(tenant) {
            Lane::Background
        } else {
            Lane::Foreground
        }
    }

    /// Where a waiting work stands in the order of [`FairQueue::take`]: the ready one whose
    /// tenant has the fewest running, then the smallest charge, then of the highest lane,
    /// then arrived first.
    fn key(&self, waiting: &Waiting, now: Instant) -> (usize, f64, u8, u64) {
        self.key_with(&self.running, waiting, now)
    }

    fn key_with(
        &self,
        running: &HashMap<Tenant, usize>,
        waiting: &Waiting,
        now: Instant,
    ) -> (usize, f64, u8, u64) {
        (
            running.get(&waiting.tenant).copied().unwrap_or(0),
            self.charge(&waiting.tenant, now),
            waiting.work.rank(),
            waiting.arrival,
        )
    }

    /// The next work that may start now, if any, marked as running: the first by
    /// [`FairQueue::key`] among those whose lane has a free place.
    pub fn take(&mut self, now: Instant) -> Option<Ticket> {
        let free = |lane| match lane {
            Lane::Foreground => self.foreground < self.policy.parallel,
            Lane::Background => self.background < self.policy.background,
        };
        let (index, lane) = self
            .waiting
            .iter()
            .enumerate()
            .filter(|(_, w)| w.not_before.is_none_or(|at| at <= now))
            .map(|(i, w)| (i, self.lane(&w.tenant, now)))
            .filter(|&(_, lane)| free(lane))
            .min_by(|&(a, _), &(b, _)| {
                let (a, b) = (
                    self.key(&self.waiting[a], now),
                    self.key(&self.waiting[b], now),
                );
                a.partial_cmp(&b).expect("charges are finite")
            })?;
        let waiting = self.waiting.remove(index);
        *self.running.entry(waiting.tenant.clone()).or_default() += 1;
        match lane {
            Lane::Foreground => self.foreground += 1,
            Lane::Background => self.background += 1,
        }
        Some(Ticket {
            work: waiting.work,
            tenant: waiting.tenant,
            lane,
            failed_starts: waiting.failed_starts,
            starved: waiting.starved,
            since: waiting.since,
            arrival: waiting.arrival,
            charged: Duration::ZERO,
        })
    }

    /// Its place in line, as things stand (1: it is next): the works waiting taken one
    /// after another in the order of [`FairQueue::take`], each counted as running once
    /// taken; none when it is not waiting.
    pub fn place(&self, work: Work, now: Instant) -> Option<usize> {
        let mut running = self.running.clone();
        let mut left: Vec<&Waiting> = self.waiting.iter().collect();
        for place in 1.. {
            let (index, next) = left.iter().enumerate().min_by(|(_, a), (_, b)| {
                let (a, b) = (
                    self.key_with(&running, a, now),
                    self.key_with(&running, b, now),
                );
                a.partial_cmp(&b).expect("charges are finite")
            })?;
            if next.work == work {
                return Some(place);
            }
            *running.entry(next.tenant.clone()).or_default() += 1;
            left.remove(index);
        }
        unreachable!("the line is finite")
    }

    /// Takes a waiting work out of the queue (its asker no longer waits); returns whether
    /// it was waiting (not running, nor ended).
    pub fn cancel(&mut self, work: Work) -> bool {
        let before = self.waiting.len();
        self.waiting.retain(|w| w.work != work);
        let cancelled = self.waiting.len() < before;
        if cancelled {
            self.held.remove(&work);
        }
        cancelled
    }

    /// The earliest moment after `now` at which a grading waiting after a failed start
    /// may be tried again (one ready already waits for a free place instead).
    pub fn next_retry(&self, now: Instant) -> Option<Instant> {
        self.waiting
            .iter()
            .filter_map(|w| w.not_before)
            .filter(|&at| at > now)
            .min()
    }

    /// Moves a foreground grading whose sandbox has used `ran` of CPU time, at least
    /// `demote_after`, to the background, freeing its slot, and charges its tenant that
    /// time now (so that their next file starts in the background). Returns whether it
    /// moved: not when it has used less, nor when the background is full (the grading
    /// keeps its slot, and is asked again later).
    pub fn demote(&mut self, ticket: &mut Ticket, ran: Duration, now: Instant) -> bool {
        if ticket.lane != Lane::Foreground
            || ran < self.policy.demote_after
            || self.background >= self.policy.background
        {
            return false;
        }
        self.foreground -= 1;
        self.background += 1;
        ticket.lane = Lane::Background;
        add_charge(&mut self.charges, &ticket.tenant, ran, now);
        add_charge(&mut self.long, &ticket.tenant, ran, now);
        ticket.charged = ran;
        *self.overrunning.entry(ticket.tenant.clone()).or_default() += 1;
        true
    }

    /// A grading ended, its sandbox having used `took` of CPU time: its place is free and
    /// its tenant charged.
    pub fn finish(&mut self, ticket: Ticket, took: Duration, now: Instant) {
        self.release(&ticket);
        self.held.remove(&ticket.work);
        let rest = took.saturating_sub(ticket.charged);
        add_charge(&mut self.charges, &ticket.tenant, rest, now);
        if took >= self.policy.demote_after {
            add_charge(&mut self.long, &ticket.tenant, rest, now);
        }
    }

    /// A grading whose sandbox did not start waits again, in its place among arrivals,
    /// until its backoff has passed; its tenant is charged nothing. Returns the wait.
    pub fn retry(&mut self, ticket: Ticket, now: Instant) -> Duration {
        let failed_starts = ticket.failed_starts + 1;
        let starved = ticket.starved;
        self.put_back(ticket, (failed_starts, starved), now)
    }

    /// A grading whose sandbox ran out of time by the clock, its CPU time not used up (the
    /// machine's doing, or a file that stops itself), waits again as a failed start does;
    /// its tenant is charged the CPU time `took` it used, as a long grading. Returns the
    /// wait.
    pub fn starved(&mut self, ticket: Ticket, took: Duration, now: Instant) -> Duration {
        let rest = took.saturating_sub(ticket.charged);
        add_charge(&mut self.charges, &ticket.tenant, rest, now);
        add_charge(&mut self.long, &ticket.tenant, rest, now);
        let failed_starts = ticket.failed_starts;
        let starved = ticket.starved + 1;
        self.put_back(ticket, (failed_starts, starved), now)
    }

    fn put_back(
        &mut self,
        ticket: Ticket,
        (failed_starts, starved): (u32, u32),
        now: Instant,
    ) -> Duration {
        self.release(&ticket);
        let wait = self.policy.retry_after(failed_starts + starved);
        self.waiting.push(Waiting {
            work: ticket.work,
            tenant: ticket.tenant,
            failed_starts,
            starved,
            not_before: Some(now + wait),
            since: ticket.since,
            arrival: ticket.arrival,
        });
        wait
    }

    fn release(&mut self, ticket: &Ticket) {
        match ticket.lane {
            Lane::Foreground => self.foreground -= 1,
            Lane::Background => self.background -= 1,
        }
        if !ticket.charged.is_zero() {
            forget_one(&mut self.overrunning, &ticket.tenant);
        }
        forget_one(&mut self.running, &ticket.tenant);
    }
}

/// One less of a tenant's count in `counts` (none is kept at zero).
fn forget_one(counts: &mut HashMap<Tenant, usize>, tenant: &Tenant) {
    if let Some(count) = counts.get_mut(tenant) {
        *count -= 1;
        if *count == 0 {
            counts.remove(tenant);
        }
    }
}

/// Adds `took` to a tenant's decayed charge in `charges`.
fn add_charge(
    charges: &mut HashMap<Tenant, Charge>,
    tenant: &Tenant,
    took: Duration,
    now: Instant,
) {
    let before = charges.get(tenant).map_or(0.0, |c| c.at(now));
    charges.insert(
        tenant.clone(),
        Charge {
            seconds: before + took.as_secs_f64(),
            at: now,
        },
    );
    // Forget tenants whose charge has all but gone, so the map stays small.
    charges.retain(|_, c| c.at(now) >= 1e-3);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn student(name: &str) -> Tenant {
        Tenant::Student {
            course: "el2320".into(),
            student: name.into(),
        }
    }

    fn policy(parallel: usize) -> Policy {
        Policy::new(parallel)
    }

    /// Takes the next grading and ends it after `took`, as the grader would.
    fn grade(queue: &mut FairQueue, now: Instant, took: Duration) -> Work {
        let ticket = queue.take(now).expect("a grading to take");
        let work = ticket.work;
        queue.finish(ticket, took, now + took);
        work
    }

    const QUICK: Duration = Duration::from_millis(600);
    const TO_THE_LIMITS: Duration = Duration::from_secs(18);

    #[test]
    fn another_students_submission_goes_before_a_flooders_second() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        // The flooder's two files (one per exercise) arrived first.
        queue.push(Work::Submission(1), student("mallory"), start);
        queue.push(Work::Submission(2), student("mallory"), start);
        let first = queue.take(start).unwrap();
        assert_eq!(first.work, Work::Submission(1));
        // Only one slot: nothing else starts while it runs.
        queue.push(Work::Submission(3), student("ada"), start);
        assert!(queue.take(start).is_none());
        queue.finish(first, QUICK, start + QUICK);
        // Ada arrived after mallory's second, and goes first.
        assert_eq!(grade(&mut queue, start + QUICK, QUICK), Work::Submission(3));
        assert_eq!(
            grade(&mut queue, start + 2 * QUICK, QUICK),
            Work::Submission(2)
        );
    }

    #[test]
    fn students_take_turns_whoever_has_more_waiting() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        let mut id = 0;
        for name in ["mallory", "mallory", "eve", "eve", "ada", "grace"] {
            id += 1;
            queue.push(Work::Submission(id), student(name), start);
        }
        let order: Vec<Work> = (0..6)
            .map(|i| grade(&mut queue, start + QUICK * i, QUICK))
            .collect();
        // Everybody's first before anybody's second.
        assert_eq!(order, [1, 3, 5, 6, 2, 4].map(Work::Submission));
    }

    #[test]
    fn a_student_whose_gradings_hit_their_limits_is_ranked_behind_and_in_the_background() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        // Mallory's file ran every phase to its limit; Ada's last four were quick ones.
        queue.push(Work::Submission(1), student("mallory"), start);
        grade(&mut queue, start, TO_THE_LIMITS);
        let mut now = start + TO_THE_LIMITS;
        for id in 2..6 {
            queue.push(Work::Submission(id), student("ada"), start);
            grade(&mut queue, now, QUICK);
            now += QUICK;
        }
        queue.push(Work::Submission(10), student("mallory"), start);
        queue.push(Work::Submission(11), student("ada"), start);
        assert_eq!(queue.lane(&student("mallory"), now), Lane::Background);
        assert_eq!(queue.lane(&student("ada"), now), Lane::Foreground);
        assert!(queue.charge(&student("mallory"), now) > queue.charge(&student("ada"), now));
        // Ada first, although Mallory arrived first; and Mallory's file does not take
        // the one foreground slot: it starts in the background beside Ada's.
        let ada = queue.take(now).unwrap();
        assert_eq!(
            (ada.work, ada.lane),
            (Work::Submission(11), Lane::Foreground)
        );
        let mallory = queue.take(now).unwrap();
        assert_eq!(
            (mallory.work, mallory.lane),
            (Work::Submission(10), Lane::Background)
        );
    }

    #[test]
    fn many_quick_gradings_leave_a_student_in_the_foreground() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        let mut now = start;
        for id in 0..50 {
            queue.push(Work::Submission(id), student("ada"), start);
            grade(&mut queue, now, QUICK);
            now += QUICK * 2;
        }
        assert!(queue.charge(&student("ada"), now) > 10.0);
        assert_eq!(queue.lane(&student("ada"), now), Lane::Foreground);
    }

    #[test]
    fn among_heavy_students_the_least_charged_goes_first() {
        let start = Instant::now();
        let mut queue = FairQueue::new(Policy {
            background: 1,
            ..policy(1)
        });
        queue.push(Work::Submission(1), student("mallory"), start);
        grade(&mut queue, start, TO_THE_LIMITS * 3);
        queue.push(Work::Submission(2), student("eve"), start);
        let now = start + TO_THE_LIMITS * 3;
        grade(&mut queue, now, TO_THE_LIMITS);
        let now = now + TO_THE_LIMITS;
        queue.push(Work::Submission(3), student("mallory"), start);
        queue.push(Work::Submission(4), student("eve"), start);
        assert_eq!(grade(&mut queue, now, QUICK), Work::Submission(4));
    }

    #[test]
    fn a_grading_that_runs_long_frees_its_slot_and_its_student_goes_to_the_background() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(Work::Submission(1), student("mallory"), start);
        let mut long = queue.take(start).unwrap();
        queue.push(Work::Submission(2), student("ada"), start);
        queue.push(Work::Submission(3), student("mallory"), start);
        assert!(queue.take(start).is_none(), "the one slot is taken");
        let later = start + Duration::from_secs(10);
        let demote_after = queue.policy().demote_after;
        // Long by the clock, but not yet by its CPU time (a busy machine): it stays.
        assert!(!queue.demote(&mut long, demote_after / 2, later));
        assert_eq!(long.lane, Lane::Foreground);
        assert!(queue.demote(&mut long, demote_after, later));
        assert_eq!(long.lane, Lane::Background);
        // The slot is Ada's; Mallory's next file is charged the time so far and waits
        // behind, for the background.
        let ada = queue.take(later).unwrap();
        assert_eq!(
            (ada.work, ada.lane),
            (Work::Submission(2), Lane::Foreground)
        );
        assert_eq!(queue.lane(&student("mallory"), later), Lane::Background);
        // And stays in the background while the long one runs, however its charge fades.
        let meanwhile = later + Duration::from_secs(1);
        assert_eq!(queue.lane(&student("mallory"), meanwhile), Lane::Background);
        // The charge is not counted twice: at the end, the time it took in all.
        queue.finish(long, TO_THE_LIMITS, start + TO_THE_LIMITS);
        let charge = queue.charge(&student("mallory"), start + TO_THE_LIMITS);
        assert!((charge - 18.0).abs() < 0.5, "{charge}");
    }

    /// A burst where every grading overruns (a loaded machine, or files that all run to
    /// their limits): demotions fill the background and stop there, so the sandboxes
    /// running never pass `parallel + background`, and everything is graded in the end.
    #[test]
    fn overrunning_gradings_never_run_more_sandboxes_than_the_lanes_hold() {
        let start = Instant::now();
        let policy = policy(2);
        let cap = policy.parallel + policy.background;
        let mut queue = FairQueue::new(policy);
        for id in 0..100 {
            queue.push(
                Work::Submission(id),
                student(&format!("s{}", id % 30)),
                start,
            );
        }
        let mut running: Vec<Ticket> = Vec::new();
        let mut now = start;
        let mut graded = 0;
        while graded < 100 {
            while let Some(ticket) = queue.take(now) {
                running.push(ticket);
            }
            assert!(running.len() <= cap, "{} sandboxes at once", running.len());
            now += queue.policy().demote_after;
            for ticket in &mut running {
                queue.demote(ticket, queue.policy().demote_after, now);
            }
            let background = running
                .iter()
                .filter(|t| t.lane == Lane::Background)
                .count();
            assert!(background <= queue.policy().background);
            // The oldest ends; the others go on overrunning.
            let done = running.remove(0);
            queue.finish(done, TO_THE_LIMITS, now);
            graded += 1;
        }
        assert!(queue.waiting().is_empty() && running.is_empty());
    }

    #[test]
    fn a_charge_fades_so_a_student_comes_back_to_the_foreground() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(Work::Submission(1), student("mallory"), start);
        grade(&mut queue, start, TO_THE_LIMITS);
        assert_eq!(queue.lane(&student("mallory"), start), Lane::Background);
        let much_later = start + HALF_LIFE * 4;
        assert_eq!(
            queue.lane(&student("mallory"), much_later),
            Lane::Foreground
        );
    }

    #[test]
    fn a_grading_that_did_not_start_waits_in_its_place_with_a_growing_bounded_backoff() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(Work::Submission(1), student("ada"), start);
        queue.push(Work::Submission(2), student("grace"), start);
        let ticket = queue.take(start).unwrap();
        let wait = queue.retry(ticket, start);
        assert_eq!(wait, queue.policy().first_retry);
        // Not charged, and not ready before its backoff: Grace goes meanwhile.
        assert_eq!(queue.charge(&student("ada"), start), 0.0);
        assert_eq!(grade(&mut queue, start, QUICK), Work::Submission(2));
        let meanwhile = start + wait / 2;
        assert!(queue.take(meanwhile).is_none());
        assert_eq!(queue.next_retry(meanwhile), Some(start + wait));
        let mut now = start + wait;
        let mut waits = Vec::new();
        for _ in 0..10 {
            let ticket = queue.take(now).expect("ready after its backoff");
            assert_eq!(ticket.work, Work::Submission(1));
            let wait = queue.retry(ticket, now);
            waits.push(wait);
            now += wait;
        }
        assert!(waits.windows(2).all(|w| w[0] <= w[1]), "{waits:?}");
        assert_eq!(*waits.last().unwrap(), MAX_RETRY);
        assert_eq!(queue.waiting()[0].failed_starts, 11);
        assert_eq!(grade(&mut queue, now, QUICK), Work::Submission(1));
    }

    /// Someone waits for a phase: among students alike in their share, phases go first,
    /// then gradings, then regrades; but a student with a phase running, or charged for
    /// one, goes behind another's grading; and a cancelled phase leaves the line.
    #[test]
    fn interactive_phases_go_first_but_students_still_take_turns() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(
            Work::RegradeItem {
                regrade: 1,
                submission: 9,
            },
            Tenant::Regrades,
            start,
        );
        queue.push(Work::Submission(1), student("ada"), start);
        queue.push(Work::Phase(1), student("mallory"), start);
        queue.push(Work::Phase(2), student("mallory"), start);
        queue.push(Work::Phase(3), student("grace"), start);
        assert_eq!(queue.place(Work::Phase(1), start), Some(1));
        assert_eq!(queue.place(Work::Phase(3), start), Some(2));
        assert_eq!(queue.place(Work::Submission(7), start), None);
        let order: Vec<Work> = (0..3)
            .map(|i| grade(&mut queue, start + QUICK * i, QUICK))
            .collect();
        // Mallory's second phase waits behind Grace's first and, once Mallory has been
        // charged, behind Ada's grading too.
        assert_eq!(order, [Work::Phase(1), Work::Phase(3), Work::Submission(1)]);
        assert!(queue.cancel(Work::Phase(2)));
        assert!(!queue.cancel(Work::Phase(2)));
        assert_eq!(
            grade(&mut queue, start + QUICK * 3, QUICK),
            Work::RegradeItem {
                regrade: 1,
                submission: 9
            }
        );
        assert!(queue.waiting().is_empty());
        assert!(
            queue.push(Work::Phase(2), student("mallory"), start),
            "held no more"
        );
    }

    /// A grading the machine starved waits again like one that did not start, but its
    /// tenant is charged the time it held its place: a tenant whose work keeps starving
    /// goes behind the others.
    #[test]
    fn a_starved_grading_waits_again_and_its_student_is_charged() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(Work::Submission(1), student("mallory"), start);
        queue.push(Work::Submission(2), student("ada"), start);
        let ticket = queue.take(start).unwrap();
        let now = start + TO_THE_LIMITS;
        let wait = queue.starved(ticket, TO_THE_LIMITS, now);
        assert_eq!(wait, queue.policy().first_retry);
        assert_eq!(
            (queue.waiting()[1].starved, queue.waiting()[1].failed_starts),
            (1, 0)
        );
        assert!(queue.charge(&student("mallory"), now) > 17.0);
        assert_eq!(queue.lane(&student("mallory"), now), Lane::Background);
        assert_eq!(grade(&mut queue, now + wait, QUICK), Work::Submission(2));
    }

    #[test]
    fn a_lone_grading_starts_at_once() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(1));
        queue.push(Work::Submission(1), student("ada"), start);
        let ticket = queue.take(start).unwrap();
        assert_eq!(ticket.lane, Lane::Foreground);
        assert!(!queue.has(&Tenant::Regrades));
        assert!(queue.has(&student("ada")));
        queue.finish(ticket, QUICK, start + QUICK);
        assert!(!queue.has(&student("ada")));
    }

    /// The database is polled for work that is waiting or running here already: each is
    /// held once, and found again once it has ended (when another grader may have left it).
    #[test]
    fn a_work_is_held_once_until_it_ends() {
        let start = Instant::now();
        let mut queue = FairQueue::new(policy(2));
        assert!(queue.push(Work::Submission(1), student("ada"), start));
        assert!(!queue.push(Work::Submission(1), student("ada"), start));
        let ticket = queue.take(start).unwrap();
        assert!(
            !queue.push(Work::Submission(1), student("ada"), start),
            "running"
        );
        assert!(queue.take(start).is_none());
        queue.retry(ticket, start);
        assert!(
            !queue.push(Work::Submission(1), student("ada"), start),
            "waiting again"
        );
        let ticket = queue.take(start + Duration::from_secs(1)).unwrap();
        queue.finish(ticket, QUICK, start + QUICK);
        assert!(queue.push(Work::Submission(1), student("ada"), start));
    }
}
