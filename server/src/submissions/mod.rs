//! Submissions: stored first (see `store`), then graded in the sandbox, one worker
//! process each, a bounded number at a time and students taking turns (`fair`); the
//! result is stored and shown to the student.

mod fair;
mod priority;
mod queue;
mod secret;

pub use fair::{Lane, Policy, Tenant, Waiting, Work};
pub use queue::Grader;
pub use secret::{Secret, grader_version};
