//! A student's file in an interpreter in its jail, answering the calls of the harness in
//! JavaScript one line of JSON at a time (see `harness.py`). Waiting for an answer, the
//! engine's thread looks every few milliseconds at the phase's budget (which counts the
//! interpreter's CPU time) and at what the interpreter does: one that is not running (a
//! `sleep`, a read of its input, a lock it waits for, a main thread that has ended while
//! another waits) rather than computing is stopped once it has been so for
//! [`SLEEP_LIMIT`] in all, over every call of its phase, since its CPU time would never
//! run out.

use super::super::cpu::CpuClock;
use super::jail::{Invocation, Jailed, Progress, Refused, Tools};
use labs::exercises::interface::Function;
use labs::grading::PhaseKind;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, OwnedFd};
use std::process::{Child, ChildStdin, ChildStdout};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The longest answer read from the interpreter: the JavaScript harness then holds it to
/// the contract's own bounds (2,000 values, 4,000 characters of text).
const MAX_REPLY: usize = 1 << 20;
/// The longest report of a phase from the harness inside the jail (JavaScript on V8):
/// a whole data set's run records a few megabytes.
const MAX_REPORT: usize = 32 << 20;
/// How long the interpreter may be asleep, waiting rather than computing, while the engine
/// waits for it, over all the calls of its phase (a wait per call would let a file that
/// sleeps a little less in each of a run's hundreds of calls outlast its worker).
pub const SLEEP_LIMIT: Duration = Duration::from_secs(2);
/// How long bubblewrap is given to end once the interpreter is killed, before it is
/// killed too (it ends at once, unless the machine is very busy: then only the count of
/// the interpreter's CPU time is lost).
const REAP_WAIT: Duration = Duration::from_secs(1);
/// How often the engine's thread looks while it waits.
const LOOK: Duration = Duration::from_millis(5);
/// CPU time for the interpreter to start and load its libraries (NumPy: about 0.1 s).
const START_LIMIT: Duration = Duration::from_secs(10);
/// How long a start may take by the clock. While it starts, the interpreter reads its
/// libraries from disk (Octave's, cold, take seconds on a busy machine): a wait of the
/// machine's, not the student's, so the start is held to no limit of sleep, only this.
/// A start that outlasts it is the sandbox's failure, never a grade.
const START_WAIT: Duration = Duration::from_secs(60);
/// What of the interpreter's stderr is kept, for a start that failed.
const COMPLAINTS: u64 = 8 << 10;

/// What the interpreter is told first.
#[derive(Serialize)]
struct Setup<'a> {
    source: &'a str,
    file: &'a str,
    functions: &'a [Function],
}

/// A request of the harness in JavaScript, or (JavaScript on V8) of the server to the
/// harness inside the jail.
#[derive(Serialize)]
#[serde(untagged)]
enum Request<'a> {
    Load {
        load: bool,
    },
    Call {
        call: &'a str,
        args: Vec<Argument<'a>>,
    },
    Phase {
        kind: PhaseKind,
        phase: &'a str,
    },
}

/// What the harness inside the jail says when it has carried out a phase.
#[derive(Deserialize)]
struct Reported {
    report: String,
}

/// One argument of a call, in an object of its own: a reader that makes one matrix of a
/// list of equal lists (Octave's `jsondecode`) keeps the arguments apart.
#[derive(Serialize)]
struct Argument<'a> {
    value: &'a Value,
}

/// Why an interpreter gives no answer.
#[derive(Debug, thiserror::Error)]
pub enum Silent {
    /// The phase's time ran out (the engine's interrupt handler ends the phase).
    #[error("the time limit ran out")]
    OverTime,
    #[error(
        "your code waited for {} s without computing (a sleep, a read of input, a lock?)",
        SLEEP_LIMIT.as_secs()
    )]
    Asleep,
    #[error("your code's answer came to more than {} KB", .0 >> 10)]
    TooLong(usize),
    #[error("your code wrote on the harness's own descriptor, out of turn")]
    OutOfTurn,
    #[error("your file's interpreter ended ({0}){1}")]
    Ended(String, String),
    /// V8's heap was full (JavaScript on V8).
    #[error(
        "out of memory (the limit is {} MB): far too much data allocated",
        super::V8_HEAP_MB
    )]
    OutOfMemory,
}

