//! The student files the tests grade: the correct files, the starter, and the classic
//! mistakes of `tests/student/mistakes.json`, each made in correct.js; the odometry
//! exercise's in [`odometry`], the sensor-fusion exercise's in [`sensor_fusion`], those of
//! the exercise on the UKF and the particle filter in [`ukf_particle`], and what those
//! three are held to, graded as the server grades them, in [`catalogue`].

#![allow(dead_code)]

pub mod catalogue;
mod native;
pub mod odometry;
pub mod sensor_fusion;
pub mod ukf_particle;

#[allow(unused_imports)]
pub use native::{matlab, python};

use labs::exercises::Graded;
use serde::Deserialize;

pub const CORRECT: &str = include_str!("../../../../tests/student/correct.js");
pub const CORRECT_ALT: &str = include_str!("../../../../tests/student/correct-alt.js");
pub const STARTER: &str = labs::exercises::ekf_localization::EkfLocalization::DECLARATION
    .starters
    .javascript;
const MISTAKES: &str = include_str!("../../../../tests/student/mistakes.json");

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

/// Text of the correct file replaced by the mistake.
#[derive(Deserialize)]
pub struct Replacement {
    from: String,
    to: String,
}

/// `correct` with the mistake `name` made by `replace`, or which replaced text does not
/// occur in it exactly once.
pub fn made_in(correct: &str, name: &str, replace: &[Replacement]) -> Result<String, String> {
    replace.iter().try_fold(correct.to_owned(), |source, r| {
        match source.matches(&r.from).count() {
            1 => Ok(source.replace(&r.from, &r.to)),
            n => Err(format!(
                "{name}: {:?} occurs {n} times in the correct file, not once",
                r.from
            )),
        }
    })
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

    /// correct.js with the mistake made, or which replaced text does not occur in it
    /// exactly once.
    pub fn source(&self) -> Result<String, String> {
        made_in(CORRECT, &self.name, &self.replace)
    }
}
