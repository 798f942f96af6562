//! The server's side of the sandbox: each grading runs the student's code in a worker
//! process of its own (`estlab sandbox-worker`), so that a crash or a hang harms no other
//! submission and not the server. The worker gets the job on stdin and writes the outputs
//! on stdout. It dies with the process that started it, and the kernel ends it when it
//! uses more CPU time than every phase's limit together; a worker that dies, or outlives
//! a generous wall-clock allowance, makes the result "not gradable", which costs the
//! student nothing.

use super::cpu;
use super::engine::LOAD_LIMIT_MS;
use super::error::{Failure, TooLarge};
use super::native::{Native, Tools, Unavailable};
use super::watchdog::{OVERRUN_EXIT, OVERRUN_PREFIX};
use super::{DidNotStart, NotNow};
use labs::grading::{
    FunctionOutput, GradeResult, Hidden, Job, Outputs, PhaseOutput, Plan, Reach, RunOutput,
};
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::{Arc, OnceLock};
use std::thread;
use std::time::{Duration, Instant};

/// The subcommand of `estlab` that is the worker.
const WORKER_COMMAND: &str = "sandbox-worker";
/// The largest source file accepted, in bytes.
pub const MAX_SOURCE: usize = 256 << 10;
/// Whether a source file is small enough to be graded; if not, why not.
pub fn check_size(source: &str) -> Result<(), TooLarge> {
    check_length(source.len() as u64)
}

/// Whether a file of `bytes` is small enough to be graded (asked before reading it).
pub fn check_length(bytes: u64) -> Result<(), TooLarge> {
    if bytes > MAX_SOURCE as u64 {
        return Err(TooLarge {
            bytes,
            limit: MAX_SOURCE,
        });
    }
    Ok(())
}

/// The most a worker may write (its outputs are a few hundred kilobytes).
const MAX_OUTPUT: u64 = 64 << 20;
/// CPU time for the worker to start, plan nothing and write, beyond the phases' limits.
const SPARE: Duration = Duration::from_secs(10);
/// How much longer than its CPU limit a worker may take by the clock: the engines' own
/// CPU clocks decide every verdict, and this allowance only catches a worker that hangs
/// without using CPU, so it is generous enough for a machine that is very busy.
const WALL_CLOCK_FACTOR: u32 = 4;

/// How many times the runs' limits a whole run of a student's report is given where the
/// student's code is interpreted: the limits hold V8 to a grading's pace, and Python and
/// Octave take some ten times V8's time over the whole data sets (`BENCHMARKS.md`, "The
/// report's runs"); a file that never ends costs no more than this.
pub const WHOLE_RUN_FACTOR: u32 = 6;

/// What the worker reads on stdin.
#[derive(Serialize, Deserialize)]
pub struct WorkerInput {
    pub source: String,
    /// How a file in another language than JavaScript runs.
    pub native: Option<Native>,
    pub job: Job,
    /// How many engines the worker may run at once.
    pub threads: usize,
}

/// Why a student's code gave no outputs.
#[derive(Debug, thiserror::Error)]
pub enum Tried {
    #[error("{0}")]
    Unavailable(Unavailable),
    #[error(transparent)]
    DidNotStart(DidNotStart),
    #[error(transparent)]
    Failed(Failure),
    /// The shown job has no phase of that name.
    #[error("the exercise has no function or run {0:?} to run")]
    NoSuchPhase(String),
}

/// A student's file: its language and its text.
#[derive(Clone, Copy, Debug)]
pub struct Code<'a> {
    pub language: Language,
    pub text: &'a str,
}

impl<'a> Code<'a> {
    pub fn javascript(text: &'a str) -> Code<'a> {
        Code {
            language: Language::JavaScript,
            text,
        }
    }
}

/// The engine that runs students' JavaScript.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum JavaScript {
    /// V8 (Node) in the operating system's sandbox, where it starts: compiled, it gets
    /// through the whole data sets. QuickJS where it does not.
    #[default]
    V8,
    /// QuickJS in the worker process, always: the portable engine, which the platform
    /// packages run, on the first few hundred readings of each data set.
    #[value(name = "quickjs")]
    QuickJs,
}

/// Starts workers from the `estlab` executable.
#[derive(Clone, Debug)]
pub struct Sandbox {
    executable: PathBuf,
    threads: usize,
    /// The tools of each native engine (V8 for JavaScript, Python's, Octave's), found
    /// and tried the first time a file in its language is graded (or when the server
    /// starts: `Sandbox::language`).
    natives: Arc<BTreeMap<Language, OnceLock<Result<Tools, Unavailable>>>>,
    javascript: JavaScript,
    /// The most a worker may take by the clock, whatever its CPU limit (the tests shorten
    /// it); none: `WALL_CLOCK_FACTOR` times its CPU limit.
    clock_limit: Option<Duration>,
}

