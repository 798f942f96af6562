//! What the harness's fusion loop gets for one run (the filter's settings, where it
//! starts, the odometry and the platforms' readings of every step) and what it records.

use crate::grading;
use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// The settings of the filter a run uses: those of the plan, or over the class's held-out
/// trials those the student's `tuning()` returns, in the same shape. An infinite number
/// is the string "Infinity" in JSON, which the loop reads back as a number.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct FilterSettings {
    pub k_xy: f64,
    pub k_theta: f64,
    pub c_xy: f64,
    /// The radius of the field of view (infinite: every reading is in view).
    #[serde(with = "grading::infinity")]
    #[ts(type = "number")]
    pub field_of_view: f64,
    /// The gate on the squared Mahalanobis distance (infinite: no gate).
    #[serde(with = "grading::infinity")]
    #[ts(type = "number")]
    pub lambda: f64,
}

/// One step of a trial as the loop gets it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct TrialStepData {
    /// The odometry's own pose, [x, y, theta].
    pub odom: [f64; 3],
    /// The two platforms' readings, [x, y, I] each, front one first; null when the
    /// detector read nothing.
    pub platforms: Option<[[f64; 3]; 2]>,
}

/// One run of the fusion loop with the student's functions: with `settings`, or when the
/// run has none (the class's held-out trials) those `tuning()` returns, and from
/// `mu = start` and `sigma = start_sigma`, at every step
///
/// (after the first) {mu_bar, sigma_bar} = predict(mu, sigma, odom_prev, odom, k_xy, k_theta);
/// where the step has a reading: z = combine_platforms(p1, p2), and when
/// in_field_of_view(z, field_of_view): Q = measurement_noise(p1, p2, c_xy), and when
/// mahalanobis(mu_bar, sigma_bar, z, Q) <= lambda: {mu, sigma} = update(mu_bar, sigma_bar, z, Q),
///
/// recording mu and sigma after the step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
pub struct TrialRun {
    pub start: [f64; 3],
    pub start_sigma: [[f64; 3]; 3],
    pub settings: Option<FilterSettings>,
    pub steps: Vec<TrialStepData>,
}

/// What the fusion loop records of a run: the belief after every step, and the settings
/// `tuning()` returned when the run asked for them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, TS)]
pub struct TrialRecord {
    #[serde(default)]
    pub tuning: Option<FilterSettings>,
    #[serde(default)]
    pub poses: Vec<[f64; 3]>,
    /// Sigma, as an array of rows.
    #[serde(default)]
    pub covariances: Vec<[[f64; 3]; 3]>,
}
