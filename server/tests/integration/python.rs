//! Students' files in Python, graded as the server grades them: the interpreter in its
//! operating-system sandbox, called by the harness in QuickJS (see
//! `server/src/sandbox/native`). A correct file of each exercise scores 1 with hidden
//! cases; a sample of classic mistakes each fails its function with its hint; and what a
//! student might try from inside is contained, with a precise message, while the other
//! tests of the file pass and the grading stays gradable. Needs `bwrap` and Python 3 with
//! NumPy (Debian's bubblewrap and python3-numpy, which `scripts/test` installs).

use crate::student;

use estlab::sandbox::{Code, Sandbox};
use labs::grading::{GradeResult, Hidden, Subject};
use labs::{Exercise, Language};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use student::catalogue::{Seeds, failing_alone};
use student::python::{EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE};

const SEEDS: [Seeds; 2] = [(1, 0x5eed_0001), (2320, 9_876_543_210)];

#[test]
fn the_correct_files_score_1_with_hidden_cases() {
    for files in [EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_the_correct_file(&SEEDS);
    }
}

#[test]
fn the_starters_score_0_and_say_what_is_not_implemented() {
    for files in [ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_the_starter(SEEDS[0]);
    }
    // The EKF's loop asks init for its settings before any function.
    let starter = Exercise::EkfLocalization
        .declaration()
        .starter(Language::Python);
    let result = grade(Exercise::EkfLocalization, starter);
    assert_eq!(result.score, 0.0);
    for test in &result.tests {
        let thrown = match &test.subject {
            Subject::Function(name) => {
                format!("threw NotImplementedError: {name}: not implemented")
            }
            Subject::Run(_) => "threw NotImplementedError: init: not implemented".to_owned(),
        };
        assert!(test.message.contains(&thrown), "{}", test.message);
    }
}

#[test]
fn a_sample_of_mistakes_each_fails_its_function_with_its_hint() {
    for files in [EKF_LOCALIZATION, ODOMETRY, SENSOR_FUSION, UKF_PARTICLE] {
        files.check_a_sample_of_mistakes(&SEEDS[..1]);
    }
}

fn sandbox() -> Sandbox {
    Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 2)
}

/// The correct odometry file with `wheel_noise` replaced by `replacement` (a later
/// definition wins), graded with hidden cases.
fn with_wheel_noise(replacement: &str) -> GradeResult {
    let source = format!("{}\n\n{replacement}\n", ODOMETRY.correct);
    grade(Exercise::Odometry, &source)
}

fn grade(exercise: Exercise, source: &str) -> GradeResult {
    let code = Code {
        language: Language::Python,
        text: source,
    };
    let hidden = Hidden {
        cases: 77,
        class: 78,
    };
    sandbox().grade(exercise, code, 5, Some(hidden))
}

/// What `wheel_noise`'s test says, failing alone.
fn wheel_noise_message(result: &GradeResult) -> String {
    failing_alone(result, "wheel_noise")
}

fn contained(replacement: &str, expected: &str) {
    let message = wheel_noise_message(&with_wheel_noise(replacement));
    assert!(
        message.contains(expected),
        "expected {expected:?} in: {message}"
    );
}

#[test]
fn the_file_system_holds_the_interpreter_and_nothing_of_the_server() {
    // The server's data folder, with its secret, is not there at all.
    let data = tempfile::tempdir().unwrap();
    let secret = data.path().join("secret");
    std::fs::write(&secret, "the server's secret").unwrap();
    contained(
        &format!(
            "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    open({:?}).read()",
            secret.display().to_string()
        ),
        "threw FileNotFoundError",
    );
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         raise RuntimeError('root ' + repr(sorted(os.listdir('/'))))",
        "root ['bin', 'dev', 'etc', 'lib', 'lib64', 'proc', 'tmp', 'usr']",
    );
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         raise RuntimeError('etc ' + repr(sorted(os.listdir('/etc'))))",
        "etc ['alternatives', 'ld.so.cache']",
    );
    // Its own processes only: itself, as process 1, and nobody.
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         pids = [p for p in os.listdir('/proc') if p.isdigit()]\n    \
         raise RuntimeError(f'pids {pids} uid {os.getuid()}')",
        "pids ['1'] uid 65534",
    );
    // The kernel's settings are not the student's, even on a server run as root (whose
    // root, mapped into the sandbox's user namespace, would own them): core_pattern once
    // ran a program of the student's as root on the host.
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         try:\n        \
         with open('/proc/sys/kernel/core_pattern', 'w') as f: f.write('core')\n    \
         except OSError as e:\n        raise RuntimeError('refused')\n    \
         raise RuntimeError('written')",
        "threw RuntimeError: refused",
    );
    // /usr is read-only.
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    open('/usr/evil', 'w')",
        "threw OSError: [Errno 30] Read-only file system",
    );
}

