//! The operating-system sandbox of a native interpreter: bubblewrap (Debian's `bwrap`)
//! starts it in fresh namespaces (no network, not even loopback; its own process ids,
//! where it is process 1; its own mounts: `/usr` read-only with the dynamic linker's few
//! files of `/etc`, its own `/proc`, `/dev` and a small `/tmp`, and nothing else of the
//! machine: no server data, no secret, no other student's file; `/proc/sys` read-only),
//! as a user of no privileges and no capabilities (a server run as root starts it as a
//! user of its own: inside a user namespace, root outside stays root for the kernel's
//! files), in a session of its own, with a system-call filter (seccomp, compiled by
//! seccompiler: no new processes, threads only, no tracing, no sockets, no mounts or
//! namespaces, no kernel keyrings, BPF, io_uring or `perf_event_open`), and with
//! resource limits (address space, file size, open files, tasks, CPU time, no core
//! dumps). It dies with the thread that started it.

use super::super::cpu::CpuClock;
use seccompiler::{
    BpfProgram, SeccompAction, SeccompCmpArgLen, SeccompCmpOp, SeccompCondition, SeccompFilter,
    SeccompRule, sock_filter,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Child, ChildStderr, ChildStdin, ChildStdout, Command, Stdio};

/// Address space for the interpreter and the student's data (NumPy with its libraries
/// maps about 100 MB before any data).
pub const MEMORY_LIMIT: u64 = 1 << 30;
/// The largest file the student's code may write (in its own `/tmp`, itself at most
/// [`TMP_SIZE`]).
const FILE_SIZE_LIMIT: u64 = 1 << 20;
const TMP_SIZE: u64 = 16 << 20;
/// Descriptors the interpreter may hold open.
const OPEN_FILES: u64 = 64;
/// The user and group the student's code runs as inside the sandbox (`nobody`), and the
/// group a server run as root starts it as.
const NOBODY: libc::uid_t = 65534;
/// A server run as root starts each sandbox as a user of its own, this plus the pid of
/// the process that becomes bubblewrap (unique among the living): no user of the machine,
/// and the one the count of processes below is kept for.
const JAIL_USERS: libc::uid_t = 0x6000_0000;
/// Processes and threads the sandbox may have at once, bubblewrap's own included (Octave
/// makes one thread, Python none): threads are allowed, and a loop that makes them would
/// otherwise take the machine's every process id.
const TASKS: u64 = 32;
/// Where the filter and the sandbox's report reach bubblewrap.
const SECCOMP_FD: RawFd = 3;
const INFO_FD: RawFd = 4;
/// Where a program that says what it is doing writes it, when its invocation asks for
/// such a descriptor (see [`Progress`]).
pub const PROGRESS_FD: RawFd = 5;
/// The bytes of a [`Progress`]: the longest label the harness writes is a few hundred.
const PROGRESS_SIZE: usize = 4096;

/// The programs a jail is made of, found once where the server starts.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Tools {
    pub bwrap: PathBuf,
    pub interpreter: PathBuf,
}

/// What a jail runs: the interpreter's arguments and its environment.
pub struct Invocation<'a> {
    pub args: &'a [&'a str],
    pub env: &'a [(&'a str, &'a str)],
    /// CPU time for the whole process, in seconds: the kernel's backstop behind the
    /// phases' own limits.
    pub cpu_seconds: u64,
    /// Whether the program is given a [`Progress`] to write on, as [`PROGRESS_FD`].
    pub progress: bool,
}

/// An interpreter running in its jail.
pub struct Jailed {
    pub child: Child,
    /// The interpreter's process as a descriptor (`pidfd_open`), by which it is ended.
    pub pidfd: OwnedFd,
    pub stdin: ChildStdin,
    pub stdout: ChildStdout,
    pub stderr: ChildStderr,
    /// The interpreter's process id as the server sees it.
    pub pid: libc::pid_t,
    /// Its CPU clock (every thread of it).
    pub clock: CpuClock,
    /// What it says it is doing, if its invocation asked for a progress descriptor.
    pub progress: Option<Progress>,
}

