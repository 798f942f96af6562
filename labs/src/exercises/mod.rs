//! Each graded exercise in a folder of its own: its student contract, its case generator,
//! its runs of the exercise's loop, its hints and its grading. What every exercise shares
//! is in [`crate::grading`]; `DESIGN.md`, "Adding an exercise", says how to add one.

pub mod ekf_localization;
pub mod odometry;