#[test]
fn no_network_processes_or_tracing() {
    contained(
        "import socket\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         socket.create_connection(('127.0.0.1', 80))",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    os.fork()",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    // A thread of its own it may make (Octave needs one), and its work counts in the
    // phase's time; clone3, whose flags the filter cannot read, is not there.
    contained(
        "import threading\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         threading.Thread(target=lambda: [0 for _ in iter(int, 1)], daemon=True).start()\n    \
         while True: pass",
        "Stopped after 2 s, the time limit, while running wheel_noise/",
    );
    contained(
        "import ctypes\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         libc = ctypes.CDLL(None, use_errno=True)\n    \
         status = libc.syscall(435, 0, 0)\n    \
         raise RuntimeError(f'clone3 {status} errno {ctypes.get_errno()}')",
        "clone3 -1 errno 38",
    );
    // Threads, but a few: a loop of them would take the machine's every process id.
    contained(
        "import threading, time\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         for n in range(100000):\n        \
         try: threading.Thread(target=time.sleep, args=(5,), daemon=True).start()\n        \
         except RuntimeError: raise RuntimeError(f'threads {n < 32}')",
        "threw RuntimeError: threads True",
    );
    contained(
        "import ctypes\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         libc = ctypes.CDLL(None, use_errno=True)\n    \
         status = libc.ptrace(16, 1, 0, 0)\n    \
         raise RuntimeError(f'ptrace {status} errno {ctypes.get_errno()}')",
        "ptrace -1 errno 1",
    );
}

#[test]
fn no_channel_between_jails_and_nothing_inherited() {
    // Locks on the files every jail shares (/usr) would carry data between phases.
    contained(
        "import fcntl\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         with open('/usr/lib/python3.11/os.py') as f:\n        \
         fcntl.lockf(f, fcntl.LOCK_SH | fcntl.LOCK_NB, 1, 7)",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    contained(
        "import fcntl\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         with open('/usr/lib/python3.11/os.py') as f:\n        fcntl.flock(f, fcntl.LOCK_SH)",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    // Nor may the page cache of those files carry data: no look at it, no emptying it.
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         fd = os.open('/usr/lib/python3.11/os.py', os.O_RDONLY)\n    \
         os.posix_fadvise(fd, 0, 4096, os.POSIX_FADV_DONTNEED)",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         fd = os.open('/usr/lib/python3.11/os.py', os.O_RDONLY)\n    \
         os.preadv(fd, [bytearray(4096)], 0, os.RWF_NOWAIT)",
        "threw PermissionError: [Errno 1] Operation not permitted",
    );
    contained(
        "import ctypes, fcntl, os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         libc = ctypes.CDLL(None, use_errno=True)\n    \
         notify = os.open('/usr/lib/python3.11', os.O_RDONLY)\n    \
         notified = libc.fcntl(notify, fcntl.F_NOTIFY, 0x80000001), ctypes.get_errno()\n    \
         shm = libc.shmget(0, 1 << 20, 0o1600), ctypes.get_errno()\n    \
         page = ctypes.create_string_buffer(1)\n    \
         seen = libc.mincore(ctypes.c_void_p(0x400000), 4096, page), ctypes.get_errno()\n    \
         raise RuntimeError(f'notify {notified} shm {shm} mincore {seen}')",
        "notify (-1, 1) shm (-1, 1) mincore (-1, 1)",
    );
    // Nothing writable but a small /tmp: not the root, not /dev.
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    open('/dev/shm/x', 'w')",
        "threw OSError: [Errno 30] Read-only file system",
    );
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    open('/x', 'w')",
        "threw OSError: [Errno 30] Read-only file system",
    );
    // The signal that ends the interpreter with its jail stays set; an x32 system call
    // (the filter's rules name x86-64's numbers) is refused too.
    contained(
        "import ctypes\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         libc = ctypes.CDLL(None, use_errno=True)\n    \
         cleared = libc.prctl(1, 0, 0, 0, 0), ctypes.get_errno()\n    \
         x32 = libc.syscall(0x40000000 | 39), ctypes.get_errno()\n    \
         raise RuntimeError(f'prctl {cleared} x32 {x32}')",
        "prctl (-1, 1) x32 (-1, 1)",
    );
    // A descriptor the server holds (without close-on-exec) is not the student's.
    let file = std::fs::File::open(env!("CARGO_MANIFEST_DIR")).unwrap();
    // SAFETY: dup2 onto a number this test does not otherwise use; the copy is not
    // close-on-exec, as a descriptor a server inherits might not be.
    let inherited = unsafe { libc::dup2(std::os::fd::AsRawFd::as_raw_fd(&file), 200) };
    assert_eq!(inherited, 200);
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    os.fstat(200)",
        "threw OSError: [Errno 9] Bad file descriptor",
    );
    // SAFETY: the copy made above, closed once.
    unsafe { libc::close(200) };
}