/// Where a program in a jail says what it is doing, read by the server only when it stops
/// the program: a file in memory of [`PROGRESS_SIZE`] bytes, sealed at that size, which
/// the program overwrites from its start with a text ended by a zero byte. A pipe would
/// wake the server for every line; a whole data set's run says where it is 13,000 times.
pub struct Progress(File);

impl Progress {
    fn new() -> std::io::Result<Progress> {
        // SAFETY: memfd_create reads a valid C string; the descriptor is owned here alone.
        let fd = unsafe {
            libc::memfd_create(
                c"estlab-progress".as_ptr(),
                libc::MFD_CLOEXEC | libc::MFD_ALLOW_SEALING,
            )
        };
        if fd < 0 {
            return Err(std::io::Error::last_os_error());
        }
        // SAFETY: the descriptor was just made and is owned here alone.
        let file = File::from(above(unsafe { OwnedFd::from_raw_fd(fd) })?);
        file.set_len(PROGRESS_SIZE as u64)?;
        let seals = libc::F_SEAL_GROW | libc::F_SEAL_SHRINK | libc::F_SEAL_SEAL;
        // SAFETY: F_ADD_SEALS changes only the file's seals.
        if unsafe { libc::fcntl(file.as_raw_fd(), libc::F_ADD_SEALS, seals) } < 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(Progress(file))
    }

    /// What the program last said it was doing (empty once cleared, or if it said nothing).
    pub fn read(&self) -> String {
        let mut bytes = vec![0; PROGRESS_SIZE];
        let read = std::os::unix::fs::FileExt::read_at(&self.0, &mut bytes, 0).unwrap_or(0);
        bytes.truncate(read);
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        String::from_utf8_lossy(&bytes[..end]).into_owned()
    }

    /// Forgets what the program said, before it is asked to do something else.
    pub fn clear(&self) {
        let _ = std::os::unix::fs::FileExt::write_at(&self.0, &[0], 0);
    }
}

/// Why a jail did not start.
#[derive(Debug, thiserror::Error)]
pub enum Refused {
    #[error("bubblewrap could not be started: {0}")]
    Spawn(std::io::Error),
    #[error("the sandbox could not be set up: {0}")]
    Setup(std::io::Error),
    #[error("bubblewrap did not start the interpreter{}", said(.0))]
    NotStarted(String),
}

fn said(complaints: &str) -> String {
    match complaints.trim() {
        "" => String::new(),
        text => format!(": {text}"),
    }
}

