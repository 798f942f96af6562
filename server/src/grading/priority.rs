//! The background lane's CPU priority. A grading there has its worker process set to
//! nice 10, so that it runs mostly on the CPU the foreground gradings leave: on the
//! engines' own CPU clocks its verdict is the same, only later. Linux weighs a thread at
//! nice 10 about a tenth of one at nice 0 (110 against 1024), so a foreground grading
//! beside one background thread gets about nine tenths of its core, and a background one
//! still gets a tenth when other programs keep the machine busy. (At nice 19, a weight of
//! 15, it got 1.5 % beside two busy programs, and a file of a few seconds took minutes:
//! tests/e2e/integrity.test.mjs.) The worker is found
//! as the child of the thread that grades (`/proc/self/task/TID/children`), and every one
//! of its threads is lowered (Linux keeps a priority per thread; a thread started after
//! a sweep inherits it from the thread that started it, and the next sweep catches one
//! started during a sweep). Without `/proc` nothing is lowered, and the lane only frees
//! the foreground's slots.

use std::fs;

/// The background lane's priority, as a nice value.
pub const BACKGROUND: libc::c_int = 10;

/// The id of the calling thread, whose children `lower_children_of` finds.
pub fn current_thread() -> libc::pid_t {
    // SAFETY: gettid has no arguments and cannot fail.
    unsafe { libc::gettid() }
}

/// Sets every thread of every process that `thread` (of this process) started to the
/// background lane's CPU priority. Raising a nice value needs no privilege; lowering it again would,
/// which is why the grading thread itself is left alone.
pub fn lower_children_of(thread: libc::pid_t) {
    let Ok(children) = fs::read_to_string(format!("/proc/self/task/{thread}/children")) else {
        return;
    };
    for child in children.split_whitespace() {
        let Ok(tasks) = fs::read_dir(format!("/proc/{child}/task")) else {
            continue;
        };
        for task in tasks.flatten() {
            if let Some(tid) = task.file_name().to_str().and_then(|t| t.parse().ok()) {
                // SAFETY: a plain system call on a thread id; a thread that has ended
                // meanwhile makes it fail, which changes nothing.
                unsafe {
                    libc::setpriority(libc::PRIO_PROCESS, tid, BACKGROUND);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::{Command, Stdio};

    fn nice_of(pid: u32) -> i64 {
        let stat = fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
        // "pid (comm) state ...": nice is field 19, the 17th after the command.
        let fields: Vec<&str> = stat[stat.rfind(')').unwrap() + 2..].split(' ').collect();
        fields[16].parse().unwrap()
    }

    #[test]
    fn a_child_of_the_thread_is_lowered_and_the_thread_is_not() {
        let before = nice_of(std::process::id());
        let (pid, lowered) = std::thread::spawn(|| {
            let mut child = Command::new("sleep")
                .arg("5")
                .stdout(Stdio::null())
                .spawn()
                .unwrap();
            lower_children_of(current_thread());
            let lowered = nice_of(child.id());
            child.kill().unwrap();
            child.wait().unwrap();
            (child.id(), lowered)
        })
        .join()
        .unwrap();
        assert_eq!(lowered, i64::from(BACKGROUND), "child {pid}");
        assert_eq!(nice_of(std::process::id()), before);
    }
}