/// A student's file in its interpreter, in its jail.
pub struct Interpreter {
    child: Child,
    /// The interpreter's process, as a descriptor.
    pidfd: OwnedFd,
    stdin: ChildStdin,
    stdout: ChildStdout,
    pid: libc::pid_t,
    clock: CpuClock,
    /// What has been read of the next answer.
    pending: Vec<u8>,
    complaints: Option<JoinHandle<String>>,
    /// Why it answers no more, once it does not.
    silent: Option<Silent>,
    /// How long it has been found asleep while the engine waited for it, once started
    /// (None while it starts).
    asleep: Option<Duration>,
    /// When it was last looked at, and its CPU time then.
    looked: Option<(Instant, Duration)>,
    /// Where it says what it is doing, if it does (JavaScript on V8).
    progress: Option<Progress>,
}

impl Interpreter {
    /// The interpreter in its jail with the harness, told the student's file: ready for
    /// requests once it has loaded its libraries (within [`START_LIMIT`] of CPU time).
    pub fn start(
        tools: &Tools,
        invocation: &Invocation,
        (source, file): (&str, &str),
        functions: &[Function],
    ) -> Result<Interpreter, Refused> {
        let Jailed {
            child,
            pidfd,
            stdin,
            stdout,
            stderr,
            pid,
            clock,
            progress,
        } = tools.jail(invocation)?;
        let complaints = std::thread::Builder::new()
            .spawn(move || drain(stderr))
            .map_err(Refused::Setup)?;
        let mut interpreter = Interpreter {
            child,
            pidfd,
            stdin,
            stdout,
            pid,
            clock,
            pending: Vec::new(),
            complaints: Some(complaints),
            silent: None,
            asleep: None,
            looked: None,
            progress,
        };
        let setup = serde_json::to_string(&Setup {
            source,
            file,
            functions,
        })
        .expect("a setup serialises");
        let began = Instant::now();
        let over =
            || clock.read().is_none_or(|cpu| cpu > START_LIMIT) || began.elapsed() > START_WAIT;
        match interpreter.exchange(&setup, &over) {
            Ok(_) => {
                interpreter.asleep = Some(Duration::ZERO);
                Ok(interpreter)
            }
            Err(silent) => Err(Refused::NotStarted(format!(
                "{silent}{}",
                interpreter.complaints()
            ))),
        }
    }

    /// Why the interpreter was stopped, if the student's code made it stop answering
    /// (rather than the phase's time running out, which the engine tells by itself):
    /// the phase ends there.
    pub fn stopped(&self) -> Option<String> {
        match &self.silent {
            None | Some(Silent::OverTime) => None,
            Some(silent) => Some(silent.to_string()),
        }
    }

    /// The interpreter's CPU clock (which reads nothing once it has ended).
    pub fn clock(&self) -> CpuClock {
        self.clock
    }

    /// Evaluates the student's file afresh: the answer's JSON text.
    pub fn load(&mut self, over: &dyn Fn() -> bool) -> String {
        self.request(&Request::Load { load: true }, over)
    }

    /// Calls the student's function `name` with `args`: the answer's JSON text.
    pub fn call(&mut self, name: &str, args: &[Value], over: &dyn Fn() -> bool) -> String {
        let args = args.iter().map(|value| Argument { value }).collect();
        self.request(&Request::Call { call: name, args }, over)
    }

    /// The answer, or `{"error": why there is none}` (the harness in JavaScript throws it
    /// as the call's error; a phase over its time is ended by the engine).
    fn request(&mut self, request: &Request, over: &dyn Fn() -> bool) -> String {
        let text = serde_json::to_string(request).expect("requests serialise");
        match self.exchange(&text, over) {
            Ok(reply) => reply,
            Err(silent) => serde_json::json!({ "error": silent.to_string() }).to_string(),
        }
    }

    /// Carries out a whole phase (`phase`, its job as JSON) with the harness inside the
    /// jail (JavaScript on V8): the harness's report, or why none came (then
    /// [`Interpreter::doing`] says where the harness was). The time found asleep is this
    /// phase's alone (a process may carry out several, one after another).
    pub fn phase(
        &mut self,
        kind: PhaseKind,
        phase: &str,
        over: &dyn Fn() -> bool,
    ) -> Result<String, Silent> {
        self.asleep = Some(Duration::ZERO);
        if let Some(progress) = &self.progress {
            progress.clear();
        }
        let request =
            serde_json::to_string(&Request::Phase { kind, phase }).expect("requests serialise");
        let line = self.converse(&request, over, MAX_REPORT)?;
        serde_json::from_str::<Reported>(&line)
            .map(|reported| reported.report)
            // Only the student's code, writing on the harness's descriptor.
            .map_err(|_| Silent::OutOfTurn)
    }

