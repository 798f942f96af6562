//! The student files of the odometry exercise the tests grade: the correct file, and the
//! classic mistakes of `tests/student/odometry/mistakes.json`, each made in the correct
//! file. The square cannot tell which heading a step follows, nor the figure eight a wheel
//! rolling backwards; along a path a function that keeps the pose it returned, or a
//! covariance not symmetrised, gives what it should. On the spot (ds = 0) F_delta's
//! columns swapped and its last row's signs flipped are one answer, which gets no hint.

use super::catalogue::Files;
use labs::{Exercise, Language};

pub const CORRECT: &str = include_str!("../../../../tests/student/odometry/correct.js");

pub const FILES: Files = Files {
    exercise: Exercise::Odometry,
    language: Language::JavaScript,
    functions: labs::exercises::odometry::FUNCTIONS,
    runs: &["square", "figure-eight"],
    correct: CORRECT,
    catalogue: (
        "tests/student/odometry/mistakes.json",
        include_str!("../../../../tests/student/odometry/mistakes.json"),
    ),
};