impl Tools {
    /// Starts the interpreter in a jail of its own.
    pub fn jail(&self, invocation: &Invocation) -> Result<Jailed, Refused> {
        let filter = filter_program().map_err(Refused::Setup)?;
        let (filter_read, filter_write) = pipe().map_err(Refused::Setup)?;
        let (info_read, info_write) = pipe().map_err(Refused::Setup)?;
        // The program is a few hundred bytes: it fits the pipe's buffer before bwrap reads.
        File::from(filter_write)
            .write_all(&filter)
            .map_err(Refused::Setup)?;

        let mut command = Command::new(&self.bwrap);
        command
            .args(self.arguments(invocation))
            .env_clear()
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let (filter_fd, info_fd) = (filter_read.as_raw_fd(), info_write.as_raw_fd());
        let progress = invocation
            .progress
            .then(Progress::new)
            .transpose()
            .map_err(Refused::Setup)?;
        let progress_fd = progress.as_ref().map(|progress| progress.0.as_raw_fd());
        let cpu = invocation.cpu_seconds;
        // A server run as root counts each sandbox's tasks under a user of its own; any
        // other counts its user's tasks, the server's too, and lets the sandbox add
        // [`TASKS`] to those it has now.
        // SAFETY: geteuid reads this process's credentials.
        let tasks = if unsafe { libc::geteuid() } == 0 {
            TASKS
        } else {
            tasks_of(unsafe { libc::getuid() }) + TASKS
        };
        // SAFETY: between fork and exec the closure calls only async-signal-safe system
        // calls (dup2, prctl, setrlimit, getpid, setuid) and allocates nothing.
        unsafe {
            command.pre_exec(move || before_exec((filter_fd, info_fd, progress_fd), cpu, tasks));
        }
        let mut child = command.spawn().map_err(Refused::Spawn)?;
        drop((filter_read, info_write));
        let mut stderr = child.stderr.take().expect("piped stderr");
        let mut info = String::new();
        let _ = File::from(info_read).take(4096).read_to_string(&mut info);
        let started = serde_json::from_str::<Info>(&info)
            .ok()
            .and_then(|info| Some((info.child_pid, CpuClock::of_process(info.child_pid)?)));
        let (pid, clock) = match started {
            Some(started) => started,
            None => {
                let _ = child.kill();
                let _ = child.wait();
                let mut complaints = String::new();
                let _ = (&mut stderr).take(4096).read_to_string(&mut complaints);
                return Err(Refused::NotStarted(complaints));
            }
        };
        let pidfd = match pidfd_open(pid) {
            Ok(pidfd) => pidfd,
            Err(e) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(Refused::Setup(e));
            }
        };
        let stdin = child.stdin.take().expect("piped stdin");
        set_nonblocking(&stdin).map_err(Refused::Setup)?;
        Ok(Jailed {
            pidfd,
            stdin,
            stdout: child.stdout.take().expect("piped stdout"),
            stderr,
            clock,
            pid,
            child,
            progress,
        })
    }

    fn arguments(&self, invocation: &Invocation) -> Vec<String> {
        let mut args: Vec<String> = [
            "--unshare-all",
            "--unshare-user",
            "--uid",
            &NOBODY.to_string(),
            "--gid",
            &NOBODY.to_string(),
            "--hostname",
            "sandbox",
            "--die-with-parent",
            "--new-session",
            "--as-pid-1",
            "--cap-drop",
            "ALL",
            "--ro-bind",
            "/usr",
            "/usr",
            "--symlink",
            "usr/lib",
            "/lib",
            "--symlink",
            "usr/lib64",
            "/lib64",
            "--symlink",
            "usr/bin",
            "/bin",
            // The dynamic linker's cache, and the alternatives its libraries go through
            // (NumPy's BLAS and LAPACK).
            "--ro-bind",
            "/etc/ld.so.cache",
            "/etc/ld.so.cache",
            "--ro-bind",
            "/etc/alternatives",
            "/etc/alternatives",
            "--proc",
            "/proc",
            // The kernel's settings, read-only whoever runs the sandbox.
            "--ro-bind",
            "/proc/sys",
            "/proc/sys",
            "--dev",
            "/dev",
            "--size",
            &TMP_SIZE.to_string(),
            "--tmpfs",
            "/tmp",
            "--chdir",
            "/tmp",
            // Nothing writable but /tmp: the root and /dev that bubblewrap makes are
            // memory too, as large as half the machine's.
            "--remount-ro",
            "/dev",
            "--remount-ro",
            "/",
            "--clearenv",
            "--seccomp",
            &SECCOMP_FD.to_string(),
            "--info-fd",
            &INFO_FD.to_string(),
        ]
        .map(str::to_owned)
        .into();
        for (name, value) in invocation.env {
            args.extend([
                "--setenv".to_owned(),
                (*name).to_owned(),
                (*value).to_owned(),
            ]);
        }
        args.push("--".to_owned());
        args.push(self.interpreter.display().to_string());
        args.extend(invocation.args.iter().map(|&arg| arg.to_owned()));
        args
    }
}

/// A descriptor of the process `pid`.
fn pidfd_open(pid: libc::pid_t) -> std::io::Result<OwnedFd> {
    // SAFETY: pidfd_open takes a number and flags and makes a new descriptor, ours alone.
    let fd = unsafe { libc::syscall(libc::SYS_pidfd_open, pid, 0) };
    if fd < 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(unsafe { OwnedFd::from_raw_fd(fd as RawFd) })
}

