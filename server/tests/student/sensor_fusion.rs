//! The student files of the sensor-fusion exercise the tests grade: the correct file, and
//! the classic mistakes of `tests/student/sensor_fusion/mistakes.json`, each made in the
//! correct file. A mistake that only a reading across +-pi, a pose exactly on the edge of
//! the field of view or a function that keeps state between separate calls shows leaves
//! the trials as the reference runs them; heading_sigma is not called along a trial.

use super::catalogue::Files;
use labs::Exercise;

pub const CORRECT: &str = include_str!("../../../tests/student/sensor_fusion/correct.js");

pub const FILES: Files = Files {
    exercise: Exercise::SensorFusion,
    functions: labs::exercises::sensor_fusion::FUNCTIONS,
    runs: &["busy-room", "wide-tour"],
    correct: CORRECT,
    catalogue: (
        "tests/student/sensor_fusion/mistakes.json",
        include_str!("../../../tests/student/sensor_fusion/mistakes.json"),
    ),
};
