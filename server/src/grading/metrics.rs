//! What an operator watches of a process's sandbox work, in Prometheus's text format
//! (`/metrics`, and `estlab grader --metrics`): each lane's depth and the age of its
//! oldest work, the sandboxes running against their cap, the CPU time each kind of work
//! used, how each work's turn ended, and the leases lost. README's "What to watch" says
//! what each tells.

use super::fair::{Waiting, Work};
use prometheus_client::encoding::{EncodeLabelSet, EncodeLabelValue, LabelValueEncoder};
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::registry::Registry;
use std::fmt::Write as _;
use std::sync::atomic::AtomicU64;
use std::time::{Duration, Instant};

/// A lane: the kind of work it holds.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Kind {
    Phase,
    Grading,
    ReportRuns,
    Regrade,
}

impl Kind {
    const ALL: [Kind; 4] = [Kind::Phase, Kind::Grading, Kind::ReportRuns, Kind::Regrade];

    fn of(work: Work) -> Kind {
        match work {
            Work::Phase(_) => Kind::Phase,
            Work::Submission(_) => Kind::Grading,
            Work::ReportRuns(_) => Kind::ReportRuns,
            Work::RegradeItem { .. } => Kind::Regrade,
        }
    }
}

impl EncodeLabelValue for Kind {
    fn encode(&self, encoder: &mut LabelValueEncoder) -> Result<(), std::fmt::Error> {
        encoder.write_str(match self {
            Kind::Phase => "phase",
            Kind::Grading => "grading",
            Kind::ReportRuns => "report_runs",
            Kind::Regrade => "regrade",
        })
    }
}

/// How a work's turn in the sandbox ended.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Outcome {
    /// Its result is stored, or handed to whoever asked.
    Done,
    /// Another grader held it, or had done it: nothing was done here.
    Elsewhere,
    /// Its sandbox did not start: it waits again.
    DidNotStart,
    /// The machine gave its sandbox too little time: it waits again.
    Starved,
    /// The server could not do it (starved too often, its database, a panic): a
    /// submission ends "not gradable", which costs its student nothing.
    GivenUp,
    /// Its lease was lost meanwhile (the process stalled, or the database was out of
    /// reach): its result is not written, and another grader does it.
    LeaseLost,
}

impl EncodeLabelValue for Outcome {
    fn encode(&self, encoder: &mut LabelValueEncoder) -> Result<(), std::fmt::Error> {
        encoder.write_str(match self {
            Outcome::Done => "done",
            Outcome::Elsewhere => "elsewhere",
            Outcome::DidNotStart => "did_not_start",
            Outcome::Starved => "starved",
            Outcome::GivenUp => "given_up",
            Outcome::LeaseLost => "lease_lost",
        })
    }
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct OfKind {
    kind: Kind,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct Ended {
    kind: Kind,
    outcome: Outcome,
}

/// A process's metrics: counters kept as work ends, gauges set from the queue when read.
pub struct Metrics {
    registry: Registry,
    waiting: Family<OfKind, Gauge>,
    oldest: Family<OfKind, Gauge<f64, AtomicU64>>,
    running: Gauge,
    cap: Gauge,
    cpu: Family<OfKind, Counter<f64, AtomicU64>>,
    ended: Family<Ended, Counter>,
    leases_lost: Counter,
}

impl Metrics {
    pub fn new() -> Metrics {
        let mut metrics = Metrics {
            registry: Registry::with_prefix("estlab_sandbox"),
            waiting: Family::default(),
            oldest: Family::default(),
            running: Gauge::default(),
            cap: Gauge::default(),
            cpu: Family::default(),
            ended: Family::default(),
            leases_lost: Counter::default(),
        };
        let registry = &mut metrics.registry;
        registry.register(
            "waiting",
            "Works waiting for a sandbox, by lane",
            metrics.waiting.clone(),
        );
        registry.register(
            "oldest_wait_seconds",
            "How long the oldest work of each lane has waited (0: none waits)",
            metrics.oldest.clone(),
        );
        registry.register("running", "Sandboxes running now", metrics.running.clone());
        registry.register(
            "cap",
            "The most sandboxes that run at once, both lanes together",
            metrics.cap.clone(),
        );
        registry.register(
            "cpu_seconds",
            "CPU time the sandboxes of each kind of work used, read from the kernel",
            metrics.cpu.clone(),
        );
        registry.register(
            "ended",
            "Works whose turn in a sandbox ended, by kind and outcome",
            metrics.ended.clone(),
        );
        registry.register(
            "leases_lost",
            "Leases found lost while their work ran (another grader may take it)",
            metrics.leases_lost.clone(),
        );
        for kind in Kind::ALL {
            // Every kind shows from the start (the lanes' gauges are set at each read).
            metrics.cpu.get_or_create(&OfKind { kind }).inc_by(0.0);
        }
        metrics
    }

    /// A work's turn ended as `outcome`, its sandbox having used `cpu`.
    pub fn ended(&self, work: Work, outcome: Outcome, cpu: Duration) {
        let kind = Kind::of(work);
        self.cpu
            .get_or_create(&OfKind { kind })
            .inc_by(cpu.as_secs_f64());
        self.ended.get_or_create(&Ended { kind, outcome }).inc();
    }

    pub fn lease_lost(&self) {
        self.leases_lost.inc();
    }

    /// The metrics as of `now`, with the queue's `waiting` works and `running` sandboxes
    /// of at most `cap`, in Prometheus's text format.
    pub fn render(
        &self,
        waiting: &[Waiting],
        (running, cap): (usize, usize),
        now: Instant,
    ) -> String {
        for kind in Kind::ALL {
            let of_kind = waiting.iter().filter(|w| Kind::of(w.work) == kind);
            let label = OfKind { kind };
            self.waiting
                .get_or_create(&label)
                .set(of_kind.clone().count() as i64);
            let oldest = of_kind
                .map(|w| now.saturating_duration_since(w.since))
                .max()
                .unwrap_or_default();
            self.oldest.get_or_create(&label).set(oldest.as_secs_f64());
        }
        self.running.set(running as i64);
        self.cap.set(cap as i64);
        let mut text = String::new();
        prometheus_client::encoding::text::encode(&mut text, &self.registry)
            .expect("writing to a String cannot fail");
        text
    }
}

impl Default for Metrics {
    fn default() -> Metrics {
        Metrics::new()
    }
}
