//! Inside the worker process: the student's code in QuickJS, driven by the same harness
//! the browser's Web Worker runs (`static/src/harness.js`). The engine has no file system,
//! network, module loader or host functions beyond the harness's progress callback; each
//! phase of the job runs under a deadline (the interrupt handler) within a memory limit
//! and a stack limit. A phase that is stopped loses its outputs.

use labs::grading::Stopped;
use rquickjs::{CatchResultExt, Context, Function, Object, Persistent, Runtime};
use serde_json::Value;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const HARNESS: &str = include_str!("../../../static/src/harness.js");
/// Memory for the student's code and its data.
pub const MEMORY_LIMIT: usize = 64 << 20;
/// Stack for the student's code: deep recursion ends in "stack overflow".
pub const STACK_LIMIT: usize = 512 << 10;

struct Engine {
    // Dropped in this order: the harness's functions, then the context, then the runtime.
    call_function: Persistent<Function<'static>>,
    run_filter: Persistent<Function<'static>>,
    context: Context,
    _runtime: Runtime,
    deadline: Arc<Mutex<Instant>>,
}

impl Engine {
    fn new() -> Result<Engine, String> {
        let runtime = Runtime::new().map_err(|e| format!("QuickJS: {e}"))?;
        runtime.set_memory_limit(MEMORY_LIMIT);
        runtime.set_max_stack_size(STACK_LIMIT);
        // Loading the harness has a few seconds; every phase sets its own deadline.
        let deadline = Arc::new(Mutex::new(Instant::now() + Duration::from_secs(5)));
        let clock = Arc::clone(&deadline);
        runtime.set_interrupt_handler(Some(Box::new(move || {
            Instant::now() > *clock.lock().expect("deadline lock")
        })));
        let context = Context::full(&runtime).map_err(|e| format!("QuickJS: {e}"))?;
        let (call_function, run_filter) = context.with(|ctx| {
            ctx.eval::<(), _>(HARNESS)
                .catch(&ctx)
                .map_err(|e| format!("the harness: {e}"))?;
            let harness: Object = ctx
                .globals()
                .get("estlabHarness")
                .map_err(|e| format!("the harness: {e}"))?;
            let get = |name: &str| -> Result<Persistent<Function<'static>>, String> {
                let f: Function = harness.get(name).map_err(|e| format!("the harness: {e}"))?;
                Ok(Persistent::save(&ctx, f))
            };
            Ok::<_, String>((get("callFunction")?, get("runFilter")?))
        })?;
        Ok(Engine {
            call_function,
            run_filter,
            context,
            _runtime: runtime,
            deadline,
        })
    }

    /// One phase: the harness's answer (JSON text), or what stopped it.
    fn phase(
        &self,
        run: bool,
        source: &str,
        phase: &str,
        limit: Duration,
    ) -> Result<String, Stopped> {
        let during = Rc::new(RefCell::new(String::from("your file")));
        *self.deadline.lock().expect("deadline lock") = Instant::now() + limit;
        let harness = if run {
            &self.run_filter
        } else {
            &self.call_function
        };
        let outcome = self.context.with(|ctx| {
            let f = harness.clone().restore(&ctx).map_err(|e| e.to_string())?;
            let label = Rc::clone(&during);
            let progress = Function::new(ctx.clone(), move |text: String| {
                *label.borrow_mut() = text;
            })
            .map_err(|e| e.to_string())?;
            f.call::<_, String>((source, phase, progress))
                .catch(&ctx)
                .map_err(|e| e.to_string())
        });
        let timed_out = Instant::now() > *self.deadline.lock().expect("deadline lock");
        outcome.map_err(|message| Stopped {
            during: during.borrow().clone(),
            cause: if timed_out {
                "time".to_owned()
            } else {
                cause(&message)
            },
        })
    }
}

/// What QuickJS said, in the words a student understands.
fn cause(message: &str) -> String {
    if message.contains("out of memory") {
        format!(
            "out of memory (the limit is {} MB): far too much data allocated",
            MEMORY_LIMIT >> 20
        )
    } else if message.contains("stack overflow") {
        "stack overflow: recursion too deep".to_owned()
    } else {
        format!("the sandbox failed: {}", message.trim())
    }
}

/// The most engines that run phases at once (each a thread with a QuickJS runtime).
const MAX_THREADS: usize = 4;
/// The stack of each engine's thread: room for QuickJS's own limit and its C frames.
const THREAD_STACK: usize = 8 << 20;

/// Carries out a whole job (from `Plan::job`) with the student's source: the outputs the
/// grader reads, as `labs::grading::Outputs` JSON. Every phase gets a fresh engine, so
/// that nothing one phase leaves behind reaches another, and phases run side by side on
/// the machine's cores, the longest (the data-set runs) first.
pub fn carry_out(source: &str, job: &Value) -> Result<Value, String> {
    let mut phases: Vec<(bool, &Value)> = Vec::new();
    for (list, run) in [("runs", true), ("functions", false)] {
        phases.extend(
            job[list]
                .as_array()
                .into_iter()
                .flatten()
                .map(|phase| (run, phase)),
        );
    }
    let outputs: Vec<Mutex<Option<Value>>> = phases.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .clamp(1, MAX_THREADS)
        .min(phases.len().max(1));
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                std::thread::Builder::new()
                    .stack_size(THREAD_STACK)
                    .spawn_scoped(scope, || {
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some(&(run, phase)) = phases.get(i) else {
                                return Ok(());
                            };
                            let output = run_phase(source, run, phase)?;
                            *outputs[i].lock().expect("an output slot") = Some(output);
                        }
                    })
                    .map_err(|e| format!("the sandbox could not start a thread: {e}"))
            })
            .collect::<Result<_, String>>()?;
        workers.into_iter().try_for_each(
            |worker: std::thread::ScopedJoinHandle<'_, Result<(), String>>| {
                worker
                    .join()
                    .map_err(|_| "a sandbox thread panicked".to_owned())?
            },
        )
    })?;
    let mut result = serde_json::json!({ "functions": [], "runs": [] });
    for (&(run, _), output) in phases.iter().zip(outputs) {
        let output = output
            .into_inner()
            .expect("an output slot")
            .expect("every phase ran");
        let list = if run { "runs" } else { "functions" };
        result[list].as_array_mut().expect("a list").push(output);
    }
    Ok(result)
}

/// One phase in an engine of its own: the harness's output, or where it was stopped.
fn run_phase(source: &str, run: bool, phase: &Value) -> Result<Value, String> {
    let engine = Engine::new()?;
    let limit = Duration::from_millis(phase["limit_ms"].as_u64().unwrap_or(1000));
    match engine.phase(run, source, &phase.to_string(), limit) {
        Ok(json) => {
            serde_json::from_str(&json).map_err(|e| format!("the harness wrote bad JSON: {e}"))
        }
        Err(stopped) => {
            let key = if run { "name" } else { "function" };
            Ok(serde_json::json!({ key: phase[key], "stopped": stopped }))
        }
    }
}
