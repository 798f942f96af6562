//! estlab's grader inside the platforms courses already use: Gradescope's autograder and
//! PrairieLearn's external grader (`DESIGN.md`, "Grading on Gradescope and PrairieLearn").
//!
//! A package carries the statically linked estlab binary, the exercise's settings
//! ([`Settings`]) and a secret that draws the hidden cases; the platform runs `estlab
//! autograde` on every submission, which finds the student's file, takes the student's
//! variant from what the platform passes, grades it exactly as `estlab grade
//! --javascript quickjs` would with that secret, and writes the platform's
//! `results.json`.

pub mod elf;
pub mod gradescope;
pub mod prairielearn;
mod results;
mod submitted;

use crate::error::Error;
use crate::grading::{Secret, grader_version};
use crate::sandbox::{Code, JavaScript, Sandbox, check_length, cores};
use labs::Exercise;
use labs::grading::{GradeResult, Reach};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::Path;

pub use results::{
    GraderData, GradescopeResults, GradescopeTest, HIDDEN_LATER, PrairieLearnResults,
    PrairieLearnTest,
};
pub use submitted::student_file;

/// The file of a package holding its [`Settings`].
pub const SETTINGS: &str = "estlab-package.json";
/// The file of a package holding its secret.
pub const SECRET: &str = "secret";

/// What a package grades: the exercise, and the course whose variants students get.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    pub lab: Exercise,
    pub course: String,
}

impl Settings {
    pub fn read(dir: &Path) -> Result<Settings, Error> {
        let path = dir.join(SETTINGS);
        let text = std::fs::read_to_string(&path).map_err(Error::io(&path))?;
        serde_json::from_str(&text).map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
    }

    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        let path = dir.join(SETTINGS);
        let text = serde_json::to_string_pretty(self).expect("settings serialise");
        std::fs::write(&path, text + "\n").map_err(Error::io(&path))
    }
}

/// A package's grader: its settings and secret, read from the folder the platform put
/// them in.
pub struct PackagedGrader {
    pub settings: Settings,
    secret: Secret,
    /// The grader's version, written into every result.
    pub version: String,
}

impl PackagedGrader {
    pub fn read(dir: &Path) -> Result<PackagedGrader, Error> {
        let settings = Settings::read(dir)?;
        let secret = Secret::read(&dir.join(SECRET))?;
        Ok(PackagedGrader {
            // A package grades students' JavaScript on QuickJS.
            version: grader_version(settings.lab, Some(&secret), Reach::Prefix),
            settings,
            secret,
        })
    }

    /// Grades the student's file in `submitted` for the variant `seed`, with the hidden
    /// cases `drawn` says (as `estlab grade --javascript quickjs --secret --submission
    /// KEY` does with the key returned beside the result); a submission without one
    /// gradable file is not gradable, and says why.
    pub fn grade(&self, submitted: &Path, seed: u64, drawn: Drawn) -> (GradeResult, Option<i64>) {
        let lab = self.settings.lab;
        let not_gradable = |reason: String| (GradeResult::not_gradable(lab, seed, reason), None);
        let path = match student_file(submitted, self.settings.lab.file_name()) {
            Ok(path) => path,
            Err(reason) => return not_gradable(reason),
        };
        let name = path
            .strip_prefix(submitted)
            .unwrap_or(&path)
            .display()
            .to_string();
        let length = std::fs::metadata(&path).map_or(0, |m| m.len());
        if let Err(problem) = check_length(length) {
            return not_gradable(format!("{name}: {problem}"));
        }
        let source = match std::fs::read(&path) {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(source) => source,
                Err(_) => return not_gradable(format!("{name} is not UTF-8 text")),
            },
            Err(e) => return not_gradable(format!("{name} could not be read: {e}")),
        };
        // QuickJS, the portable engine, whatever the machine: a platform's image grades
        // in a container whose own sandbox refuses the operating system's.
        let sandbox = match Sandbox::current(cores()) {
            Ok(sandbox) => sandbox.with_javascript(JavaScript::QuickJs),
            Err(e) => return not_gradable(format!("the grader could not start: {e}")),
        };
        let key = drawn.key(&source);
        let hidden = Some(self.secret.hidden(key, &self.settings.course));
        let result = sandbox.grade(self.settings.lab, Code::javascript(&source), seed, hidden);
        (result, Some(key))
    }
}

/// What a submission's hidden cases are drawn from on a platform, besides the secret. A
/// submission gets hidden cases of its own, so that what a hidden case revealed (what the
/// student's code threw with its arguments) is of no use the next time; grading the same
/// submission again draws the same. The platform's name goes into the key, so a package
/// made with a server's secret draws other cases than the server.
pub enum Drawn {
    /// Gradescope: the submission's id.
    GradescopeSubmission(i64),
    /// PrairieLearn, which passes no submission id: the variant's seed and the file
    /// graded (a variant may be submitted many times; every other file gets other cases).
    PrairieLearnVariant(u64),
}

impl Drawn {
    /// The key `Secret::hidden` takes: a SHA-256 of the platform, what identifies
    /// the submission and the file's text, cut to a whole number below 2^53.
    fn key(&self, source: &str) -> i64 {
        let hash = match self {
            Drawn::GradescopeSubmission(id) => Sha256::new()
                .chain_update(b"gradescope submission ")
                .chain_update(id.to_le_bytes()),
            Drawn::PrairieLearnVariant(seed) => Sha256::new()
                .chain_update(b"prairielearn variant ")
                .chain_update(seed.to_le_bytes())
                .chain_update(source.as_bytes()),
        }
        .finalize();
        let mut first = [0; 8];
        first.copy_from_slice(&hash[..8]);
        (u64::from_le_bytes(first) & ((1 << 53) - 1)) as i64
    }
}

/// Writes the results `graded` made under `root`; when grading could not even start (the
/// package or the platform's metadata unreadable), writes results that say why, worth
/// nothing, in the platform's format (`unreadable`), and returns the error.
fn write_graded<R: Serialize>(
    root: &Path,
    graded: Result<R, Error>,
    unreadable: impl FnOnce(&str) -> R,
) -> Result<(), Error> {
    match graded {
        Ok(results) => write_results(root, &results),
        Err(error) => {
            let reason = format!("the package could not grade this submission: {error}");
            write_results(root, &unreadable(&reason))?;
            Err(error)
        }
    }
}

/// Writes `json` to `results/results.json` under `root`, making the folder (neither
/// platform makes it).
fn write_results(root: &Path, json: &impl Serialize) -> Result<(), Error> {
    let dir = root.join("results");
    std::fs::create_dir_all(&dir).map_err(Error::io(&dir))?;
    let path = dir.join("results.json");
    let text = serde_json::to_string_pretty(json).expect("results serialise");
    std::fs::write(&path, text + "\n").map_err(Error::io(&path))
}
