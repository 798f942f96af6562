//! A watch on every engine's CPU time from outside the engines. QuickJS looks at its
//! clock (the interrupt handler) between bytecode steps only, so one built-in call on
//! huge data (a naive `indexOf` of a long string, the digits of a huge BigInt) can run for
//! a minute without a look. Each engine thread shows the watchdog a [`Pulse`]: the CPU
//! time at which its engine last looked at its clock, and what it is running. When a
//! thread has used [`STALL`] of CPU time since its engine last looked, the watchdog ends
//! the whole worker process with [`OVERRUN_EXIT`], naming the call and the phase on
//! stderr: the student's code, not the sandbox, and the server grades it so.
//!
//! A stalled call is so ended within a second of CPU time, whatever the phase's limit,
//! plus at most one [`PATROL`] (20 ms): no legitimate call of a student's code runs that
//! long without the engine looking (it looks every 10,000 bytecode steps or so, and the
//! allocator counts a large block as a look: see `memory::LOOKS_FROM`).

use super::cpu::CpuClock;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The worker's exit code when the watchdog ended it.
pub const OVERRUN_EXIT: i32 = 3;
/// What starts the watchdog's line on stderr; the call and the phase follow.
pub const OVERRUN_PREFIX: &str = "estlab-sandbox overran: ";
/// How much CPU time a thread may use without its engine looking at its clock.
const STALL: Duration = Duration::from_secs(1);
/// How often the watchdog looks.
const PATROL: Duration = Duration::from_millis(20);

/// What an engine's thread shows the watchdog, written by the engine.
#[derive(Default)]
pub struct Pulse {
    /// What the engine runs now, as the harness said it (a case, a step of a run).
    running: Mutex<String>,
    /// The thread's CPU time, in nanoseconds, when its engine last looked at its clock.
    looked_ns: AtomicU64,
}

impl Pulse {
    /// The engine is about to run `label`.
    pub fn running(&self, label: String) {
        *self.running.lock().unwrap_or_else(|e| e.into_inner()) = label;
    }

    /// What the engine runs now (empty before the harness said).
    pub fn label(&self) -> String {
        self.running
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The engine looked at its clock when its thread had used `cpu`.
    pub fn looked(&self, cpu: Duration) {
        self.looked_ns.store(nanos(cpu), Ordering::Relaxed);
    }

    fn looked_at(&self) -> Duration {
        Duration::from_nanos(self.looked_ns.load(Ordering::Relaxed))
    }
}

fn nanos(time: Duration) -> u64 {
    u64::try_from(time.as_nanos()).unwrap_or(u64::MAX)
}

/// One phase being watched: its thread's clock and its engine's pulse.
struct Watch {
    clock: CpuClock,
    phase: String,
    pulse: Arc<Pulse>,
}

impl Watch {
    /// The call and the phase, as the student reads them (the harness's labels start with
    /// their phase's name: `o3/sequential: at time step 1, predict`, `predict/p3`).
    fn stalled(&self) -> String {
        match self.pulse.label() {
            label if label.is_empty() => self.phase.clone(),
            label if label.starts_with(&self.phase) => label,
            label => format!("{label}, in the phase {}", self.phase),
        }
    }
}

/// Watches the engines of one worker, one slot per engine thread.
pub struct Watchdog {
    slots: Vec<Mutex<Option<Watch>>>,
    done: AtomicBool,
}

/// Keeps a phase watched while it lives.
pub struct Watching<'a> {
    slot: &'a Mutex<Option<Watch>>,
}

impl Drop for Watching<'_> {
    fn drop(&mut self) {
        *self.slot.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }
}

impl Watchdog {
    pub fn new(slots: usize) -> Watchdog {
        Watchdog {
            slots: (0..slots).map(|_| Mutex::new(None)).collect(),
            done: AtomicBool::new(false),
        }
    }

    /// Watches the phase `phase` that the calling thread runs now, in slot `slot`, by the
    /// engine's `pulse`, until the returned guard is dropped.
    pub fn watch(&self, slot: usize, phase: &str, pulse: Arc<Pulse>) -> Watching<'_> {
        let clock = CpuClock::of_this_thread();
        // The watch starts as if the engine had just looked.
        pulse.looked(clock.read().unwrap_or_default());
        let slot = &self.slots[slot];
        *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(Watch {
            clock,
            phase: phase.to_owned(),
            pulse,
        });
        Watching { slot }
    }

    /// Looks at every watched phase until [`Watchdog::stop`]; ends the process when one
    /// has stalled in a single call.
    pub fn patrol(&self) {
        while !self.done.load(Ordering::Relaxed) {
            for slot in &self.slots {
                let watch = slot.lock().unwrap_or_else(|e| e.into_inner());
                let Some(watch) = watch.as_ref() else {
                    continue;
                };
                let unlooked = watch.clock.read().map_or(Duration::ZERO, |now| {
                    now.saturating_sub(watch.pulse.looked_at())
                });
                if unlooked > STALL {
                    eprintln!("{OVERRUN_PREFIX}{}", watch.stalled());
                    std::process::exit(OVERRUN_EXIT);
                }
            }
            std::thread::sleep(PATROL);
        }
    }

    pub fn stop(&self) {
        self.done.store(true, Ordering::Relaxed);
    }
}
