//! The server's side of the sandbox: each grading runs the student's code in a worker
//! process of its own (`estlab sandbox-worker`), so that a crash or a hang harms no other
//! submission and not the server. The worker gets the job on stdin and writes the outputs
//! on stdout; a worker that dies, or outlives every phase's time limit together, makes
//! the result "not gradable", which costs the student nothing.

use labs::grading::{GradeResult, LAB, Outputs, Plan, grade};
use serde_json::{Value, json};
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

/// The subcommand of `estlab` that is the worker.
const WORKER_COMMAND: &str = "sandbox-worker";
/// The largest source file accepted, in bytes.
pub const MAX_SOURCE: usize = 256 << 10;
/// Whether a source file is small enough to be graded; if not, why not.
pub fn check_size(source: &str) -> Result<(), String> {
    if source.len() > MAX_SOURCE {
        return Err(format!(
            "{} bytes; a submission may have at most {} KB",
            source.len(),
            MAX_SOURCE >> 10
        ));
    }
    Ok(())
}

/// The most a worker may write (its outputs are a few hundred kilobytes).
const MAX_OUTPUT: u64 = 64 << 20;
/// Time for the worker to start, generate nothing and write, beyond the phases' limits.
const SPARE: Duration = Duration::from_secs(10);

/// Starts workers from the `estlab` executable.
#[derive(Clone, Debug)]
pub struct Sandbox {
    executable: PathBuf,
}

impl Sandbox {
    pub fn new(executable: PathBuf) -> Sandbox {
        Sandbox { executable }
    }

    /// This very executable.
    pub fn current() -> std::io::Result<Sandbox> {
        Ok(Sandbox::new(std::env::current_exe()?))
    }

    /// Grades a source file for a seed: the plan, the student's code in a worker, the
    /// comparison. Blocks for as long as the worker runs.
    pub fn grade(&self, source: &str, seed: u64) -> GradeResult {
        let plan = Plan::new(seed);
        let job = plan.job();
        match self.carry_out(source, &job) {
            Ok(outputs) => grade(&plan, &outputs),
            Err(reason) => GradeResult::not_gradable(LAB, seed, reason),
        }
    }

    fn carry_out(&self, source: &str, job: &Value) -> Result<Outputs, String> {
        let limit = SPARE + phase_limits(job);
        let mut child = Command::new(&self.executable)
            .arg(WORKER_COMMAND)
            .env_clear()
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("the sandbox did not start: {e}"))?;
        let input = json!({ "source": source, "job": job }).to_string();
        let mut stdin = child.stdin.take().expect("piped stdin");
        let writer = thread::spawn(move || stdin.write_all(input.as_bytes()));
        let stdout = child.stdout.take().expect("piped stdout");
        let reader = thread::spawn(move || {
            let mut text = String::new();
            stdout
                .take(MAX_OUTPUT)
                .read_to_string(&mut text)
                .map(|_| text)
        });
        let stderr = child.stderr.take().expect("piped stderr");
        let complaints = thread::spawn(move || {
            let mut text = String::new();
            let _ = stderr.take(64 << 10).read_to_string(&mut text);
            text
        });

        let started = Instant::now();
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if started.elapsed() > limit => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(format!(
                        "the sandbox did not finish within {} s",
                        limit.as_secs()
                    ));
                }
                Ok(None) => thread::sleep(Duration::from_millis(5)),
                Err(e) => return Err(format!("the sandbox could not be watched: {e}")),
            }
        };
        let _ = writer.join();
        let output = reader.join().ok().and_then(Result::ok).unwrap_or_default();
        let complaints = complaints.join().unwrap_or_default();
        if !status.success() {
            return Err(format!(
                "the sandbox failed ({status}){}",
                if complaints.trim().is_empty() {
                    String::new()
                } else {
                    format!(": {}", complaints.trim())
                }
            ));
        }
        serde_json::from_str(&output)
            .map_err(|e| format!("the sandbox wrote unreadable outputs: {e}"))
    }
}

/// Every phase's time limit, together.
fn phase_limits(job: &Value) -> Duration {
    let ms: u64 = ["functions", "runs"]
        .iter()
        .flat_map(|list| job[list].as_array().into_iter().flatten())
        .map(|phase| phase["limit_ms"].as_u64().unwrap_or(0))
        .sum();
    Duration::from_millis(ms)
}
