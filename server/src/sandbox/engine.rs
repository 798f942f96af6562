//! Inside the worker process: the student's code in QuickJS, driven by the same harness
//! the browser's Web Worker runs (`static/src/harness.js`, with the loop of the exercise
//! whose run a phase is, from its folder). The engine has no file system,
//! network, module loader or host functions beyond the harness's progress callback; each
//! phase of the job runs within a limit of its own CPU time (the interrupt handler reads
//! the clock of the engine's thread, so a busy machine changes no verdict), a memory limit
//! and a stack limit. A phase that is stopped loses its outputs. What stopped it is read
//! from the engine's state, never from what was thrown (which the student's code can
//! imitate): the interrupt handler's flag for time, the allocator's for memory.

use super::cpu::{CpuClock, ThreadClock};
use super::error::Failure;
use super::memory::Metered;
use super::native::{self, Bridge, Interpreter, Native};
use super::watchdog::{Pulse, Watchdog};
use labs::grading::{
    Cause, FUNCTION_LIMIT_MS, FunctionOutput, FunctionPhase, Job, Outputs, Phase, PhaseKind,
    PhaseOutput, RunOutput, Stopped,
};
use labs::{Exercise, Language};
use rquickjs::{CatchResultExt, CaughtError, Context, Function, Object, Persistent, Runtime};
use std::cell::{Cell, RefCell};
use std::rc::Rc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

pub(super) const HARNESS: &str = include_str!("../../../static/src/harness.js");
/// Memory for the student's code and its data (the harness's too).
pub const MEMORY_LIMIT: usize = 64 << 20;
/// Stack for the student's code: deep recursion ends in "stack overflow".
pub const STACK_LIMIT: usize = 512 << 10;
/// CPU time for loading the harness into a fresh engine.
const HARNESS_LIMIT: Duration = Duration::from_secs(5);
/// CPU time for evaluating the student's file once before any phase: a file whose top
/// level never ends is stopped once, not once per phase. The same as a function phase's
/// limit, which is all the browser (which has no such check) gives the top level.
pub const LOAD_LIMIT_MS: u32 = FUNCTION_LIMIT_MS;

/// The CPU time one phase may still use, shared between the engine and its interrupt
/// handler (both on the engine's thread): the engine's own, and for a file in another
/// language its interpreter's.
struct Budget {
    clock: ThreadClock,
    interpreter: Option<ProcessTime>,
    limit: Cell<Duration>,
    /// Set when the handler stopped the code: the phase ended for time, whatever the
    /// error that unwound it says.
    interrupted: Cell<bool>,
    /// Where the watchdog sees that the engine looked at its clock.
    pulse: Arc<Pulse>,
    /// Where and why the student's code made its interpreter stop answering, if it did:
    /// the interrupt handler then ends the phase.
    halted: RefCell<Option<(String, String)>>,
}

impl Budget {
    fn exhausted(&self) -> bool {
        let now = self.clock.now();
        self.pulse.looked(now);
        let interpreter = self
            .interpreter
            .as_ref()
            .map_or(Duration::ZERO, ProcessTime::elapsed);
        let over = self.clock.elapsed() + interpreter > self.limit.get();
        if over {
            self.interrupted.set(true);
        }
        over
    }

    fn start(&self, limit: Duration) {
        self.clock.restart();
        if let Some(interpreter) = &self.interpreter {
            interpreter.restart();
        }
        self.limit.set(limit);
        self.interrupted.set(false);
    }
}

/// A stopwatch of an interpreter's CPU time, which keeps its last reading once the
/// process has ended.
struct ProcessTime {
    clock: CpuClock,
    start: Cell<Duration>,
    last: Cell<Duration>,
}

impl ProcessTime {
    fn new(clock: CpuClock) -> ProcessTime {
        let time = ProcessTime {
            clock,
            start: Cell::new(Duration::ZERO),
            last: Cell::new(Duration::ZERO),
        };
        time.restart();
        time
    }

    fn now(&self) -> Duration {
        if let Some(now) = self.clock.read() {
            self.last.set(now);
        }
        self.last.get()
    }

    fn restart(&self) {
        self.start.set(self.now());
    }

    fn elapsed(&self) -> Duration {
        self.now().saturating_sub(self.start.get())
    }
}

/// A student's file in another language: how it runs, and its text.
#[derive(Clone, Copy)]
pub struct Foreign<'a> {
    pub native: &'a Native,
    pub source: &'a str,
}