impl Sandbox {
    /// Workers of `executable`, each running at most `threads` engines at once, with
    /// JavaScript on V8 where its sandbox starts.
    pub fn new(executable: PathBuf, threads: usize) -> Sandbox {
        Sandbox {
            executable,
            threads: threads.max(1),
            natives: Arc::new(
                Language::ALL
                    .iter()
                    .map(|&language| (language, OnceLock::new()))
                    .collect(),
            ),
            javascript: JavaScript::default(),
            clock_limit: None,
        }
    }

    /// This very executable.
    pub fn current(threads: usize) -> std::io::Result<Sandbox> {
        Ok(Sandbox::new(std::env::current_exe()?, threads))
    }

    /// The same sandbox with students' JavaScript on `engine`.
    pub fn with_javascript(self, engine: JavaScript) -> Sandbox {
        Sandbox {
            javascript: engine,
            ..self
        }
    }

    /// The same sandbox with workers given at most `limit` by the clock.
    pub fn with_clock_limit(self, limit: Duration) -> Sandbox {
        Sandbox {
            clock_limit: Some(limit),
            ..self
        }
    }

    /// Whether files in `language` can be graded here, and if not, why not (its tools are
    /// looked for and tried once). JavaScript always can: see [`Sandbox::v8`].
    pub fn language(&self, language: Language) -> Result<(), Unavailable> {
        self.tools(language).map(|_| ())
    }

    /// Whether students' JavaScript runs on V8 here, and if not, why it runs on QuickJS.
    pub fn v8(&self) -> Result<(), Unavailable> {
        self.v8_tools().map(|_| ())
    }

    /// How much of each data set a grading of a file in `language` goes through: the
    /// whole on V8, the first readings where the student's code is interpreted.
    pub fn reach(&self, language: Language) -> Reach {
        match (language, self.v8()) {
            (Language::JavaScript, Ok(())) => Reach::Whole,
            _ => Reach::Prefix,
        }
    }

    fn v8_tools(&self) -> Result<&Tools, Unavailable> {
        match self.javascript {
            JavaScript::V8 => self.detected(Language::JavaScript),
            JavaScript::QuickJs => Err(Unavailable::Declined),
        }
    }

    /// The tools of a file's native engine (None for JavaScript on QuickJS).
    fn tools(&self, language: Language) -> Result<Option<&Tools>, Unavailable> {
        match language {
            Language::JavaScript => Ok(self.v8_tools().ok()),
            _ => self.detected(language).map(Some),
        }
    }