    /// Whether the interpreter has written nothing beyond its last answer (the harness
    /// writes one line a request: more is the student's code, out of turn).
    pub fn quiet(&self) -> bool {
        self.pending.is_empty() && !ready(self.stdout.as_raw_fd(), libc::POLLIN, Duration::ZERO)
    }

    /// What the harness in the jail last said it was doing (empty if nothing).
    pub fn doing(&self) -> String {
        self.progress
            .as_ref()
            .map(Progress::read)
            .unwrap_or_default()
    }

    fn exchange(&mut self, line: &str, over: &dyn Fn() -> bool) -> Result<String, Silent> {
        self.converse(line, over, MAX_REPLY)
    }

    /// Sends `line`, then reads the answer's line, of at most `longest` bytes.
    fn converse(
        &mut self,
        line: &str,
        over: &dyn Fn() -> bool,
        longest: usize,
    ) -> Result<String, Silent> {
        if let Some(silent) = &self.silent {
            return Err(Silent::Ended("earlier".to_owned(), format!(": {silent}")));
        }
        let outcome = if self.pending.is_empty() {
            // An empty line after each: a reader that looks a character past the end of a
            // line (Octave's `fgetl`) has one to look at without waiting for the next.
            let mut line = line.as_bytes().to_vec();
            line.extend(b"\n\n");
            self.send(&line, over)
                .and_then(|()| self.reply(over, longest))
        } else {
            // The harness answers each request with one line: more is the student's code
            // writing on the harness's descriptor.
            Err(Silent::OutOfTurn)
        };
        match outcome {
            Ok(answer) => Ok(answer),
            Err(silent) => {
                self.stop();
                let message = silent.to_string();
                self.silent = Some(silent);
                Err(Silent::Ended("stopped".to_owned(), format!(": {message}")))
            }
        }
    }

