//! The graded exercises, one folder each, and their registry: the one list of them.
//!
//! An exercise's folder holds the whole exercise: its student contract, its case
//! generator, its plan (the cases and the runs of its loop), its hints and its grading in
//! Rust; its starter file, the harness's loop for its runs and the workbench's view of a
//! run in JavaScript (`web/`); its texts (its [`Declaration`]); and its contract as prose
//! (`README.md`). What every exercise shares is in [`crate::grading`], which names none
//! of them. Everything that lists exercises (the [`Exercise`] enum, the pages, the wasm
//! grader, the server's sandbox, the platforms, the command line) reads this registry;
//! `DESIGN.md`, "Adding an exercise", says how to add one.

mod declaration;
pub mod interface;
pub mod starter;

pub use declaration::{Declaration, Graded, ReportRun, Runs, Starters, Visit, Workbench};

use crate::grading::{Contract, Shape};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;
use std::str::FromStr;

pub mod ekf_localization;
pub mod odometry;
pub mod sensor_fusion;
pub mod ukf_particle;

/// The registry: every graded exercise (a module above) as its variant of [`Exercise`]
/// and the type that declares it ([`Graded`]). The first is the default of the command
/// line.
macro_rules! registry {
    ($($(#[$doc:meta])* $variant:ident => $module:ident :: $graded:ident,)+) => {
        /// A graded exercise.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Exercise {
            $($(#[$doc])* $variant,)+
        }

        impl Exercise {
            /// Every graded exercise, in the registry's order.
            pub const ALL: &'static [Exercise] = &[$(Exercise::$variant),+];

            /// The exercise's folder under `labs/src/exercises/` (its module), by which
            /// the asset build knows its scripts.
            pub fn folder(self) -> &'static str {
                match self {
                    $(Exercise::$variant => stringify!($module),)+
                }
            }

            /// Calls `visitor` with the exercise's [`Graded`] type.
            pub fn visit<V: Visit>(self, visitor: V) -> V::Output {
                match self {
                    $(Exercise::$variant => visitor.visit::<$module::$graded>(),)+
                }
            }
        }
    };
}

registry! {
    /// EKF localization of a differential-drive robot (EL2320 Lab 1, part II).
    EkfLocalization => ekf_localization::EkfLocalization,
    /// Odometry of a differential-drive robot and how its error grows: one step, its
    /// Jacobians, the wheels' noise and the propagation of the pose's covariance.
    Odometry => odometry::Odometry,
    /// Fusing wheel odometry with an indoor positioning sensor (Northstar): the pose from
    /// two platforms, its noise, the field of view, prediction, gate and update.
    SensorFusion => sensor_fusion::SensorFusion,
    /// The unscented Kalman filter and the particle filter on MRCLAM-like data: the arc,
    /// sigma points, unscented prediction and update, the particles' motion, weights,
    /// low-variance resampling and estimate, and the camera's noise learned.
    UkfParticle => ukf_particle::UkfParticle,
}

impl Default for Exercise {
    fn default() -> Exercise {
        Exercise::ALL[0]
    }
}

/// The declaration of an exercise, read from its [`Graded`] type.
struct Declared;

impl Visit for Declared {
    type Output = &'static Declaration;
    fn visit<G: Graded>(self) -> &'static Declaration {
        &G::DECLARATION
    }
}

/// An exercise's generated test cases, as JSON.
struct Generated {
    seed: u64,
    per_function: usize,
}

impl Visit for Generated {
    type Output = String;
    fn visit<G: Graded>(self) -> String {
        let cases = (G::GENERATE)(self.seed, self.per_function);
        serde_json::to_string(&cases).expect("cases serialise")
    }
}

/// The named fields of each student function's output, where the contract's output is an
/// object of named fields.
struct OutputFields;

impl Visit for OutputFields {
    type Output = BTreeMap<&'static str, Vec<&'static str>>;
    fn visit<G: Graded>(self) -> Self::Output {
        (G::GENERATE)(0, 1)
            .iter()
            .filter_map(|case| match case.call.output_shape() {
                (_, Shape::Object(fields)) => Some((
                    case.call.function(),
                    fields.iter().map(|&(name, _)| name).collect(),
                )),
                _ => None,
            })
            .collect()
    }
}

/// The student functions of an exercise's contract.
struct Functions;

impl Visit for Functions {
    type Output = &'static [&'static str];
    fn visit<G: Graded>(self) -> Self::Output {
        G::Call::FUNCTIONS
    }
}

