//! Submissions: stored first (see `store`), then graded in the sandbox, one worker
//! process each, a bounded number at a time; the result is stored and shown to the
//! student.

mod queue;
mod secret;

pub use queue::Grader;
pub use secret::{Secret, grader_version};
