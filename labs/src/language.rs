//! The languages a student may write an exercise's file in. JavaScript runs everywhere (the
//! browser's worker, QuickJS on the server and in the platforms' packages); the others
//! run on the server only (MATLAB in GNU Octave), each in its interpreter inside the
//! operating-system sandbox, called by the same harness and graded by the same code.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;
use ts_rs::TS;

/// A language of students' files.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, TS,
)]
#[serde(rename_all = "lowercase")]
pub enum Language {
    #[default]
    JavaScript,
    Python,
    /// MATLAB, graded with GNU Octave.
    Matlab,
}

impl Language {
    pub const ALL: &'static [Language] =
        &[Language::JavaScript, Language::Python, Language::Matlab];

    /// The name the API, the command line and the store use: `python`.
    pub fn name(self) -> &'static str {
        match self {
            Language::JavaScript => "javascript",
            Language::Python => "python",
            Language::Matlab => "matlab",
        }
    }

    /// What a person calls it.
    pub fn title(self) -> &'static str {
        match self {
            Language::JavaScript => "JavaScript",
            Language::Python => "Python",
            Language::Matlab => "MATLAB",
        }
    }

    /// How many times the phases' time limits a file in this language is given: Octave
    /// runs the lab's loops of small matrices several times slower than QuickJS and
    /// NumPy (`BENCHMARKS.md`, "Students' files in MATLAB"), and a correct file must not
    /// be held to QuickJS's pace.
    pub fn time_factor(self) -> u32 {
        match self {
            Language::JavaScript | Language::Python => 1,
            Language::Matlab => 4,
        }
    }

    /// The extension of its files, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Language::JavaScript => "js",
            Language::Python => "py",
            Language::Matlab => "m",
        }
    }

    /// The language of a file, by its extension.
    pub fn of_file(name: &str) -> Option<Language> {
        let (_, extension) = name.rsplit_once('.')?;
        Language::ALL
            .iter()
            .copied()
            .find(|language| language.extension().eq_ignore_ascii_case(extension))
    }

    /// A student's file of an exercise in this language: `ekf_localization.py` for the
    /// exercise's `ekf_localization.js`.
    pub fn file_name(self, exercise_file: &str) -> String {
        let stem = exercise_file
            .rsplit_once('.')
            .map_or(exercise_file, |(stem, _)| stem);
        format!("{stem}.{}", self.extension())
    }
}

impl fmt::Display for Language {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no language's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown language {given:?}; the languages graded here: {}", known())]
pub struct UnknownLanguage {
    pub given: String,
}

fn known() -> String {
    let names: Vec<&str> = Language::ALL.iter().map(|l| l.name()).collect();
    names.join(", ")
}

impl FromStr for Language {
    type Err = UnknownLanguage;

    fn from_str(name: &str) -> Result<Language, UnknownLanguage> {
        Language::ALL
            .iter()
            .copied()
            .find(|language| language.name() == name)
            .ok_or_else(|| UnknownLanguage {
                given: name.to_owned(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_files_tell_their_language() {
        for &language in Language::ALL {
            assert_eq!(language.name().parse(), Ok(language));
            assert_eq!(
                serde_json::to_value(language).unwrap(),
                serde_json::json!(language.name())
            );
            let file = language.file_name("ekf_localization.js");
            assert_eq!(Language::of_file(&file), Some(language));
        }
        assert_eq!(Language::Python.file_name("odometry.js"), "odometry.py");
        assert_eq!(Language::of_file("odometry.m"), Some(Language::Matlab));
        assert_eq!(Language::of_file("odometry.mat"), None);
        assert_eq!(Language::of_file("Makefile"), None);
        assert_eq!(
            "octave".parse::<Language>().unwrap_err().to_string(),
            "unknown language \"octave\"; the languages graded here: javascript, python, matlab"
        );
    }
}
