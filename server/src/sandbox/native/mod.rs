//! Students' files in native engines, each phase's in an interpreter inside an
//! operating-system sandbox of its own (`jail`). Python 3 with NumPy and MATLAB in GNU
//! Octave answer the calls of the same harness in JavaScript that grades JavaScript
//! (`interpreter`, `harness.py`, `harness.m`): the harness and the exercise's loop run in
//! QuickJS as for a JavaScript file, outside the jail, with a file of stand-ins for the
//! student's functions (`bridge`), so the loop's bookkeeping and the run's data stay out
//! of the student's reach, and the grading is the same code whatever the language.
//! JavaScript on V8 (Node) runs that harness itself, with the student's file, inside the
//! jail (`harness.node.js`): compiled rather than interpreted, it gets through whole data
//! sets.

mod bridge;
mod interpreter;
mod jail;

pub use bridge::Bridge;
pub use interpreter::Interpreter;
pub use jail::{Invocation, Tools};

use jail::PROGRESS_FD;

use super::engine::HARNESS;
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::LazyLock;

/// How a native language's files are run: its interpreter in its jail.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Native {
    pub language: Language,
    pub tools: Tools,
    /// The student's file, as its language names it (`ekf_localization.py`): its
    /// interpreter's messages name it.
    pub file: String,
    /// Whose functions the file holds: their arguments and outputs, as the harness in
    /// the interpreter carries them (`Exercise::interface`).
    pub exercise: Exercise,
}

/// Why a language cannot be graded on this machine.
#[derive(Clone, Debug, thiserror::Error)]
pub enum Unavailable {
    #[error("{0} is not installed (looked in {1})")]
    Missing(&'static str, String),
    #[error("the sandbox for {language} does not start on this machine: {reason}")]
    NoSandbox { language: Language, reason: String },
    /// JavaScript on QuickJS was asked for.
    #[error("QuickJS was chosen (--javascript quickjs)")]
    Declined,
}

/// Where the programs are looked for: Debian's places.
const SEARCHED: &[&str] = &["/usr/bin", "/usr/local/bin", "/bin"];

impl Native {
    /// The tools for `language` on this machine, tried once: its interpreter started in
    /// its jail and loading its libraries.
    pub fn detect(language: Language) -> Result<Tools, Unavailable> {
        let program = match language {
            Language::Python => "python3",
            Language::Matlab => "octave-cli",
            Language::JavaScript => "node",
        };
        let tools = Tools {
            bwrap: find("bwrap")?,
            interpreter: find(program)?,
        };
        let check = Interpreter::start(&tools, &invocation(language, 15), ("", "check.py"), &[]);
        check
            .map(|_| tools)
            .map_err(|refused| Unavailable::NoSandbox {
                language,
                reason: refused.to_string(),
            })
    }
}

fn find(program: &'static str) -> Result<PathBuf, Unavailable> {
    SEARCHED
        .iter()
        .map(|dir| Path::new(dir).join(program))
        .find(|path| path.is_file())
        .ok_or_else(|| Unavailable::Missing(program, SEARCHED.join(", ")))
}

/// How a language's interpreter is started, with `cpu_seconds` of CPU time in all.
pub fn invocation(language: Language, cpu_seconds: u64) -> Invocation<'static> {
    match language {
        Language::Python => Invocation {
            // Isolated (no user site, no environment, no working folder on the path), the
            // harness as the program.
            args: &["-I", "-c", HARNESS_PY],
            // One thread for NumPy's BLAS: the filter lets the process make no other.
            env: &[("OPENBLAS_NUM_THREADS", "1"), ("OMP_NUM_THREADS", "1")],
            cpu_seconds,
            progress: false,
        },
        Language::Matlab => Invocation {
            args: &OCTAVE_ARGS[..],
            env: &[("OPENBLAS_NUM_THREADS", "1"), ("OMP_NUM_THREADS", "1")],
            cpu_seconds,
            progress: false,
        },
        Language::JavaScript => Invocation {
            args: &NODE_ARGS[..],
            env: &[],
            cpu_seconds,
            progress: true,
        },
    }
}

/// V8's heap for the student's data and the harness's records of a whole data set.
pub const V8_HEAP_MB: u32 = 256;

/// What Node says on stderr when V8's heap is full, before it aborts.
pub const V8_OUT_OF_MEMORY: &str = "JavaScript heap out of memory";

/// Node's arguments: V8's heap limit, one helper thread of V8's, a later tier-up to
/// V8's optimising compiler, and the program of `harness.node.js` called with the
/// harness and every exercise's loop. Each process compiles the harness and the
/// student's code afresh, and its optimising compiler took a third of a grading's CPU
/// time; optimising only what has run about four times as long as V8 waits by default
/// made the runs and the function phases a seventh cheaper in all (BENCHMARKS.md).
static NODE_ARGS: LazyLock<[&'static str; 5]> = LazyLock::new(|| {
    [
        NODE_HEAP.as_str(),
        "--v8-pool-size=1",
        "--interrupt-budget=300000",
        "-e",
        NODE_PROGRAM.as_str(),
    ]
});

static NODE_HEAP: LazyLock<String> = LazyLock::new(|| format!("--max-old-space-size={V8_HEAP_MB}"));

static NODE_PROGRAM: LazyLock<String> = LazyLock::new(|| {
    let loops: Vec<(&str, &str)> = Exercise::ALL
        .iter()
        .map(|exercise| {
            let declared = exercise.declaration();
            (declared.run_loop, declared.harness_loop)
        })
        .collect();
    format!(
        "{}({}, {}, {PROGRESS_FD});",
        HARNESS_NODE.trim_end(),
        serde_json::Value::from(HARNESS),
        serde_json::json!(loops)
    )
});

/// Octave's arguments: no start-up files of the user's or the site's, no history, no
/// window system, and a few lines that write the harness (`harness.m`) into the
/// sandbox's `/tmp` and run it (a function file, so that its helpers are its own and the
/// student's `clear all` leaves them be).
static OCTAVE_ARGS: LazyLock<[&'static str; 8]> = LazyLock::new(|| {
    [
        "--norc",
        "--no-history",
        "--no-init-file",
        "--no-site-file",
        "--no-window-system",
        "--quiet",
        "--eval",
        OCTAVE_BOOT.as_str(),
    ]
});

static OCTAVE_BOOT: LazyLock<String> = LazyLock::new(|| {
    let text = HARNESS_M
        .replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n");
    format!(
        "mkdir('/tmp/estlab-harness'); fid = fopen('/tmp/estlab-harness/estlab_harness.m', 'w'); \
         fputs(fid, \"{text}\"); fclose(fid); clear fid; addpath('/tmp/estlab-harness'); \
         estlab_harness();"
    )
});

/// How a function missing from a file is to be declared, in the harness's message: its
/// name takes the place of `NAME`.
pub fn declaring(language: Language) -> &'static str {
    match language {
        Language::Python => "def NAME(...):",
        Language::Matlab => "function ... = NAME(...)",
        Language::JavaScript => "function NAME(...) { ... }",
    }
}

const HARNESS_NODE: &str = include_str!("harness.node.js");
const HARNESS_PY: &str = include_str!("harness.py");
const HARNESS_M: &str = include_str!("harness.m");