impl Exercise {
    /// The student functions its contract's cases call, in the order it introduces them.
    pub fn functions(self) -> &'static [&'static str] {
        self.visit(Functions)
    }

    /// The fields of the outputs of the student functions that return named fields (as
    /// `predict` returns `mu_bar` and `sigma_bar`), in the contract's order: how a
    /// language whose functions return several values in a tuple names them.
    pub fn output_fields(self) -> BTreeMap<&'static str, Vec<&'static str>> {
        self.visit(OutputFields)
    }

    /// `per_function` generated test cases of every student function of the variant
    /// `seed`, as a JSON array.
    pub fn generated_cases(self, seed: u64, per_function: usize) -> String {
        self.visit(Generated { seed, per_function })
    }

    /// What the exercise declares of itself: its name, title, file and texts.
    pub fn declaration(self) -> &'static Declaration {
        self.visit(Declared)
    }

    /// The name the API, the command line, the store and the packages use.
    pub fn name(self) -> &'static str {
        self.declaration().name
    }

    /// What a person calls it: "EKF localization".
    pub fn title(self) -> &'static str {
        self.declaration().title
    }

    /// The student's file, as the workbench downloads it and the platforms' packages
    /// look for it: `ekf_localization.js`.
    pub fn file_name(self) -> &'static str {
        self.declaration().file_name
    }

    /// Every exercise's name, for a message or a command line's choices.
    pub fn names() -> Vec<&'static str> {
        Exercise::ALL.iter().map(|e| e.name()).collect()
    }
}

impl fmt::Display for Exercise {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no exercise's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown exercise {given:?}; the exercises graded here: {}", Exercise::names().join(", "))]
pub struct UnknownExercise {
    pub given: String,
}

impl FromStr for Exercise {
    type Err = UnknownExercise;

    fn from_str(name: &str) -> Result<Exercise, UnknownExercise> {
        Exercise::ALL
            .iter()
            .copied()
            .find(|e| e.name() == name)
            .ok_or_else(|| UnknownExercise {
                given: name.to_owned(),
            })
    }
}

impl Serialize for Exercise {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Exercise {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Exercise, D::Error> {
        let name = String::deserialize(deserializer)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn names_round_trip_and_an_unknown_one_lists_the_known() {
        for &exercise in Exercise::ALL {
            assert_eq!(exercise.name().parse(), Ok(exercise));
            assert_eq!(
                serde_json::to_value(exercise).unwrap(),
                serde_json::json!(exercise.name())
            );
        }
        let unknown = "kidnapped-robot".parse::<Exercise>().unwrap_err();
        assert_eq!(
            unknown.to_string(),
            "unknown exercise \"kidnapped-robot\"; the exercises graded here: ekf-localization, odometry, sensor-fusion, ukf-particle"
        );
    }

    /// What tells exercises apart in a URL, a file and the harness is each one's own.
    #[test]
    fn every_exercise_declares_names_of_its_own() {
        let mut seen = BTreeSet::new();
        for &exercise in Exercise::ALL {
            let d = exercise.declaration();
            for name in [d.name, d.file_name, d.run_loop, d.workbench.path] {
                assert!(seen.insert(name), "{name} declared twice");
            }
            assert!(d.workbench.path.starts_with('/'), "{}", d.workbench.path);
            assert!(d.file_name.ends_with(".js"), "{}", d.file_name);
            for text in [d.title, d.runs.noun, d.starter_template, d.harness_loop] {
                assert!(!text.trim().is_empty(), "{}: an empty text", d.name);
            }
        }
    }
}