#[test]
fn endless_work_sleep_memory_disk_and_huge_answers_are_stopped_with_a_message() {
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    while True: pass",
        "Stopped after 2 s, the time limit, while running wheel_noise/",
    );
    // Native code the interpreter cannot interrupt: the CPU clock is read from outside.
    contained(
        "import numpy as np\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         a = np.ones((4000, 4000))\n    return a @ a",
        "Stopped after 2 s, the time limit, while running wheel_noise/",
    );
    contained(
        "import time\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    time.sleep(600)",
        "your code waited for 2 s without computing",
    );
    // The time asleep adds up over the calls of a phase: a little less in each of many
    // calls would otherwise outlast the worker, and the grading would be no grading.
    contained(
        "import time\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    time.sleep(0.3)\n    \
         return [[k_r * abs(ds_r), 0], [0, k_l * abs(ds_l)]]",
        "your code waited for 2 s without computing",
    );
    // A main thread that ends while another sleeps is asleep too.
    contained(
        "import ctypes, threading, time\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         threading.Thread(target=lambda: time.sleep(10**6), daemon=True).start()\n    \
         ctypes.CDLL(None).syscall(60, 0)",
        "your code waited for 2 s without computing",
    );
    contained(
        "import numpy as np\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         return np.ones(10**10)",
        "threw MemoryError",
    );
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         with open('/tmp/fill', 'wb') as f:\n        f.write(b'x' * (2 << 20))",
        "threw OSError: [Errno 27] File too large",
    );
    contained(
        "import numpy as np\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         return np.zeros(10**6)",
        "returned an array of 1000000 values, more than the 2000 a call may return",
    );
    contained(
        "def wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         while True: print('x' * 10000)",
        "Stopped after 2 s, the time limit",
    );
}

#[test]
fn ending_the_interpreter_or_writing_on_its_channel_harms_only_the_file() {
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    os._exit(0)",
        "your file's interpreter ended",
    );
    // The interpreter is process 1 of its namespace: a signal it sends itself is ignored.
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    os.kill(1, 9)",
        "got null (not the contract's shape)",
    );
    contained(
        "import sys\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    sys.exit(3)",
        "threw SystemExit: 3",
    );
    // A reply forged on every descriptor answers only the forger's own call, and the next
    // request stops the phase: a flood of them cannot fill the pipes and hang the grading.
    contained(
        "import os, time\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         for fd in range(3, 64):\n        \
         try: os.write(fd, b'{\"output\": [[1, 0], [0, 1]]}\\n' * 3000)\n        \
         except OSError: pass\n    time.sleep(600)",
        "your code wrote on the harness's own descriptor, out of turn",
    );
    contained(
        "import os\ndef wheel_noise(ds_r, ds_l, k_r, k_l):\n    \
         for fd in range(64):\n        \
         try: os.write(fd, b'{\"output\": [[1, 0], [0, 1]]}\\n')\n        \
         except OSError: pass\n    return 'mine'",
        "wheel_noise",
    );
}

#[test]
fn a_tuple_of_the_wrong_length_says_what_the_function_returns() {
    let source = format!(
        "{}\n\ndef predict(mu, sigma, odom_prev, odom, k_xy, k_theta):\n    return mu, sigma, 0\n",
        SENSOR_FUSION.correct
    );
    let result = grade(Exercise::SensorFusion, &source);
    let test = result
        .tests
        .iter()
        .find(|t| t.subject == Subject::Function("predict".to_owned()))
        .expect("a test of predict");
    assert!(
        test.message
            .contains("returned a tuple of 3 values, where predict returns 2: mu_bar, sigma_bar"),
        "{}",
        test.message
    );
}

#[test]
fn a_missing_function_is_named_with_its_python_declaration() {
    let source = ODOMETRY
        .correct
        .replace("def wheel_noise(", "def wheel_noises(");
    let message = wheel_noise_message(&grade(Exercise::Odometry, &source));
    assert!(
        message.contains(
            "wheel_noise is not defined: declare it at top level, as def wheel_noise(...):"
        ),
        "{message}"
    );
}

#[test]
fn a_file_scores_the_same_beside_busy_processes() {
    let alone = grade(Exercise::EkfLocalization, EKF_LOCALIZATION.correct);
    let slow = format!(
        "{}\n\ndef observation_model(x, M, j):\n    while True: pass\n",
        EKF_LOCALIZATION.correct
    );
    let slow_alone = grade(Exercise::EkfLocalization, &slow);
    let busy = AtomicBool::new(true);
    let (beside, slow_beside) = std::thread::scope(|scope| {
        for _ in 0..4 {
            scope.spawn(|| {
                let mut x = 0u64;
                while busy.load(Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_mul(31).wrapping_add(7));
                }
            });
        }
        let results = (
            grade(Exercise::EkfLocalization, EKF_LOCALIZATION.correct),
            grade(Exercise::EkfLocalization, &slow),
        );
        busy.store(false, Ordering::Relaxed);
        results
    });
    assert_eq!(alone.score, 1.0);
    assert_eq!(beside.tests, alone.tests);
    assert!(slow_alone.score < 1.0);
    assert_eq!(slow_beside.tests, slow_alone.tests);
}
