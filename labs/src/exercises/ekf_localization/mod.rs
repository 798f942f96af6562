//! EKF localization of a differential-drive robot (EL2320 Lab 1, part II): the student
//! contract (eight functions and `init`, `DESIGN.md`, "The student contract"), its case
//! generator and the original EL2320 fixtures, the hints for its classic mistakes, and
//! the data-set runs of the lab's filter loop held to the lab's bounds.

mod contract;
mod el2320;
mod generate;
mod grade;
mod hints;
mod job;
mod plan;

pub use contract::{Call, FUNCTIONS, Mat2, Mat2x3, Mat3, TwoRows, Vec2, Vec3};
pub use el2320::{FIXTURE_FILES, load_fixtures};
pub use generate::generate;
pub use grade::{grade, student_run};
pub use hints::HintKind;
pub use job::{FilterRecord, FilterRun, Mode, RobotJob, StepJob};
pub use plan::{Plan, RunSpec, bound, graded_readings, mode_name, run_name, shows_the_lesson};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;