/// Writes to `fd` return at once when they cannot go on (the engine waits as it decides).
fn set_nonblocking(fd: &impl AsRawFd) -> std::io::Result<()> {
    // SAFETY: fcntl reads and sets the flags of a descriptor of ours.
    unsafe {
        let flags = libc::fcntl(fd.as_raw_fd(), libc::F_GETFL);
        if flags < 0 || libc::fcntl(fd.as_raw_fd(), libc::F_SETFL, flags | libc::O_NONBLOCK) < 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    Ok(())
}

/// What bubblewrap reports on its info descriptor once the interpreter runs.
#[derive(Deserialize)]
struct Info {
    #[serde(rename = "child-pid")]
    child_pid: libc::pid_t,
}

/// A pipe whose ends are not inherited, numbered above the descriptors the child is given
/// (so that moving one into place cannot overwrite the other).
fn pipe() -> std::io::Result<(OwnedFd, OwnedFd)> {
    let mut fds = [0; 2];
    // SAFETY: pipe2 writes two descriptors into a valid array of two.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: both descriptors were just made and are owned here alone.
    let [read, write] = fds.map(|fd| unsafe { OwnedFd::from_raw_fd(fd) });
    Ok((above(read)?, above(write)?))
}

fn above(fd: OwnedFd) -> std::io::Result<OwnedFd> {
    // SAFETY: F_DUPFD_CLOEXEC makes a new descriptor, which is owned here alone.
    let moved = unsafe { libc::fcntl(fd.as_raw_fd(), libc::F_DUPFD_CLOEXEC, 10) };
    if moved < 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(unsafe { OwnedFd::from_raw_fd(moved) })
}

/// In bubblewrap's process, before it runs: the filter, the info descriptor and the
/// progress descriptor (if any) in their places, death with the thread that started it,
/// and the limits, which its interpreter inherits.
fn before_exec(
    (filter, info, progress): (RawFd, RawFd, Option<RawFd>),
    cpu_seconds: u64,
    tasks: u64,
) -> std::io::Result<()> {
    let check = |status: libc::c_int| {
        if status < 0 {
            Err(std::io::Error::last_os_error())
        } else {
            Ok(())
        }
    };
    // A limit is only ever lowered: one this process inherited stays where it is tighter
    // (the worker's CPU time, which a kept V8 process's backstop may exceed), and raising
    // a hard limit would take a privilege given up with root.
    let limit = |resource, soft: u64, hard: u64| {
        let mut inherited = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes one valid rlimit.
        check(unsafe { libc::getrlimit(resource, &mut inherited) })?;
        let hard = hard.min(inherited.rlim_max);
        let limit = libc::rlimit {
            rlim_cur: soft.min(hard),
            rlim_max: hard,
        };
        // SAFETY: setrlimit reads one valid rlimit.
        check(unsafe { libc::setrlimit(resource, &limit) })
    };
    // SAFETY: plain system calls on this process's own descriptors and credentials.
    unsafe {
        check(libc::dup2(filter, SECCOMP_FD))?;
        check(libc::dup2(info, INFO_FD))?;
        if let Some(progress) = progress {
            check(libc::dup2(progress, PROGRESS_FD))?;
        }
        // A server run as root gives up root first: bubblewrap maps the user inside the
        // sandbox to the user that starts it, and the root of the machine inside, even
        // without capabilities, owns what root owns outside (the kernel's sysctls, whose
        // core_pattern runs a program as root).
        if libc::geteuid() == 0 {
            check(libc::setgroups(0, std::ptr::null()))?;
            check(libc::setgid(NOBODY))?;
            check(libc::setuid(JAIL_USERS + libc::getpid() as libc::uid_t))?;
        }
        // After the change of user, which clears it.
        check(libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL))?;
    }
    // Nothing the server inherited reaches the sandbox: every other descriptor is closed
    // at exec (marked, not closed, so that the spawn still hears of a failed exec).
    let last = if progress.is_some() {
        PROGRESS_FD
    } else {
        INFO_FD
    };
    super::super::close_others_at_exec(last + 1)?;
    limit(libc::RLIMIT_AS, MEMORY_LIMIT, MEMORY_LIMIT)?;
    limit(libc::RLIMIT_FSIZE, FILE_SIZE_LIMIT, FILE_SIZE_LIMIT)?;
    limit(libc::RLIMIT_NOFILE, OPEN_FILES, OPEN_FILES)?;
    limit(libc::RLIMIT_CORE, 0, 0)?;
    limit(libc::RLIMIT_NPROC, tasks, tasks)?;
    limit(libc::RLIMIT_CPU, cpu_seconds, cpu_seconds + 1)
}