struct Engine {
    // Dropped in this order: the harness's functions, then the context, then the runtime.
    call_function: Persistent<Function<'static>>,
    run: Persistent<Function<'static>>,
    context: Context,
    _runtime: Runtime,
    budget: Rc<Budget>,
    /// Set by the allocator when it first refused an allocation, to what the engine ran
    /// then: the phase ran out of memory there.
    out_of_memory: Rc<RefCell<Option<String>>>,
    /// How a missing function is to be declared, in the student's language (`None`:
    /// JavaScript, which the harness knows).
    declaring: Option<&'static str>,
    /// The interpreter of a file in another language (ended with the engine).
    _bridge: Option<Bridge>,
}

impl Engine {
    /// An engine with the harness loaded, and the loop of the exercise whose run it is to
    /// carry out if it is one, showing the watchdog its `pulse`.
    fn new(
        pulse: Arc<Pulse>,
        run_loop: Option<&str>,
        foreign: Option<(Foreign, Duration)>,
    ) -> Result<Engine, Failure> {
        let bridge = foreign
            .map(|(foreign, limit)| {
                let invocation = native::invocation(
                    foreign.native.language,
                    limit.as_secs() + INTERPRETER_SPARE_S,
                );
                Interpreter::start(
                    &foreign.native.tools,
                    &invocation,
                    (foreign.source, &foreign.native.file),
                    &foreign.native.exercise.interface(),
                )
                .map(Bridge::new)
                .map_err(|refused| Failure::Jail(refused.to_string()))
            })
            .transpose()?;
        let out_of_memory = Rc::new(RefCell::new(None));
        let allocator = Metered::new(MEMORY_LIMIT, Arc::clone(&pulse), Rc::clone(&out_of_memory));
        let runtime = Runtime::new_with_alloc(allocator).map_err(Failure::Engine)?;
        runtime.set_max_stack_size(STACK_LIMIT);
        let budget = Rc::new(Budget {
            clock: ThreadClock::start(),
            interpreter: bridge
                .as_ref()
                .map(|bridge| ProcessTime::new(bridge.clock())),
            limit: Cell::new(HARNESS_LIMIT),
            interrupted: Cell::new(false),
            pulse,
            halted: RefCell::new(None),
        });
        let handler = Rc::clone(&budget);
        // The handler runs on this thread only: the engine never leaves it.
        runtime.set_interrupt_handler(Some(Box::new(move || {
            handler.exhausted() || handler.halted.borrow().is_some()
        })));
        let context = Context::full(&runtime).map_err(Failure::Engine)?;
        let (call_function, run) = context.with(|ctx| {
            ctx.eval::<(), _>(HARNESS)
                .catch(&ctx)
                .map_err(harness_failed(HARNESS_PART))?;
            if let Some(source) = run_loop {
                ctx.eval::<(), _>(source)
                    .catch(&ctx)
                    .map_err(harness_failed("the harness's loop"))?;
            }
            if let Some(bridge) = &bridge {
                let (watched, halted) = (Rc::clone(&budget), Rc::clone(&budget));
                let halt = move |reason: String| {
                    let mut slot = halted.halted.borrow_mut();
                    if slot.is_none() {
                        *slot = Some((halted.pulse.label(), reason));
                    }
                };
                bridge
                    .install(&ctx, Rc::new(move || watched.exhausted()), Rc::new(halt))
                    .catch(&ctx)
                    .map_err(harness_failed("the bridge to the interpreter"))?;
            }
            let harness: Object = ctx
                .globals()
                .get("estlabHarness")
                .map_err(harness_failed(HARNESS_PART))?;
            let get = |name: &str| -> Result<Persistent<Function<'static>>, Failure> {
                let f: Function = harness.get(name).map_err(harness_failed(HARNESS_PART))?;
                Ok(Persistent::save(&ctx, f))
            };
            Ok::<_, Failure>((get("callFunction")?, get("run")?))
        })?;
        Ok(Engine {
            call_function,
            run,
            context,
            _runtime: runtime,
            budget,
            out_of_memory,
            declaring: foreign.map(|(foreign, _)| native::declaring(foreign.native.language)),
            _bridge: bridge,
        })
    }

    /// One phase: the harness's report (JSON text), or what stopped it.
    fn phase(
        &self,
        kind: PhaseKind,
        source: &str,
        phase: &str,
        limit: Duration,
    ) -> Result<String, Stopped> {
        let pulse = &self.budget.pulse;
        let harness = match kind {
            PhaseKind::Run => &self.run,
            PhaseKind::Function => &self.call_function,
        };
        self.budget.start(limit);
        let outcome = self.context.with(|ctx| {
            let f = harness.clone().restore(&ctx).map_err(|e| e.to_string())?;
            let label = Arc::clone(pulse);
            let progress = Function::new(ctx.clone(), move |text: String| label.running(text))
                .map_err(|e| e.to_string())?;
            f.call::<_, String>((source, phase, progress, self.declaring))
                .catch(&ctx)
                .map_err(|e| escaped(&e))
        });
        // QuickJS looks at the clock between bytecode steps only: one built-in call on
        // huge data (a naive indexOf, a huge BigInt's digits) can run past the limit and
        // return. Such a phase is over its time all the same.
        let over_time = self.budget.interrupted.get() || self.budget.exhausted();
        // Where it stopped: where it ran out of memory, if it did, else where it was
        // when it ended (what the harness said last).
        let out_of_memory = self.out_of_memory.borrow().clone();
        let stopped = |label: String, cause: Cause| Stopped {
            // The limit the message names: the phase's own.
            limit_ms: (cause == Cause::Time).then_some(limit.as_millis() as u32),
            during: if label.is_empty() {
                "your file".to_owned()
            } else {
                label
            },
            cause,
        };
        let halted = self.budget.halted.take();
        match (outcome, out_of_memory) {
            _ if over_time => Err(stopped(pulse.label(), Cause::Time)),
            // The interpreter stopped answering (it slept, wrote too much, ended): the
            // phase ends where it was then.
            _ if halted.is_some() => {
                let (label, reason) = halted.unwrap_or_default();
                Err(stopped(label, Cause::Other(reason)))
            }
            // However the phase ended: its code, or the harness after it, lacked memory
            // for something, and what it reported is not to be trusted.
            (_, Some(label)) => Err(stopped(
                label,
                Cause::Other(format!(
                    "out of memory (the limit is {} MB): far too much data allocated",
                    MEMORY_LIMIT >> 20
                )),
            )),
            (Ok(report), None) => Ok(report),
            (Err(what), None) => Err(stopped(
                pulse.label(),
                Cause::Other(format!("the test harness failed: {what}")),
            )),
        }
    }
}

