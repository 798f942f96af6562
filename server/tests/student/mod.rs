//! The student files the tests grade: the correct files, the starter, and the classic
//! mistakes of `tests/student/mistakes.json`, each made in correct.js.

#![allow(dead_code)]

use serde::Deserialize;

pub const CORRECT: &str = include_str!("../../../tests/student/correct.js");
pub const CORRECT_ALT: &str = include_str!("../../../tests/student/correct-alt.js");
pub const STARTER: &str = include_str!("../../../static/src/ekf/starter.js");
const MISTAKES: &str = include_str!("../../../tests/student/mistakes.json");

/// A classic mistake: correct.js with some lines replaced.
#[derive(Deserialize)]
pub struct Mistake {
    pub name: String,
    /// The function it breaks.
    pub breaks: String,
    /// For a mistake in `init`: the data sets whose runs it breaks (all when absent).
    #[serde(default)]
    pub datasets: Option<Vec<String>>,
    /// The hint it must get.
    pub hint: String,
    replace: Vec<Replacement>,
}

#[derive(Deserialize)]
struct Replacement {
    from: String,
    to: String,
}

impl Mistake {
    pub fn all() -> Vec<Mistake> {
        serde_json::from_str(MISTAKES).expect("tests/student/mistakes.json")
    }

    pub fn named(name: &str) -> Mistake {
        Mistake::all()
            .into_iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("no mistake {name} in tests/student/mistakes.json"))
    }

    /// correct.js with the mistake made, or which replaced text it does not contain.
    pub fn source(&self) -> Result<String, String> {
        self.replace
            .iter()
            .try_fold(CORRECT.to_owned(), |source, r| {
                if source.contains(&r.from) {
                    Ok(source.replace(&r.from, &r.to))
                } else {
                    Err(format!(
                        "{}: {:?} does not occur in correct.js",
                        self.name, r.from
                    ))
                }
            })
    }
}