/// The tasks (processes and threads) of the user `uid` on the machine now.
fn tasks_of(uid: libc::uid_t) -> u64 {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return 0;
    };
    entries
        .filter_map(Result::ok)
        .filter(|entry| {
            entry
                .file_name()
                .to_string_lossy()
                .bytes()
                .all(|b| b.is_ascii_digit())
        })
        .filter_map(|entry| std::fs::read_to_string(entry.path().join("status")).ok())
        .filter_map(|status| {
            let field = |name: &str| {
                status
                    .lines()
                    .find_map(|line| line.strip_prefix(name))
                    .and_then(|rest| rest.split_whitespace().next()?.parse::<u64>().ok())
            };
            (field("Uid:")? == u64::from(uid)).then(|| field("Threads:"))?
        })
        .sum()
}

/// The system calls the interpreter may not make: each fails with EPERM. Everything
/// here either reaches past the process (new processes and threads, tracing, another
/// process's memory, the network, mounts and namespaces, the kernel's keyrings, BPF,
/// io_uring, performance counters) or is of no use to a student's computation.
const DENIED: &[libc::c_long] = &[
    libc::SYS_fork,
    libc::SYS_vfork,
    libc::SYS_execveat,
    libc::SYS_ptrace,
    libc::SYS_process_vm_readv,
    libc::SYS_process_vm_writev,
    libc::SYS_socket,
    libc::SYS_mount,
    libc::SYS_umount2,
    libc::SYS_pivot_root,
    libc::SYS_chroot,
    libc::SYS_unshare,
    libc::SYS_setns,
    libc::SYS_keyctl,
    libc::SYS_add_key,
    libc::SYS_request_key,
    libc::SYS_bpf,
    libc::SYS_perf_event_open,
    libc::SYS_userfaultfd,
    libc::SYS_personality,
    libc::SYS_io_uring_setup,
    libc::SYS_io_uring_enter,
    libc::SYS_io_uring_register,
    libc::SYS_open_by_handle_at,
    libc::SYS_name_to_handle_at,
    libc::SYS_kexec_load,
    libc::SYS_init_module,
    libc::SYS_finit_module,
    libc::SYS_delete_module,
    libc::SYS_syslog,
    libc::SYS_acct,
    libc::SYS_swapon,
    libc::SYS_swapoff,
    libc::SYS_reboot,
    // Locks and notifications on files every jail shares (those of /usr) are one kernel
    // object for all: a channel between the phases of a grading, and between gradings.
    libc::SYS_flock,
    libc::SYS_inotify_init,
    libc::SYS_inotify_init1,
    libc::SYS_inotify_add_watch,
    libc::SYS_fanotify_init,
    // So is the page cache of those files, which these look at or empty without reading
    // (the class challenge's held-out readings went out so, a bit a page).
    libc::SYS_mincore,
    libc::SYS_fadvise64,
    libc::SYS_readahead,
    libc::SYS_preadv2,
    libc::SYS_pwritev2,
    SYS_CACHESTAT,
    // Shared memory outside the address space's limit (System V's segments stay when
    // detached), and message queues.
    libc::SYS_shmget,
    libc::SYS_shmat,
    libc::SYS_shmctl,
    libc::SYS_msgget,
    libc::SYS_semget,
    libc::SYS_mq_open,
    libc::SYS_memfd_create,
];

/// `cachestat` (Linux 6.5), which the libc crate names on some architectures only: a
/// file's page cache.
const SYS_CACHESTAT: libc::c_long = 451;

/// The advice of `madvise` that pushes pages of a file out of memory (the page cache
/// every jail shares).
const PAGE_OUT: &[libc::c_int] = &[libc::MADV_COLD, libc::MADV_PAGEOUT];

/// The commands of `fcntl` that lock a file (and ask about another's lock), or ask to
/// hear of others' use of it (leases, dnotify): refused, as `flock` and `inotify` are.
const LOCKS: &[libc::c_int] = &[
    libc::F_GETLK,
    libc::F_SETLK,
    libc::F_SETLKW,
    libc::F_OFD_GETLK,
    libc::F_OFD_SETLK,
    libc::F_OFD_SETLKW,
    libc::F_SETLEASE,
    libc::F_GETLEASE,
    libc::F_NOTIFY,
];

