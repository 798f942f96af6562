//! The student files in other languages than JavaScript that the tests grade: a correct
//! file of each exercise and a sample of its classic mistakes
//! (`tests/student/LANGUAGE/mistakes/`), each made in the correct file. The hints read
//! outputs, not code, so the catalogue carries over whole; the sample shows it does,
//! mistake and hint alike, through each language's interpreter.

/// The files of one language, in `tests/student/$folder/`, as a module of four
/// [`Files`](super::catalogue::Files).
macro_rules! files_in {
    ($module:ident, $language:expr, $folder:literal, $extension:literal) => {
        pub mod $module {
            use super::super::catalogue::Files;
            use labs::{Exercise, Language};

            const LANGUAGE: Language = $language;

            pub const EKF_LOCALIZATION: Files = Files {
                exercise: Exercise::EkfLocalization,
                language: LANGUAGE,
                functions: labs::exercises::ekf_localization::FUNCTIONS,
                runs: &["o3", "outliers", "no-odometry"],
                correct: include_str!(concat!(
                    "../../../../tests/student/",
                    $folder,
                    "/ekf_localization.",
                    $extension
                )),
                catalogue: (
                    concat!("tests/student/", $folder, "/mistakes/ekf_localization.json"),
                    include_str!(concat!(
                        "../../../../tests/student/",
                        $folder,
                        "/mistakes/ekf_localization.json"
                    )),
                ),
            };

            pub const ODOMETRY: Files = Files {
                exercise: Exercise::Odometry,
                language: LANGUAGE,
                functions: labs::exercises::odometry::FUNCTIONS,
                runs: &["square", "figure-eight"],
                correct: include_str!(concat!(
                    "../../../../tests/student/",
                    $folder,
                    "/odometry.",
                    $extension
                )),
                catalogue: (
                    concat!("tests/student/", $folder, "/mistakes/odometry.json"),
                    include_str!(concat!(
                        "../../../../tests/student/",
                        $folder,
                        "/mistakes/odometry.json"
                    )),
                ),
            };

            pub const SENSOR_FUSION: Files = Files {
                exercise: Exercise::SensorFusion,
                language: LANGUAGE,
                functions: labs::exercises::sensor_fusion::FUNCTIONS,
                runs: &["busy-room", "wide-tour"],
                correct: include_str!(concat!(
                    "../../../../tests/student/",
                    $folder,
                    "/sensor_fusion.",
                    $extension
                )),
                catalogue: (
                    concat!("tests/student/", $folder, "/mistakes/sensor_fusion.json"),
                    include_str!(concat!(
                        "../../../../tests/student/",
                        $folder,
                        "/mistakes/sensor_fusion.json"
                    )),
                ),
            };

            pub const UKF_PARTICLE: Files = Files {
                exercise: Exercise::UkfParticle,
                language: LANGUAGE,
                functions: labs::exercises::ukf_particle::FUNCTIONS,
                runs: &["ukf", "particle-filter"],
                correct: include_str!(concat!(
                    "../../../../tests/student/",
                    $folder,
                    "/ukf_particle.",
                    $extension
                )),
                catalogue: (
                    concat!("tests/student/", $folder, "/mistakes/ukf_particle.json"),
                    include_str!(concat!(
                        "../../../../tests/student/",
                        $folder,
                        "/mistakes/ukf_particle.json"
                    )),
                ),
            };
        }
    };
}

files_in!(python, Language::Python, "python", "py");
files_in!(matlab, Language::Matlab, "matlab", "m");