/// CPU time an interpreter may use beyond its phase's limit before the kernel ends it:
/// the phase's own limit ends it first.
const INTERPRETER_SPARE_S: u64 = 12;

/// What the harness is called in a failure to load it.
const HARNESS_PART: &str = "the harness";

/// A part of the harness that did not load, with QuickJS's reason.
fn harness_failed<E: std::fmt::Display>(part: &'static str) -> impl FnOnce(E) -> Failure {
    move |reason| Failure::Harness {
        part,
        reason: reason.to_string(),
    }
}

/// What escaped the harness, by its kind only: the harness describes everything the
/// student's code throws, so this is a fault of the harness, and no text of the student's
/// belongs in it (nor an address of the engine's heap, as a value's display has).
fn escaped(error: &CaughtError) -> String {
    match error {
        CaughtError::Exception(_) => "an exception escaped it".to_owned(),
        CaughtError::Value(value) => format!("a value ({}) escaped it", value.type_name()),
        CaughtError::Error(error) => format!("the engine said: {error}"),
    }
}

/// The stack of each engine's thread: room for QuickJS's own limit and its C frames.
const THREAD_STACK: usize = 8 << 20;

/// Carries out a whole job with the student's source, with at most `threads` engines at
/// once: the outputs the grader reads. The file is evaluated once first; if that is
/// stopped, every phase reports it without running. Otherwise every phase gets a fresh
/// engine, so that nothing one phase leaves behind reaches another, the longest (the
/// data-set runs) first. A watchdog ends the process if a phase stalls in a single call
/// (see `watchdog`).
/// A file in another language runs in its interpreter, one per phase, called through
/// stand-ins of its functions (see `native`).
pub fn carry_out(
    source: &str,
    native: Option<&Native>,
    job: &Job,
    threads: usize,
) -> Result<Outputs, Failure> {
    // JavaScript on V8 runs the harness inside the jail, with the file itself.
    let stand_ins = native
        .filter(|native| native.language != Language::JavaScript)
        .map(|_| Bridge::stand_ins(job));
    let file = File {
        harness_source: stand_ins.as_deref().unwrap_or(source),
        foreign: native.map(|native| Foreign { native, source }),
        functions_cpu_s: job
            .functions
            .iter()
            .map(|phase| u64::from(phase.limit_ms))
            .chain([u64::from(LOAD_LIMIT_MS)])
            .sum::<u64>()
            .div_ceil(1000),
    };
    let source = &file;
    let phases: Vec<Phase> = job.phases().collect();
    let threads = threads.clamp(1, phases.len().max(1));
    let watchdog = Watchdog::new(threads);
    std::thread::scope(|scope| {
        scope.spawn(|| watchdog.patrol());
        // Stopped however `watched` ends, a panic included: the scope waits for the patrol.
        let _stop = StopOnDrop(&watchdog);
        watched(source, job, &phases, threads, &watchdog)
    })
}

