//! The student files of the exercise on the UKF and the particle filter the tests grade:
//! the correct file, and the classic mistakes of `tests/student/ukf_particle/mistakes.json`,
//! each made in the correct file. A mistake in a function the correct file calls from
//! another (the arc from the UKF's prediction, the sigma points from its prediction and
//! update) fails those too (its `also`). A heading not wrapped after the arc leaves the
//! filters as they were (their means are atan2s, their deviations wrapped); angles
//! averaged as numbers and residuals not wrapped break a run only where the drawn robot
//! meets +-pi, and the arc's division by zero the particle filter only where a draw of
//! omega is exactly 0: those runs are the mistakes' `by_chance`.

use super::catalogue::Files;
use labs::{Exercise, Language};

pub const CORRECT: &str = include_str!("../../../../tests/student/ukf_particle/correct.js");

pub const FILES: Files = Files {
    exercise: Exercise::UkfParticle,
    language: Language::JavaScript,
    functions: labs::exercises::ukf_particle::FUNCTIONS,
    runs: &["ukf", "particle-filter"],
    correct: CORRECT,
    catalogue: (
        "tests/student/ukf_particle/mistakes.json",
        include_str!("../../../../tests/student/ukf_particle/mistakes.json"),
    ),
};
