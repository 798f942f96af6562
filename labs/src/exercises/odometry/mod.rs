//! Odometry and how its error grows: the student contract (five functions: one step of
//! odometry, its two Jacobians, the wheels' noise and one step of covariance propagation;
//! `static/src/odometry/starter.js`), its case generator, the hints for its classic
//! mistakes, and the runs of the harness's path loop, held to the reference's poses and
//! covariances along a square and a figure eight. The reference answers all come from
//! the model in [`crate::odometry`].

mod contract;
mod generate;
mod grade;
mod hints;
mod job;
mod plan;

pub use contract::{Call, FUNCTIONS, Mat2, Mat3, Mat3x2, Vec3};
pub use generate::generate;
pub use grade::{COVARIANCE_TOLERANCE, POSE_TOLERANCE, grade};
pub use hints::HintKind;
pub use job::{PathRecord, PathRun};
pub use plan::{PATH_FUNCTIONS, PathSpec, Plan, RUN_LIMIT_MS};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;