/// Stops the watchdog's patrol when dropped.
struct StopOnDrop<'a>(&'a Watchdog);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.stop();
    }
}

/// The student's file as each phase's engine takes it.
struct File<'a> {
    /// What the harness loads: the student's JavaScript, or the stand-ins of the functions
    /// of a file in another language.
    harness_source: &'a str,
    foreign: Option<Foreign<'a>>,
    /// The CPU time of every function phase's limit together, the load check's with them,
    /// in whole seconds: the most a V8 process kept for function phases may use.
    functions_cpu_s: u64,
}

impl<'a> File<'a> {
    /// The file, if it is JavaScript to run on V8.
    fn on_v8(&self) -> Option<Foreign<'a>> {
        self.foreign
            .filter(|foreign| foreign.native.language == Language::JavaScript)
    }
}

/// A worker thread's Node process for function phases (JavaScript on V8), kept from one
/// phase to the next while they end well (see `on_v8`).
type Kept = Option<Interpreter>;

fn watched(
    source: &File,
    job: &Job,
    phases: &[Phase],
    threads: usize,
    watchdog: &Watchdog,
) -> Result<Outputs, Failure> {
    let (stopped, mut kept) = load_check(source, job, watchdog)?;
    if let Some(stopped) = stopped {
        return Ok(Outputs::every_phase(
            job,
            |function| FunctionOutput::stopped(function, stopped.clone()),
            |run| RunOutput::stopped(run, stopped.clone()),
        ));
    }
    let reports: Vec<Mutex<Option<Report>>> = phases.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|slot| {
                let (next, reports) = (&next, &reports);
                // The load check's process goes on with the first worker's functions.
                let mut kept = kept.take();
                std::thread::Builder::new()
                    .stack_size(THREAD_STACK)
                    .spawn_scoped(scope, move || {
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some(phase) = phases.get(i) else {
                                return Ok(());
                            };
                            let watched_as = (slot, phase.name());
                            let report =
                                run_phase(source, *phase, watchdog, watched_as, &mut kept)?;
                            *reports[i].lock().expect("a report slot") = Some(report);
                        }
                    })
                    .map_err(Failure::Thread)
            })
            .collect::<Result<_, Failure>>()?;
        workers.into_iter().try_for_each(
            |worker: std::thread::ScopedJoinHandle<'_, Result<(), Failure>>| {
                worker.join().map_err(|_| Failure::Panicked)?
            },
        )
    })?;
    let mut outputs = Outputs::default();
    for (phase, report) in phases.iter().zip(reports) {
        let report = report
            .into_inner()
            .expect("a report slot")
            .expect("every phase ran");
        match phase.kind() {
            PhaseKind::Function => outputs.functions.push(match report {
                Ok(text) => FunctionOutput::from_report(phase.name(), &text),
                Err(stopped) => FunctionOutput::stopped(phase.name(), stopped),
            }),
            PhaseKind::Run => outputs.runs.push(match report {
                Ok(text) => RunOutput::from_report(phase.name(), &text),
                Err(stopped) => RunOutput::stopped(phase.name(), stopped),
            }),
        }
    }
    Ok(outputs)
}

/// A phase's report, or where the engine stopped it.
type Report = Result<String, Stopped>;

/// What the watchdog calls the evaluation of the file before the phases.
pub const TOP_LEVEL: &str = "the top level of your file (evaluated once, before every test)";

