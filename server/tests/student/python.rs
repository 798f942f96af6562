//! The student files in Python the tests grade: a correct file of each exercise and a
//! sample of its classic mistakes (`tests/student/python/mistakes/`), each made in the
//! correct file. The hints read outputs, not code, so the catalogue carries over whole;
//! the sample shows it does, mistake and hint alike, through the Python engine.

use super::catalogue::Files;
use labs::{Exercise, Language};

pub const EKF_LOCALIZATION: Files = Files {
    exercise: Exercise::EkfLocalization,
    language: Language::Python,
    functions: labs::exercises::ekf_localization::FUNCTIONS,
    runs: &["o3", "outliers", "no-odometry"],
    correct: include_str!("../../../tests/student/python/ekf_localization.py"),
    catalogue: (
        "tests/student/python/mistakes/ekf_localization.json",
        include_str!("../../../tests/student/python/mistakes/ekf_localization.json"),
    ),
};

pub const ODOMETRY: Files = Files {
    exercise: Exercise::Odometry,
    language: Language::Python,
    functions: labs::exercises::odometry::FUNCTIONS,
    runs: &["square", "figure-eight"],
    correct: include_str!("../../../tests/student/python/odometry.py"),
    catalogue: (
        "tests/student/python/mistakes/odometry.json",
        include_str!("../../../tests/student/python/mistakes/odometry.json"),
    ),
};

pub const SENSOR_FUSION: Files = Files {
    exercise: Exercise::SensorFusion,
    language: Language::Python,
    functions: labs::exercises::sensor_fusion::FUNCTIONS,
    runs: &["busy-room", "wide-tour"],
    correct: include_str!("../../../tests/student/python/sensor_fusion.py"),
    catalogue: (
        "tests/student/python/mistakes/sensor_fusion.json",
        include_str!("../../../tests/student/python/mistakes/sensor_fusion.json"),
    ),
};
