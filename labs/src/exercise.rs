//! The exercises estlab grades, by the name the API, the command line, the store and the
//! packages use for them.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// A graded exercise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Exercise {
    /// EKF localization of a differential-drive robot (EL2320 Lab 1, part II).
    #[default]
    #[serde(rename = "ekf-localization")]
    EkfLocalization,
    /// Odometry of a differential-drive robot and how its error grows: one step, its
    /// Jacobians, the wheels' noise and the propagation of the pose's covariance.
    #[serde(rename = "odometry")]
    Odometry,
}

impl Exercise {
    /// Every graded exercise.
    pub const ALL: [Exercise; 2] = [Exercise::EkfLocalization, Exercise::Odometry];

    pub const fn name(self) -> &'static str {
        match self {
            Exercise::EkfLocalization => "ekf-localization",
            Exercise::Odometry => "odometry",
        }
    }

    /// What a person calls it: "EKF localization".
    pub const fn title(self) -> &'static str {
        match self {
            Exercise::EkfLocalization => "EKF localization",
            Exercise::Odometry => "Odometry and its error propagation",
        }
    }

    /// The student's file, as the workbench downloads it and the platforms' packages
    /// look for it: `ekf_localization.js`.
    pub const fn file_name(self) -> &'static str {
        match self {
            Exercise::EkfLocalization => "ekf_localization.js",
            Exercise::Odometry => "odometry.js",
        }
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
            .into_iter()
            .find(|e| e.name() == name)
            .ok_or_else(|| UnknownExercise {
                given: name.to_owned(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_an_unknown_one_lists_the_known() {
        for exercise in Exercise::ALL {
            assert_eq!(exercise.name().parse(), Ok(exercise));
            assert_eq!(
                serde_json::to_value(exercise).unwrap(),
                serde_json::json!(exercise.name())
            );
        }
        let unknown = "particle-filter".parse::<Exercise>().unwrap_err();
        assert_eq!(
            unknown.to_string(),
            "unknown exercise \"particle-filter\"; the exercises graded here: ekf-localization, odometry"
        );
    }
}
