//! Grading the stored submissions: the grading queue (`queue`, the grader), students
//! taking turns (`fair`, `priority`), what an operator watches of it (`metrics`) and the
//! server's secret that draws each submission's hidden cases (`secret`). A submission is stored first (see `store`), then graded in
//! the sandbox, one worker process each, a bounded number at a time; the result is stored
//! and shown to the student.

mod asked;
mod fair;
mod metrics;
mod priority;
mod queue;
mod secret;

pub use asked::{Busy, PhaseAsked};
pub use fair::{Lane, Policy, Tenant, Waiting, Work};
pub use queue::Grader;
pub use secret::{Secret, grader_version};