    /// Writes `bytes` to the interpreter's input as it reads them, waiting as long as the
    /// budget lasts (an interpreter that reads nothing fills the pipe).
    fn send(&mut self, mut bytes: &[u8], over: &dyn Fn() -> bool) -> Result<(), Silent> {
        while !bytes.is_empty() {
            match self.stdin.write(bytes) {
                Ok(0) => return Err(self.ended()),
                Ok(n) => bytes = &bytes[n..],
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    if !ready(self.stdin.as_raw_fd(), libc::POLLOUT, LOOK) {
                        self.waited(over)?;
                    }
                }
                Err(_) => return Err(self.ended()),
            }
        }
        Ok(())
    }

    /// The next line the interpreter writes, waiting as long as the budget lasts.
    fn reply(&mut self, over: &dyn Fn() -> bool, longest: usize) -> Result<String, Silent> {
        loop {
            if let Some(end) = self.pending.iter().position(|&b| b == b'\n') {
                let line: Vec<u8> = self.pending.drain(..=end).collect();
                return Ok(String::from_utf8_lossy(&line[..end]).into_owned());
            }
            if self.pending.len() > longest {
                return Err(Silent::TooLong(longest));
            }
            if ready(self.stdout.as_raw_fd(), libc::POLLIN, LOOK) {
                let mut chunk = [0u8; 16 << 10];
                match self.stdout.read(&mut chunk) {
                    Ok(0) | Err(_) => return Err(self.ended()),
                    Ok(n) => self.pending.extend_from_slice(&chunk[..n]),
                }
                continue;
            }
            self.waited(over)?;
        }
    }

    /// After a look that found nothing to do: whether to go on waiting. Not when the
    /// phase's time has run out, nor when the interpreter has been asleep for too long.
    fn waited(&mut self, over: &dyn Fn() -> bool) -> Result<(), Silent> {
        if over() {
            return Err(Silent::OverTime);
        }
        let look = (Instant::now(), self.clock.read().unwrap_or_default());
        let since = self.looked.replace(look);
        if let Some(asleep) = &mut self.asleep
            && since.is_some_and(|(at, cpu)| {
                waits_of_its_own(state(self.pid), look.1.saturating_sub(cpu), look.0 - at)
            })
        {
            *asleep += LOOK;
            if *asleep >= SLEEP_LIMIT {
                return Err(Silent::Asleep);
            }
        }
        Ok(())
    }

    /// Why the interpreter answers no more, once its process has ended.
    fn ended(&mut self) -> Silent {
        let status = self
            .child
            .wait()
            .map_or_else(|e| e.to_string(), |status| status.to_string());
        let complaints = self.stderr();
        if complaints.contains(super::V8_OUT_OF_MEMORY) {
            return Silent::OutOfMemory;
        }
        Silent::Ended(status, last_line(&complaints))
    }

    /// What the interpreter wrote on stderr, once it has ended, as the end of a message.
    fn complaints(&mut self) -> String {
        let text = self.stderr();
        last_line(&text)
    }

    /// What the interpreter wrote on stderr (its start), once it has ended.
    fn stderr(&mut self) -> String {
        self.stop();
        match self.complaints.take().map(JoinHandle::join) {
            Some(Ok(text)) => text,
            _ => String::new(),
        }
    }

    /// Ends the interpreter (through its pidfd, which names it and no later process of
    /// its number: it may have cleared the signal that ends it with bubblewrap), then
    /// bubblewrap. Bubblewrap is left [`REAP_WAIT`] to wait for the interpreter and end
    /// on its own: the interpreter's CPU time then counts in bubblewrap's, and so in the
    /// worker's, which the server charges its student (`cpu::workers_spent`).
    fn stop(&mut self) {
        // SAFETY: pidfd_send_signal reads a descriptor of ours and no pointer (none given).
        unsafe {
            libc::syscall(
                libc::SYS_pidfd_send_signal,
                self.pidfd.as_raw_fd(),
                libc::SIGKILL,
                std::ptr::null::<libc::siginfo_t>(),
                0,
            );
        }
        let give_up = Instant::now() + REAP_WAIT;
        while matches!(self.child.try_wait(), Ok(None)) && Instant::now() < give_up {
            std::thread::sleep(LOOK);
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Interpreter {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Whether `fd` is ready for `events` (or has ended) within `wait`.
fn ready(fd: std::os::fd::RawFd, events: libc::c_short, wait: Duration) -> bool {
    let mut poll = libc::pollfd {
        fd,
        events,
        revents: 0,
    };
    // SAFETY: poll reads and writes one valid pollfd.
    let ready = unsafe { libc::poll(&mut poll, 1, wait.as_millis() as libc::c_int) };
    ready > 0
}

/// Whether an interpreter found in `state` (in `/proc/PID/stat`), having computed `cpu`
/// of the `wall` time since the last look, waits of its own making: it computed for less
/// than half that time, and it is neither running nor waiting for a processor (`R`: a
/// busy machine) nor for the kernel (`D`: pages it touches being made or swapped in, as
/// a file allocating much makes it wait). Its own waits are the rest: asleep (`S`),
/// stopped (`T`, `t`), or a main thread that has ended (`Z`) while another waits.
fn waits_of_its_own(state: Option<char>, cpu: Duration, wall: Duration) -> bool {
    !matches!(state, Some('R' | 'D')) && cpu * 2 < wall
}

/// The state of a process, the letter after its command in `/proc/PID/stat`; none once
/// it is gone.
fn state(pid: libc::pid_t) -> Option<char> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let (_, rest) = stat.rsplit_once(')')?;
    rest.trim_start().chars().next()
}

/// The last line of what an interpreter wrote on stderr, as the end of a message.
fn last_line(text: &str) -> String {
    match text.trim().lines().last() {
        Some(last) => format!(": {last}"),
        None => String::new(),
    }
}

/// Reads stderr to its end, keeping the start.
fn drain(stderr: std::process::ChildStderr) -> String {
    let mut kept = Vec::new();
    let mut stderr = stderr;
    let _ = (&mut stderr).take(COMPLAINTS).read_to_end(&mut kept);
    let _ = std::io::copy(&mut stderr, &mut std::io::sink());
    String::from_utf8_lossy(&kept).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    const LOOKED: Duration = Duration::from_millis(5);

    #[test]
    fn a_sleeping_interpreter_waits_of_its_own() {
        for state in ['S', 'T', 't', 'Z'] {
            assert!(
                waits_of_its_own(Some(state), Duration::ZERO, LOOKED),
                "{state}"
            );
        }
        assert!(waits_of_its_own(None, Duration::ZERO, LOOKED), "gone");
        // A little computing between sleeps is still sleeping.
        let sip = Duration::from_micros(200);
        assert!(waits_of_its_own(Some('S'), sip, LOOKED));
    }

    #[test]
    fn an_interpreter_that_computes_or_waits_for_the_machine_does_not() {
        assert!(
            !waits_of_its_own(Some('R'), Duration::ZERO, LOOKED),
            "a busy machine"
        );
        assert!(
            !waits_of_its_own(Some('D'), Duration::ZERO, LOOKED),
            "pages swapped in"
        );
        // Found asleep, but it computed most of the time since (pages made, a lock
        // passed between its threads).
        assert!(!waits_of_its_own(
            Some('S'),
            Duration::from_millis(4),
            LOOKED
        ));
    }
}
