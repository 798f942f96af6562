//! Fusing wheel odometry with an indoor positioning sensor: the reference model of the
//! exercise on the Northstar report.
//!
//! A detector on the ceiling sees two infrared platforms on the robot and reports where
//! they are and how bright ([`sensor`]); the robot's pose follows from the two, its noise
//! from their intensities. Wheel odometry drifts without bound; the sensor does not drift
//! but is noisy, skews towards the edge of its field of view and reports nothing or
//! garbage beyond it. A Kalman filter ([`filter`]) predicts with the odometry's increments
//! and corrects with the sensor where it can be trusted: inside the field of view and
//! inside the Mahalanobis gate.
//!
//! Trials ([`trial`]) are the report's two (read from its files, never shipped) or made
//! from a seed ([`simulate`]); [`metrics`] says how good an estimate is and what tuning
//! the process noise on one trial does on another.
//!
//! As everywhere in `labs`: R is the process noise and Q the measurement noise (the
//! report writes them the other way round); every transcendental function is `libm`'s,
//! so the browser gets the command line's numbers bit for bit.

pub mod filter;
pub mod metrics;
pub mod sensor;
pub mod simulate;
pub mod trial;

pub use filter::{Estimate, Settings, Use, inside_three_sigma, run};
pub use metrics::{Errors, REPORT_FIGURES, ReportFigures, Summary, tune};
pub use sensor::{Detector, Measurement, NoiseModel, Platform};
pub use simulate::{TrialParams, generate};
pub use trial::{Reading, Step, Trial};