    fn detected(&self, language: Language) -> Result<&Tools, Unavailable> {
        self.natives[&language]
            .get_or_init(|| Native::detect(language))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// Grades a source file of an exercise for a seed (and, on the server, the seed of its
    /// hidden cases): the plan, the student's code in a worker, the comparison. Blocks for
    /// as long as the worker runs.
    pub fn grade(
        &self,
        exercise: Exercise,
        code: Code,
        seed: u64,
        hidden: Option<Hidden>,
    ) -> GradeResult {
        self.grade_plan(&self.plan(exercise, seed, hidden, code.language), code)
    }

    /// As `grade`, but a worker that did not start, or did not finish for want of the
    /// machine's time, is an error rather than a result "not gradable": the server's
    /// grader tries again later.
    pub fn try_grade(
        &self,
        exercise: Exercise,
        code: Code,
        seed: u64,
        hidden: Option<Hidden>,
    ) -> Result<GradeResult, NotNow> {
        self.try_grade_plan(&self.plan(exercise, seed, hidden, code.language), code)
    }

    /// Grades `code` on a plan of the caller's, however far into the data sets it goes
    /// (engines compared on the same plan).
    pub fn grade_plan(&self, plan: &Plan, code: Code) -> GradeResult {
        self.try_grade_plan(plan, code).unwrap_or_else(|e| {
            GradeResult::not_gradable(plan.exercise(), plan.seed(), e.to_string())
        })
    }

    /// The plan of a grading of a file in `language`, as far into the data sets as its
    /// engine gets here.
    fn plan(
        &self,
        exercise: Exercise,
        seed: u64,
        hidden: Option<Hidden>,
        language: Language,
    ) -> Plan {
        Plan::reaching(exercise, seed, hidden, self.reach(language))
    }

    fn try_grade_plan(&self, plan: &Plan, code: Code) -> Result<GradeResult, NotNow> {
        let (exercise, language) = (plan.exercise(), code.language);
        Ok(match self.outputs(exercise, code, plan.job()) {
            Ok(outputs) => plan.grade(&outputs).in_language(language),
            Err(Tried::DidNotStart(did_not_start)) => return Err(did_not_start.into()),
            Err(Tried::Failed(Failure::Hung { seconds })) => {
                return Err(NotNow::Starved { seconds });
            }
            Err(failed) => GradeResult::not_gradable(exercise, plan.seed(), failed.to_string()),
        })
    }

    /// One phase of the shown job of `seed` (a function's tests, by the function's name,
    /// or a run, by its name), carried out with the student's code as a grading carries
    /// it out: its output, for the browser to grade and show as it does its own (a
    /// language whose files run on the server only). Nothing is graded or stored here.
    pub fn phase(
        &self,
        exercise: Exercise,
        code: Code,
        seed: u64,
        phase: &str,
    ) -> Result<Outputs, Tried> {
        let mut job = Plan::new(exercise, seed, None).job();
        job.functions.retain(|function| function.function == phase);
        job.runs.retain(|run| run.name == phase);
        if job.functions.len() + job.runs.len() != 1 {
            return Err(Tried::NoSuchPhase(phase.to_owned()));
        }
        self.outputs(exercise, code, job)
    }

    /// The runs `runs` (by name) of the shown job of `seed`, each on the whole of its data
    /// set, carried out with the student's code: what a student's report draws. An
    /// interpreted engine (Python, Octave, QuickJS) is given [`WHOLE_RUN_FACTOR`] times the
    /// runs' limits, which hold V8 to a grading's pace: the report is made once a
    /// submission, not within a grading's second.
    pub fn whole_runs(
        &self,
        exercise: Exercise,
        code: Code,
        seed: u64,
        runs: &[&str],
    ) -> Result<Outputs, Tried> {
        let mut job = Plan::reaching(exercise, seed, None, Reach::Whole).job();
        job.functions.clear();
        job.runs.retain(|run| runs.contains(&run.name.as_str()));
        if let Some(missing) = runs
            .iter()
            .find(|name| !job.runs.iter().any(|run| run.name == **name))
        {
            return Err(Tried::NoSuchPhase((*missing).to_owned()));
        }
        let job = match self.reach(code.language) {
            Reach::Whole => job,
            Reach::Prefix => job.with_time_factor(WHOLE_RUN_FACTOR),
        };
        self.outputs(exercise, code, job)
    }

    /// The outputs of `job` with the student's code, in a worker.
    fn outputs(&self, exercise: Exercise, code: Code, job: Job) -> Result<Outputs, Tried> {
        let job = job.with_time_factor(code.language.time_factor());
        let native = self
            .tools(code.language)
            .map_err(Tried::Unavailable)?
            .map(|tools| Native {
                language: code.language,
                tools: tools.clone(),
                file: code.language.file_name(exercise.file_name()),
                exercise,
            });
        let cpu_limit = SPARE + Duration::from_millis(job.limits_ms() + u64::from(LOAD_LIMIT_MS));
        let child = self.start(cpu_limit).map_err(Tried::DidNotStart)?;
        self.carry_out(child, code.text, native, job, cpu_limit)
            .map_err(Tried::Failed)
    }

    /// A worker, started with its limits, before it is given anything.
    fn start(&self, cpu_limit: Duration) -> Result<std::process::Child, DidNotStart> {
        let parent = std::process::id();
        let mut command = Command::new(&self.executable);
        command
            .arg(WORKER_COMMAND)
            .env_clear()
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let seconds = cpu_limit.as_secs() + 1;
        // SAFETY: between fork and exec the closure calls only async-signal-safe functions
        // (prctl, getppid, setrlimit) and allocates nothing.
        unsafe {
            command.pre_exec(move || die_with_parent(parent, seconds));
        }
        command.spawn().map_err(DidNotStart)
    }

    /// The outputs of a worker that started, or why it gave none.
    fn carry_out(
        &self,
        mut child: std::process::Child,
        source: &str,
        native: Option<Native>,
        job: Job,
        cpu_limit: Duration,
    ) -> Result<Outputs, Failure> {
        let limit = (cpu_limit * WALL_CLOCK_FACTOR).min(self.clock_limit.unwrap_or(Duration::MAX));
        let input = serde_json::to_string(&WorkerInput {
            source: source.to_owned(),
            native,
            job: job.clone(),
            threads: self.threads,
        })
        .expect("worker inputs serialise");
        let mut stdin = child.stdin.take().expect("piped stdin");
        let writer = beside(&mut child, move || stdin.write_all(input.as_bytes()))?;
        let stdout = child.stdout.take().expect("piped stdout");
        let reader = beside(&mut child, move || {
            // One byte past the limit tells a report that is too large; stopping there
            // ends the worker, whose next write fails.
            let mut text = String::new();
            stdout
                .take(MAX_OUTPUT + 1)
                .read_to_string(&mut text)
                .map(|_| text)
        })?;
        let stderr = child.stderr.take().expect("piped stderr");
        let complaints = beside(&mut child, move || {
            let mut text = String::new();
            let _ = stderr.take(64 << 10).read_to_string(&mut text);
            text
        })?;

        // Reaped here (not by `child`), so that its CPU time is counted: `workers_spent`.
        let pid = child.id() as libc::pid_t;
        let started = Instant::now();
        let status = loop {
            match cpu::reap(pid, false) {
                Ok(Some(status)) => break status,
                Ok(None) if started.elapsed() > limit => {
                    let _ = child.kill();
                    let _ = cpu::reap(pid, true);
                    return Err(Failure::Hung {
                        seconds: limit.as_secs(),
                    });
                }
                Ok(None) => thread::sleep(Duration::from_millis(5)),
                Err(e) => return Err(Failure::Unwatched(e)),
            }
        };
        let _ = writer.join();
        let output = reader.join().ok().and_then(Result::ok).unwrap_or_default();
        let complaints = complaints.join().unwrap_or_default();
        if let Some(error) = student_fault(output.len(), status, &complaints, cpu_limit) {
            return Ok(Outputs::every_phase(
                &job,
                |function| FunctionOutput::failed(function, error.clone()),
                |run| RunOutput::failed(run, error.clone()),
            ));
        }
        if !status.success() {
            return Err(Failure::Crashed { status, complaints });
        }
        serde_json::from_str(&output).map_err(Failure::Unreadable)
    }
}

/// Why a worker's end is the student's code's doing, not the sandbox's, if it is: then
/// every test fails with this message, and the submission stays gradable.
/// A thread of this process beside the worker `child` (feeding it, reading it): one the
/// machine will not give (out of threads, as a loop of them elsewhere could leave it) is
/// a fault of the sandbox's, and the worker is ended.
fn beside<T: Send + 'static>(
    child: &mut std::process::Child,
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<thread::JoinHandle<T>, Failure> {
    thread::Builder::new().spawn(work).map_err(|e| {
        let _ = child.kill();
        let _ = child.wait();
        Failure::Unwatched(e)
    })
}

fn student_fault(
    output_bytes: usize,
    status: std::process::ExitStatus,
    complaints: &str,
    cpu_limit: Duration,
) -> Option<String> {
    if output_bytes as u64 > MAX_OUTPUT {
        // Only the student's code makes the reports this large.
        return Some(format!(
            "Your code's answers came to more than {} MB, far more than any answer of the exercise: every test fails.",
            MAX_OUTPUT >> 20
        ));
    }
    if status.code() == Some(OVERRUN_EXIT) {
        // The watchdog ended the worker: a phase stalled in one call, which it names.
        let call = complaints
            .lines()
            .find_map(|line| line.strip_prefix(OVERRUN_PREFIX))
            .unwrap_or("a test");
        return Some(format!(
            "Stopped while running {call}: a single call ran for more than a second of CPU time where the time limit cannot interrupt it (a built-in function on huge data, such as indexOf on long strings?), and every test fails."
        ));
    }
    // The kernel's limit on the worker's CPU time: only the student's code gets there,
    // with built-in calls the engines' own limits cannot interrupt.
    (status.signal() == Some(libc::SIGXCPU)).then(|| {
        format!(
            "Your code used more than {} s of CPU time in all, in single calls the time limits cannot interrupt (a built-in function on huge data?): every test fails.",
            cpu_limit.as_secs()
        )
    })
}

/// In the worker, before it runs: it gets SIGKILL when the process that started it dies
/// (even by SIGKILL), and SIGXCPU from the kernel after `cpu_seconds` of CPU time.
fn die_with_parent(parent: u32, cpu_seconds: u64) -> std::io::Result<()> {
    // SAFETY: plain system calls on this process, with no pointers but a valid rlimit.
    unsafe {
        if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
            return Err(std::io::Error::last_os_error());
        }
        // The parent may have died before the signal was asked for. (No allocation
        // between fork and exec: an error made from a number.)
        if libc::getppid() as u32 != parent {
            return Err(std::io::Error::from_raw_os_error(libc::ESRCH));
        }
        // SIGXCPU at the soft limit (which the server tells from a crash), SIGKILL a
        // second later if that did not end it.
        let limit = libc::rlimit {
            rlim_cur: cpu_seconds,
            rlim_max: cpu_seconds + 1,
        };
        if libc::setrlimit(libc::RLIMIT_CPU, &limit) != 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    // Nothing the server inherited (a socket, a log) reaches the worker and what it runs.
    super::close_others_at_exec(3)
}