/// Evaluates the file once, calling nothing (a function phase without calls): what
/// stopped it, if anything did, and the V8 process that did it, to go on with.
fn load_check(
    source: &File,
    job: &Job,
    watchdog: &Watchdog,
) -> Result<(Option<Stopped>, Kept), Failure> {
    // Any function of the job will do: none is called.
    let function = job
        .functions
        .iter()
        .map(|phase| &phase.function)
        .chain(job.runs.iter().flat_map(|run| &run.functions))
        .next()
        .expect("every job calls a student function");
    let nothing = FunctionPhase {
        function: function.clone(),
        calls: Vec::new(),
        limit_ms: LOAD_LIMIT_MS,
    };
    let check = || {
        let mut kept = None;
        let phase = Phase::Function(&nothing);
        run_phase(source, phase, watchdog, (0, TOP_LEVEL), &mut kept).map(|report| (report, kept))
    };
    let (report, kept) = if source.on_v8().is_some() {
        // Here, on the thread that outlives the workers: the kernel ends a jailed process
        // with the thread that started it, and this one goes on with the first worker's
        // functions.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(check))
            .map_err(|_| Failure::Panicked)??
    } else {
        // QuickJS, on a thread with room for its stack.
        std::thread::scope(|scope| {
            std::thread::Builder::new()
                .stack_size(THREAD_STACK)
                .spawn_scoped(scope, check)
                .map_err(Failure::Thread)?
                .join()
                .map_err(|_| Failure::Panicked)?
        })?
    };
    let stopped = report.err().map(|stopped| Stopped {
        during: TOP_LEVEL.to_owned(),
        limit_ms: Some(LOAD_LIMIT_MS),
        ..stopped
    });
    Ok((stopped, kept))
}

/// One phase in an engine of its own (on V8, a function phase may go on in the worker's
/// `kept` process), watched in `slot` under the name `watched_as`: the harness's report,
/// or where it was stopped. Only a failure of the sandbox itself is an error.
fn run_phase(
    file: &File,
    phase: Phase,
    watchdog: &Watchdog,
    (slot, watched_as): (usize, &str),
    kept: &mut Kept,
) -> Result<Report, Failure> {
    if let Some(foreign) = file.on_v8() {
        return on_v8(foreign, phase, file.functions_cpu_s, kept);
    }
    let pulse = Arc::new(Pulse::default());
    let run_loop = match phase {
        Phase::Run(run) => Exercise::ALL
            .iter()
            .map(|exercise| exercise.declaration())
            .find(|declared| declared.run_loop == run.run_loop)
            .map(|declared| declared.harness_loop),
        Phase::Function(_) => None,
    };
    let limit = Duration::from_millis(phase.limit_ms().into());
    let engine = Engine::new(
        Arc::clone(&pulse),
        run_loop,
        file.foreign.map(|foreign| (foreign, limit)),
    )?;
    let _watching = watchdog.watch(slot, watched_as, pulse);
    Ok(engine.phase(phase.kind(), file.harness_source, &phase.to_json(), limit))
}

/// One phase on V8: Node in its jail with the harness and the student's file, the phase's
/// time the process's CPU time from its request on (V8's compiler and collector
/// included). A run has a process of its own, its main realm; function phases go on in
/// the `kept` process of the worker, each in a fresh realm (`harness.node.js`), while
/// they end with a report; a phase stopped ends its process. Node's own start is no part
/// of a phase; a start that fails is the sandbox's failure.
fn on_v8(
    foreign: Foreign,
    phase: Phase,
    functions_cpu_s: u64,
    kept: &mut Kept,
) -> Result<Report, Failure> {
    let limit = Duration::from_millis(phase.limit_ms().into());
    let reused = match phase.kind() {
        PhaseKind::Function => kept.take(),
        PhaseKind::Run => None,
    };
    let mut node = match reused {
        Some(node) => node,
        None => {
            let cpu_s = match phase.kind() {
                PhaseKind::Function => functions_cpu_s,
                PhaseKind::Run => limit.as_secs(),
            };
            let invocation = native::invocation(Language::JavaScript, cpu_s + INTERPRETER_SPARE_S);
            Interpreter::start(
                &foreign.native.tools,
                &invocation,
                (foreign.source, &foreign.native.file),
                &[],
            )
            .map_err(|refused| Failure::Jail(refused.to_string()))?
        }
    };
    let time = ProcessTime::new(node.clock());
    let over = || time.elapsed() > limit;
    let outcome = node.phase(phase.kind(), &phase.to_json(), &over);
    let stopped = |cause: Cause| Stopped {
        limit_ms: (cause == Cause::Time).then_some(phase.limit_ms()),
        during: Some(node.doing())
            .filter(|doing| !doing.is_empty())
            .unwrap_or_else(|| "your file".to_owned()),
        cause,
    };
    Ok(match outcome {
        // However it ended, a phase past its time is over time (as on QuickJS).
        _ if over() => Err(stopped(Cause::Time)),
        Ok(report) => {
            // Kept only if it wrote nothing beyond its report: the student's code writing
            // on the harness's descriptor would otherwise be heard in the next phase.
            if phase.kind() == PhaseKind::Function && node.quiet() {
                *kept = Some(node);
            }
            Ok(report)
        }
        Err(silent) => Err(stopped(Cause::Other(
            node.stopped().unwrap_or_else(|| silent.to_string()),
        ))),
    })
}
