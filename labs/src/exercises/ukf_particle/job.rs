//! What the harness's loop gets for one run (which filter, the step's length, the control
//! noise, the camera's residuals to learn its noise from, where the filter starts, the
//! commands and readings of every step and, for the particle filter, every random number
//! it draws) and what it records.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// Which filter a run strings the student's functions into.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "kebab-case")]
#[ts(rename = "UkfParticleFilter")]
pub enum RunFilter {
    Ukf,
    Particle,
}

/// A reading of a post: `z` = [range, bearing], and where the post stands.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, TS)]
#[ts(rename = "UkfParticleReading")]
pub struct PostReading {
    pub z: [f64; 2],
    pub landmark: [f64; 2],
}

/// One step of a run as the loop gets it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[ts(rename = "UkfParticleStep")]
pub struct FilterStepData {
    /// The command over the step, [v, omega].
    pub u: [f64; 2],
    pub readings: Vec<PostReading>,
    /// The particle filter's normal draws for the step, [n_v, n_omega] a particle; null
    /// where the robot stands still (the cloud does not move) and in the UKF's runs.
    pub normals: Option<Vec<[f64; 2]>>,
    /// The particle filter's offset of the comb, uniform in [0, 1), for the step's
    /// resampling if it resamples; null in the UKF's runs.
    pub r: Option<f64>,
}

/// One run of the loop with the student's functions. The loop first learns the camera's
/// noise, `Q = measurement_noise(residuals)`, and the control noise's, `alphas =
/// learn_alphas(commanded, implied)`, then from the start, at every step after the first:
///
/// the UKF: R = process_noise(mu, u, dt, alphas); {mu_bar, sigma_bar} =
/// ukf_predict(mu, sigma, u, dt, R); for each reading, {mu, sigma, d2} = ukf_update(...,
/// z, landmark, Q), kept when d2 <= gate;
///
/// the particle filter: particles = sample_motion(particles, u, dt, alphas, normals)
/// where the step has normals; weights = particle_weights(particles, weights, z,
/// landmark, Q) for each reading; after a reading, when needs_resampling(weights), the
/// particles at low_variance_resample(weights, r) with even weights; {mu, sigma} =
/// particle_estimate(particles, weights);
///
/// recording mu and sigma at the start and after every step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[ts(rename = "UkfParticleRun")]
pub struct FilterRun {
    pub filter: RunFilter,
    /// The length of a step, seconds.
    pub dt: f64,
    /// The commands over the run's span on the data's 50 Hz grid, [v, omega] each, and
    /// beside each the motion the ground truth implies.
    pub commanded: Vec<[f64; 2]>,
    pub implied: Vec<[f64; 2]>,
    /// The camera's residuals against the ground truth, [range, bearing] each.
    pub residuals: Vec<[f64; 2]>,
    /// The UKF's gate on d2 (chi2inv(0.999, 2)).
    pub gate: f64,
    pub start: [f64; 3],
    pub start_sigma: [[f64; 3]; 3],
    /// The particle filter's cloud at the start; null in the UKF's runs.
    pub particles: Option<Vec<[f64; 3]>>,
    pub steps: Vec<FilterStepData>,
}

/// What the loop records of a run: the noise it learned, and the belief at the start and
/// after every step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, TS)]
#[ts(rename = "UkfParticleRecord")]
pub struct FilterRecord {
    #[serde(default)]
    #[serde(rename = "Q")]
    pub q: Option<[[f64; 2]; 2]>,
    #[serde(default)]
    pub alphas: Option<[f64; 4]>,
    #[serde(default)]
    pub poses: Vec<[f64; 3]>,
    /// Sigma, as an array of rows.
    #[serde(default)]
    pub covariances: Vec<[[f64; 3]; 3]>,
}
