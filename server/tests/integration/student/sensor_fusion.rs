//! The student files of the sensor-fusion exercise the tests grade: the correct file, and
//! the classic mistakes of `tests/student/sensor_fusion/mistakes.json`, each made in the
//! correct file. heading_sigma is not called along a trial, and a pose exactly on the edge
//! of the field of view, a heading out of [-pi, pi) (a trial compares headings modulo
//! 2 pi) or a predict that keeps the odometry it was last given (along a trial that is
//! odom_prev) leave the trials as the reference runs them. An innovation not wrapped
//! breaks a trial only where a reading meets the prediction across +-pi, the square field
//! of view only where the robot is read in a corner of the square around it, and the
//! gate's distance not squared the wide tour only where it meets an outlier: those runs
//! are the mistakes' `by_chance`.

use super::catalogue::Files;
use labs::{Exercise, Language};

pub const CORRECT: &str = include_str!("../../../../tests/student/sensor_fusion/correct.js");

pub const FILES: Files = Files {
    exercise: Exercise::SensorFusion,
    language: Language::JavaScript,
    functions: labs::exercises::sensor_fusion::FUNCTIONS,
    runs: &["busy-room", "wide-tour"],
    correct: CORRECT,
    catalogue: (
        "tests/student/sensor_fusion/mistakes.json",
        include_str!("../../../../tests/student/sensor_fusion/mistakes.json"),
    ),
};
