//! The CPU time of a thread or a process (Linux's CPU clocks): what a student's code has
//! used of its limit, however many other processes share the cores.

use std::os::unix::process::ExitStatusExt;
use std::process::ExitStatus;
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

thread_local! {
    /// The CPU time of the workers this thread waited for to their end, in all.
    static WORKERS_SPENT: std::cell::Cell<Duration> = const { std::cell::Cell::new(Duration::ZERO) };
}

/// The CPU time that the worker processes this thread started have used in all, once
/// each ended (a worker's own, and that of every process it started and waited for: an
/// interpreter's jail, the interpreter): read before and after a work, it is what the
/// work's sandboxes cost, however busy the machine was.
pub fn workers_spent() -> Duration {
    WORKERS_SPENT.get()
}

/// Waits for the worker `pid` to end (blocking or not), and counts its CPU time in
/// [`workers_spent`]: its status once it has ended. The worker is reaped here, so its
/// `Child` is not waited for again.
pub(super) fn reap(pid: libc::pid_t, block: bool) -> std::io::Result<Option<ExitStatus>> {
    let mut status = 0;
    // SAFETY: rusage is plain data, valid when all zeros; wait4 writes it and the status
    // through valid pointers.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let flags = if block { 0 } else { libc::WNOHANG };
    // SAFETY: as above.
    let reaped = unsafe { libc::wait4(pid, &mut status, flags, &mut usage) };
    match reaped {
        -1 => Err(std::io::Error::last_os_error()),
        0 => Ok(None),
        _ => {
            let spent = time_of(usage.ru_utime) + time_of(usage.ru_stime);
            WORKERS_SPENT.set(WORKERS_SPENT.get() + spent);
            Ok(Some(ExitStatus::from_raw(status)))
        }
    }
}

fn time_of(time: libc::timeval) -> Duration {
    Duration::new(time.tv_sec as u64, time.tv_usec as u32 * 1_000)
}

/// The CPU time used so far by the processes that `thread` (of this process) started and
/// that run still, each with its descendants (those that run, and those it waited for):
/// what a work's worker has cost while it runs, read from `/proc`. Zero without `/proc`.
pub fn started_by(thread: libc::pid_t) -> Duration {
    let children = std::fs::read_to_string(format!("/proc/self/task/{thread}/children"));
    children.map_or(Duration::ZERO, |children| {
        children
            .split_whitespace()
            .filter_map(|pid| pid.parse().ok())
            .map(tree)
            .sum()
    })
}

/// The CPU time of process `pid` and of its descendants.
fn tree(pid: libc::pid_t) -> Duration {
    let Some(own) = used(pid) else {
        return Duration::ZERO;
    };
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return own;
    };
    let children: Duration = tasks
        .flatten()
        .filter_map(|task| std::fs::read_to_string(task.path().join("children")).ok())
        .flat_map(|children| {
            children
                .split_whitespace()
                .filter_map(|child| child.parse().ok())
                .collect::<Vec<libc::pid_t>>()
        })
        .map(tree)
        .sum();
    own + children
}

/// A process's CPU time and that of the children it waited for: `utime`, `stime`,
/// `cutime` and `cstime` in `/proc/PID/stat` (fields 14 to 17), in clock ticks.
fn used(pid: libc::pid_t) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // "pid (comm) state ppid ...": after the command, utime is the 12th field.
    let after = &stat[stat.rfind(')')? + 2..];
    let ticks: u64 = after
        .split(' ')
        .skip(11)
        .take(4)
        .map(|field| field.parse::<u64>().ok())
        .sum::<Option<u64>>()?;
    // SAFETY: sysconf has no pointer arguments.
    let per_second = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as u64;
    Some(Duration::from_nanos(ticks * 1_000_000_000 / per_second))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    /// A child that computes for a while: `sh` counting.
    fn busy_child() -> std::process::Child {
        Command::new("sh")
            .args(["-c", "i=0; while [ $i -lt 200000 ]; do i=$((i+1)); done"])
            .spawn()
            .unwrap()
    }

    #[test]
    #[expect(clippy::zombie_processes, reason = "`reap` waits for it")]
    fn a_reaped_workers_time_is_counted_on_the_thread_that_reaped_it() {
        std::thread::spawn(|| {
            let before = workers_spent();
            let child = busy_child();
            let status = reap(child.id() as libc::pid_t, true).unwrap().unwrap();
            assert!(status.success());
            let spent = workers_spent() - before;
            assert!(spent > Duration::ZERO, "the loop computed");
            // Another thread's count is its own.
            let other = std::thread::spawn(workers_spent).join().unwrap();
            assert_eq!(other, Duration::ZERO);
        })
        .join()
        .unwrap();
    }

    #[test]
    fn a_running_childs_time_is_read_from_proc() {
        std::thread::spawn(|| {
            // SAFETY: gettid has no arguments and cannot fail.
            let thread = unsafe { libc::gettid() };
            let mut child = Command::new("sh")
                .args(["-c", "while :; do :; done"])
                .spawn()
                .unwrap();
            // It computes: its time grows (read until it has, whatever the machine's load).
            while started_by(thread).is_zero() {
                std::thread::sleep(Duration::from_millis(10));
            }
            child.kill().unwrap();
            child.wait().unwrap();
            assert_eq!(started_by(thread), Duration::ZERO, "none runs");
        })
        .join()
        .unwrap();
    }
}
