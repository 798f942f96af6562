//! The reference filters of estlab and everything an exercise is made of.
//!
//! Pure computation: no I/O beyond parsing and writing text, no clock, no network. The
//! crate builds natively and for `wasm32-unknown-unknown`, and every transcendental
//! function goes through [`libm`] (square roots are exact in IEEE 754 anyway), so a seed
//! gives bit-identical numbers on both.
//!
//! Notation follows Probabilistic Robotics, as the EL2320 lab does: state `mu`,
//! covariance `Sigma`, control `u`, measurement `z`; **R is the process noise covariance
//! and Q the measurement noise covariance**.

pub mod angle;
pub mod car;
pub mod dataset;
pub mod ekf;
mod error;
pub mod exercises;
pub mod fusion;
pub mod grading;
mod language;
pub mod mrclam;
pub mod odometry;
pub mod rng;
mod text;
mod typescript;

pub use error::Error;
pub use exercises::{Exercise, UnknownExercise};
pub use language::{Language, UnknownLanguage};
