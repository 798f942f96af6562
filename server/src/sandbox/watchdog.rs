//! A watch on every engine's CPU time from outside the engines. QuickJS checks its limit
//! between bytecode steps only, so one built-in call on huge data (a naive `indexOf` of a
//! long string, the digits of a huge BigInt) can run for a minute without a check. The
//! watchdog reads each engine thread's CPU clock, and when a phase runs on past its limit
//! by [`GRACE`], it ends the whole worker process with [`OVERRUN_EXIT`], naming the phase
//! on stderr: the student's code, not the sandbox, and the server grades it so.

use super::cpu::CpuClock;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The worker's exit code when the watchdog ended it.
pub const OVERRUN_EXIT: i32 = 3;
/// What starts the watchdog's line on stderr; the phase's name follows.
pub const OVERRUN_PREFIX: &str = "estlab-sandbox overran: ";
/// How far past its limit a phase may get inside one call before the worker is ended.
const GRACE: Duration = Duration::from_secs(1);
/// How often the watchdog looks.
const PATROL: Duration = Duration::from_millis(20);

/// One phase being watched: the thread's clock and where it stood at the start.
struct Watch {
    clock: CpuClock,
    started: Duration,
    limit: Duration,
    phase: String,
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

    /// Watches the phase `phase` that the calling thread runs now, in slot `slot`, with
    /// `limit` of CPU time, until the returned guard is dropped.
    pub fn watch(&self, slot: usize, phase: &str, limit: Duration) -> Watching<'_> {
        let clock = CpuClock::of_this_thread();
        let started = clock.read().unwrap_or_default();
        let slot = &self.slots[slot];
        *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(Watch {
            clock,
            started,
            limit,
            phase: phase.to_owned(),
        });
        Watching { slot }
    }

    /// Looks at every watched phase until [`Watchdog::stop`]; ends the process when one
    /// has run past its limit by the grace.
    pub fn patrol(&self) {
        while !self.done.load(Ordering::Relaxed) {
            for slot in &self.slots {
                let watch = slot.lock().unwrap_or_else(|e| e.into_inner());
                let Some(watch) = watch.as_ref() else {
                    continue;
                };
                let used = watch
                    .clock
                    .read()
                    .map_or(Duration::ZERO, |now| now.saturating_sub(watch.started));
                if used > watch.limit + GRACE {
                    eprintln!("{OVERRUN_PREFIX}{}", watch.phase);
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