/// The filter as bubblewrap reads it: the program's instructions, as in memory.
fn filter_program() -> std::io::Result<Vec<u8>> {
    let when = |arg: u8, value: u64| {
        SeccompCondition::new(arg, SeccompCmpArgLen::Dword, SeccompCmpOp::Eq, value)
            .and_then(|condition| SeccompRule::new(vec![condition]))
            .map_err(std::io::Error::other)
    };
    let mut rules: BTreeMap<i64, Vec<SeccompRule>> =
        DENIED.iter().map(|&call| (call, Vec::new())).collect();
    rules.insert(
        libc::SYS_fcntl,
        LOCKS
            .iter()
            .map(|&command| when(1, command as u64))
            .collect::<Result<_, _>>()?,
    );
    // A new process; a thread of its own is allowed (Octave's signal thread), and its CPU
    // time counts in the process's. (`clone3`, whose flags no filter can read, fails
    // with ENOSYS before the filter, and the C library falls back on `clone`.)
    rules.insert(
        libc::SYS_clone,
        vec![
            SeccompCondition::new(
                0,
                SeccompCmpArgLen::Qword,
                SeccompCmpOp::MaskedEq(libc::CLONE_THREAD as u64),
                0,
            )
            .and_then(|condition| SeccompRule::new(vec![condition]))
            .map_err(std::io::Error::other)?,
        ],
    );
    // The parent-death signal bubblewrap sets: the interpreter would outlive its jail.
    rules.insert(
        libc::SYS_prctl,
        vec![when(0, libc::PR_SET_PDEATHSIG as u64)?],
    );
    rules.insert(
        libc::SYS_madvise,
        PAGE_OUT
            .iter()
            .map(|&advice| when(2, advice as u64))
            .collect::<Result<_, _>>()?,
    );
    let arch = std::env::consts::ARCH
        .try_into()
        .map_err(std::io::Error::other)?;
    let filter = SeccompFilter::new(
        rules,
        SeccompAction::Allow,
        SeccompAction::Errno(libc::EPERM as u32),
        arch,
    )
    .map_err(std::io::Error::other)?;
    let program: BpfProgram = filter.try_into().map_err(std::io::Error::other)?;
    Ok(BEFORE_THE_FILTER
        .iter()
        .chain(program.iter())
        .flat_map(|instruction| {
            let mut bytes = Vec::with_capacity(8);
            bytes.extend(instruction.code.to_ne_bytes());
            bytes.push(instruction.jt);
            bytes.push(instruction.jf);
            bytes.extend(instruction.k.to_ne_bytes());
            bytes
        })
        .collect())
}

/// Before the filter: a system call of the x32 ABI (its number with bit 30 set, under the
/// same architecture as x86-64's) fails with EPERM, since the filter's rules name
/// x86-64's numbers only (i386's calls, another architecture, the filter kills); and
/// `clone3` fails with ENOSYS, as on a kernel without it, so that threads are made with
/// `clone`, whose flags the filter reads.
const BEFORE_THE_FILTER: [sock_filter; 5] = [
    // Load the call's number (`seccomp_data.nr`, at offset 0).
    sock_filter {
        code: 0x20, // BPF_LD | BPF_W | BPF_ABS
        jt: 0,
        jf: 0,
        k: 0,
    },
    // Bit 30 set: go on to the refusal; else skip it.
    sock_filter {
        code: 0x45, // BPF_JMP | BPF_JSET | BPF_K
        jt: 0,
        jf: 1,
        k: 0x4000_0000,
    },
    sock_filter {
        code: 0x06, // BPF_RET | BPF_K
        jt: 0,
        jf: 0,
        k: 0x0005_0000 | libc::EPERM as u32, // SECCOMP_RET_ERRNO
    },
    // `clone3`: go on to its refusal; else skip it.
    sock_filter {
        code: 0x15, // BPF_JMP | BPF_JEQ | BPF_K
        jt: 0,
        jf: 1,
        k: libc::SYS_clone3 as u32,
    },
    sock_filter {
        code: 0x06, // BPF_RET | BPF_K
        jt: 0,
        jf: 0,
        k: 0x0005_0000 | libc::ENOSYS as u32, // SECCOMP_RET_ERRNO
    },
];
