//! The CPU time of the calling thread (Linux's `CLOCK_THREAD_CPUTIME_ID`): what a
//! student's code has used of its limit, however many other processes share the cores.

use std::time::Duration;

/// A stopwatch of this thread's CPU time. Read it on the thread that started it.
pub struct ThreadClock {
    start: std::cell::Cell<Duration>,
}

impl ThreadClock {
    pub fn start() -> ThreadClock {
        ThreadClock {
            start: std::cell::Cell::new(now()),
        }
    }

    pub fn restart(&self) {
        self.start.set(now());
    }

    /// CPU time this thread used since the start.
    pub fn elapsed(&self) -> Duration {
        now().saturating_sub(self.start.get())
    }
}

fn now() -> Duration {
    let mut time = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer; the thread CPU
    // clock exists on every Linux since 2.6.12, so it cannot fail with a valid clock id.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut time) };
    assert_eq!(status, 0, "the thread CPU clock is unavailable");
    Duration::new(time.tv_sec as u64, time.tv_nsec as u32)
}
