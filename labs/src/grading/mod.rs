//! Grading a student's implementation of the EKF localization exercise.
//!
//! A [`Plan`] made from the student's seed holds the test cases and the data sets; its
//! [`Plan::job`] goes to the JavaScript harness (`static/src/harness.js`), which calls
//! the student's code in a sandbox (a Web Worker in the browser, QuickJS in a worker
//! process on the server) and reports [`Outputs`]; [`grade`] turns those into a
//! [`GradeResult`]. The browser and the server run the same harness on the same job and
//! grade with this same code, so they reach the same verdict.

mod grade;
mod hints;
mod job;
mod outputs;
mod plan;
mod platforms;
mod result;

pub use grade::{LAB, POINTS, grade, student_run};
pub use hints::{Hint, HintKind};
pub use job::{CallJob, FunctionPhase, Job, Mode, Phase, PhaseKind, RobotJob, RunPhase, StepJob};
pub use outputs::{CallResult, FunctionOutput, Outputs, PhaseOutput, Reports, RunOutput, Stopped};
pub use plan::{FUNCTION_LIMIT_MS, Plan, PlannedCase, RunSpec, Suite, bound};
pub use platforms::{
    GraderData, GradescopeResults, GradescopeTest, HIDDEN_LATER, PrairieLearnResults,
    PrairieLearnTest,
};
pub use result::{Failure, GradeResult, RunFigures, Status, Test, Visibility};

/// The course a student's variant belongs to unless another is named.
pub const DEFAULT_COURSE: &str = "el2320";

/// The seed of a student's variant: the same for the same course and student, on every
/// machine (FNV-1a over both names), a whole number below 2^53 so JavaScript holds it.
pub fn student_seed(course: &str, student: &str) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in course.bytes().chain([0]).chain(student.trim().bytes()) {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash & ((1 << 53) - 1)
}
