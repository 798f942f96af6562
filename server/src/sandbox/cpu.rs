//! The CPU time of a thread or a process (Linux's CPU clocks): what a student's code has
//! used of its limit, however many other processes share the cores.

use std::time::Duration;

/// A thread's CPU clock, which any thread of the process may read, or a process's.
#[derive(Clone, Copy, Debug)]
pub struct CpuClock(libc::clockid_t);

impl CpuClock {
    /// The clock of the calling thread.
    pub fn of_this_thread() -> CpuClock {
        let mut clock: libc::clockid_t = 0;
        // SAFETY: pthread_self is always valid for the caller, and the call writes one
        // clockid_t through a valid pointer.
        let status = unsafe { libc::pthread_getcpuclockid(libc::pthread_self(), &mut clock) };
        assert_eq!(status, 0, "this thread's CPU clock is unavailable");
        CpuClock(clock)
    }

    /// The clock of a process (every thread of it), which Linux lets any process read.
    /// None when there is no such process.
    pub fn of_process(pid: libc::pid_t) -> Option<CpuClock> {
        let mut clock: libc::clockid_t = 0;
        // SAFETY: the call writes one clockid_t through a valid pointer.
        let status = unsafe { libc::clock_getcpuclockid(pid, &mut clock) };
        (status == 0).then_some(CpuClock(clock))
    }

    /// The CPU time the thread has used, or None once it has ended.
    pub fn read(self) -> Option<Duration> {
        let mut time = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec through a valid pointer; a clock of a
        // thread that has ended gives an error, not undefined behaviour.
        let status = unsafe { libc::clock_gettime(self.0, &mut time) };
        (status == 0).then(|| Duration::new(time.tv_sec as u64, time.tv_nsec as u32))
    }
}

/// A stopwatch of this thread's CPU time. Read it on the thread that started it.
pub struct ThreadClock {
    clock: CpuClock,
    start: std::cell::Cell<Duration>,
}

impl ThreadClock {
    pub fn start() -> ThreadClock {
        let clock = CpuClock::of_this_thread();
        ThreadClock {
            clock,
            start: std::cell::Cell::new(now(clock)),
        }
    }

    pub fn restart(&self) {
        self.start.set(now(self.clock));
    }

    /// CPU time this thread used since the start.
    pub fn elapsed(&self) -> Duration {
        self.now().saturating_sub(self.start.get())
    }

    /// CPU time this thread used in all.
    pub fn now(&self) -> Duration {
        now(self.clock)
    }
}

fn now(clock: CpuClock) -> Duration {
    clock
        .read()
        .expect("a running thread's own CPU clock can be read")
}
