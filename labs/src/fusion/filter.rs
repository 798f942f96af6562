//! The fusion filter: odometry predicts, the indoor positioning sensor corrects.
//!
//! The state is the pose `mu = (x, y, theta)` with covariance `Sigma`.
//!
//! **Prediction from odometry increments** ([`predict`]). The odometry's own pose
//! drifts, but its motion from one step to the next is good: the increment, in the frame
//! of the robot at the previous step,
//!
//! ```text
//! (dx, dy) = Rot(-theta_o,k-1) (p_o,k - p_o,k-1),   dtheta = wrap(theta_o,k - theta_o,k-1)
//! ```
//!
//! is applied to the filtered pose: `(x, y) += Rot(theta) (dx, dy)`, `theta += dtheta`.
//! Taking the odometry's pose itself as the prediction would throw every correction away
//! at the next step: the estimate would snap back onto the odometry's drifting path, and
//! the filter could never be better than the sensor alone.
//!
//! Its Jacobian `G = d mu' / d mu` is the identity but for the third column,
//! `(-sin theta dx - cos theta dy, cos theta dx - sin theta dy, 1)`, and the process
//! noise grows with the motion: `R = diag((k_xy s)^2, (k_xy s)^2, (k_theta (s +
//! |dtheta|))^2)`, `s = |(dx, dy)|`, so a robot standing still gains no uncertainty:
//! `Sigma' = G Sigma G' + R`.
//!
//! **Update** ([`update`]). The sensor measures the whole pose, `H = I`, with
//! `Q = diag(sigma_xy^2, sigma_xy^2, sigma_theta^2)` from the noise model; a reading
//! outside the field of view has `Q = infinity` and so no weight: the filter runs on
//! odometry alone. The innovation `nu = z - mu` has its heading wrapped, `S = Sigma + Q`,
//! and a reading whose Mahalanobis distance `nu' S^-1 nu` exceeds the gate (the chi-square
//! quantile of 3 degrees of freedom at the gate's probability) is rejected. Otherwise
//! `K = Sigma S^-1`, `mu += K nu`, `Sigma = (I - K) Sigma`, symmetrised.
//!
//! Letters: estlab writes R for the process noise and Q for the measurement noise, as the
//! lab and Probabilistic Robotics do. The Northstar report, like many lectures, uses them
//! the other way round.

use super::sensor::{Detector, Measurement, NoiseModel};
use super::trial::{Reading, Step, Trial};
use crate::Error;
use crate::angle::wrap;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// Everything the filter depends on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "FusionSettings")]
#[serde(default)]
pub struct Settings {
    /// `k_xy`: the standard deviation of the position per metre moved.
    pub process_xy: f64,
    /// `k_theta`: the standard deviation of the heading per metre moved and radian turned.
    pub process_theta: f64,
    pub noise: NoiseModel,
    /// Readings farther than this from the point under the detector are ignored, metres.
    pub field_of_view: f64,
    /// The gate's probability: a reading is rejected when its Mahalanobis distance is
    /// beyond the chi-square quantile of 3 degrees of freedom at it; 1 rejects none.
    pub gate: f64,
    /// The standard deviations of the start: x, y, theta.
    pub start_sigma: [f64; 3],
}

impl Default for Settings {
    /// Round settings: 5 cm per metre, 0.05 rad per metre or radian, the noise model's
    /// constants, the report's field of view, a gate at 99.9 %.
    fn default() -> Self {
        Settings {
            process_xy: 0.05,
            process_theta: 0.05,
            noise: NoiseModel::default(),
            field_of_view: 2.0,
            gate: 0.999,
            start_sigma: [0.01, 0.01, 0.01],
        }
    }
}

impl Settings {
    /// Checks every setting, naming the first that is out of its domain.
    pub fn validate(&self) -> Result<(), Error> {
        for (field, value) in [
            ("process_xy", self.process_xy),
            ("process_theta", self.process_theta),
        ] {
            if !(value.is_finite() && (0.0..=10.0).contains(&value)) {
                return Err(Error::invalid(field, "must be a number in [0, 10]"));
            }
        }
        self.noise.validate()?;
        if !(self.field_of_view.is_finite() && (0.0..=100.0).contains(&self.field_of_view)) {
            return Err(Error::invalid(
                "field_of_view",
                "must be a number of metres in [0, 100]",
            ));
        }
        if !(self.gate > 0.0 && self.gate <= 1.0) {
            return Err(Error::invalid("gate", "must be a probability in (0, 1]"));
        }
        if !self
            .start_sigma
            .iter()
            .all(|s| s.is_finite() && (1e-6..=100.0).contains(s))
        {
            return Err(Error::invalid("start_sigma", "each must be in [1e-6, 100]"));
        }
        Ok(())
    }

    /// The gate on the Mahalanobis distance: `chi2inv(gate, 3)`, infinite at 1.
    pub fn gate_threshold(&self) -> f64 {
        chi2inv_3(self.gate)
    }
}

/// The distribution function of the chi-square distribution with 3 degrees of freedom,
/// `F(x) = erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2)`: the gate's probability of a threshold.
pub fn chi2cdf_3(x: f64) -> f64 {
    if x == f64::INFINITY {
        return 1.0;
    }
    libm::erf((x / 2.0).sqrt()) - (2.0 * x / std::f64::consts::PI).sqrt() * libm::exp(-x / 2.0)
}

/// The quantile of the chi-square distribution with 3 degrees of freedom, by bisection of
/// its distribution function [`chi2cdf_3`].
pub fn chi2inv_3(p: f64) -> f64 {
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let cdf = chi2cdf_3;
    let (mut low, mut high) = (0.0, 1.0);
    while cdf(high) < p {
        high *= 2.0;
    }
    for _ in 0..200 {
        let mid = (low + high) / 2.0;
        if mid == low || mid == high {
            break;
        }
        if cdf(mid) < p { low = mid } else { high = mid }
    }
    high
}

/// The odometry's motion from `before` to `after`, in the robot's frame at `before`:
/// `[dx, dy, dtheta]`.
pub fn increment(before: [f64; 3], after: [f64; 3]) -> Vector3<f64> {
    let (sin, cos) = libm::sincos(before[2]);
    let (gx, gy) = (after[0] - before[0], after[1] - before[1]);
    Vector3::new(
        cos * gx + sin * gy,
        -sin * gx + cos * gy,
        wrap(after[2] - before[2]),
    )
}

/// One prediction from an odometry increment (module documentation).
pub fn predict(
    mu: &Vector3<f64>,
    sigma: &Matrix3<f64>,
    increment: &Vector3<f64>,
    settings: &Settings,
) -> (Vector3<f64>, Matrix3<f64>) {
    let (sin, cos) = libm::sincos(mu.z);
    let (dx, dy, dtheta) = (increment.x, increment.y, increment.z);
    let predicted = Vector3::new(
        mu.x + cos * dx - sin * dy,
        mu.y + sin * dx + cos * dy,
        wrap(mu.z + dtheta),
    );
    let mut g = Matrix3::identity();
    g[(0, 2)] = -sin * dx - cos * dy;
    g[(1, 2)] = cos * dx - sin * dy;
    let moved = libm::hypot(dx, dy);
    let r = Matrix3::from_diagonal(&Vector3::new(
        (settings.process_xy * moved).powi(2),
        (settings.process_xy * moved).powi(2),
        (settings.process_theta * (moved + dtheta.abs())).powi(2),
    ));
    let sigma = g * sigma * g.transpose() + r;
    (predicted, (sigma + sigma.transpose()) / 2.0)
}

/// The measurement a reading makes, with the noise model's standard deviations.
pub fn measurement(reading: &Reading, noise: &NoiseModel, detector: &Detector) -> Measurement {
    match reading {
        Reading::Platforms(platforms) => noise.measure(platforms),
        Reading::Pose(pose) => noise.measure_pose(*pose, detector),
    }
}

/// Whether a measurement is inside the field of view: at most `radius` from the point
/// under the detector (the boundary belongs inside).
pub fn in_view(measurement: &Measurement, radius: f64) -> bool {
    Vector2::new(measurement.pose[0], measurement.pose[1]).norm() <= radius
}

/// The measurement noise covariance `Q = diag(sigma_xy^2, sigma_xy^2, sigma_theta^2)`.
pub fn measurement_noise(measurement: &Measurement) -> Matrix3<f64> {
    let (xy, theta) = (
        measurement.sigma_xy.powi(2),
        measurement.sigma_theta.powi(2),
    );
    Matrix3::from_diagonal(&Vector3::new(xy, xy, theta))
}

/// What became of a step's reading.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "ReadingUse")]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Use {
    /// The step had none.
    NoReading,
    /// It lay outside the field of view.
    OutsideView,
    /// Its Mahalanobis distance was beyond the gate.
    Gated { distance: f64 },
    /// It corrected the estimate.
    Used { distance: f64 },
}

/// What an update made of a measurement, with its Mahalanobis distance `nu' S^-1 nu`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Updated {
    Corrected {
        mu: Vector3<f64>,
        sigma: Matrix3<f64>,
        distance: f64,
    },
    Rejected {
        distance: f64,
    },
}

/// The innovation `nu = z - mu`, its heading wrapped.
pub fn innovation(mu: &Vector3<f64>, z: &Vector3<f64>) -> Vector3<f64> {
    let mut nu = z - mu;
    nu.z = wrap(nu.z);
    nu
}

/// The squared Mahalanobis distance of a measurement `z` with noise `q` from the belief:
/// `nu' S^-1 nu`, `S = Sigma + Q`; infinite when `S` has no inverse.
pub fn mahalanobis(
    mu: &Vector3<f64>,
    sigma: &Matrix3<f64>,
    z: &Vector3<f64>,
    q: &Matrix3<f64>,
) -> f64 {
    let nu = innovation(mu, z);
    (sigma + q)
        .try_inverse()
        .map_or(f64::INFINITY, |s_inv| (nu.transpose() * s_inv * nu)[0])
}

/// One update with a measurement `z` whose noise is `q` (module documentation); rejected
/// when the Mahalanobis distance is beyond `gate`.
pub fn update(
    mu: &Vector3<f64>,
    sigma: &Matrix3<f64>,
    z: &Vector3<f64>,
    q: &Matrix3<f64>,
    gate: f64,
) -> Updated {
    let distance = mahalanobis(mu, sigma, z, q);
    let s_inv = match (sigma + q).try_inverse() {
        Some(s_inv) if distance <= gate => s_inv,
        _ => return Updated::Rejected { distance },
    };
    let k = sigma * s_inv;
    let mut corrected = mu + k * innovation(mu, z);
    corrected.z = wrap(corrected.z);
    let posterior = (Matrix3::identity() - k) * sigma;
    Updated::Corrected {
        mu: corrected,
        sigma: (posterior + posterior.transpose()) / 2.0,
        distance,
    }
}

/// The filter at one step, after its update.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct Estimate {
    /// `[x, y, theta]`
    pub pose: [f64; 3],
    /// `Sigma`, rows.
    pub sigma: [[f64; 3]; 3],
    /// The step's measurement, where it had a reading.
    pub measurement: Option<Measurement>,
    pub reading: Use,
}

/// The filter run over a whole trial, from the first odometry pose.
pub fn run(trial: &Trial, settings: &Settings, detector: &Detector) -> Vec<Estimate> {
    let gate = settings.gate_threshold();
    let first = &trial.steps[0];
    let mut mu = Vector3::from(first.odometry);
    let mut sigma = Matrix3::from_diagonal(&Vector3::from(settings.start_sigma.map(|s| s * s)));
    let mut previous: Option<&Step> = None;
    let mut out = Vec::with_capacity(trial.steps.len());
    for step in &trial.steps {
        if let Some(before) = previous {
            (mu, sigma) = predict(
                &mu,
                &sigma,
                &increment(before.odometry, step.odometry),
                settings,
            );
        }
        previous = Some(step);
        let measurement = step
            .reading
            .map(|r| measurement(&r, &settings.noise, detector));
        let reading = match measurement {
            None => Use::NoReading,
            Some(m) if !in_view(&m, settings.field_of_view) => Use::OutsideView,
            Some(m) => {
                let z = Vector3::from(m.pose);
                match update(&mu, &sigma, &z, &measurement_noise(&m), gate) {
                    Updated::Corrected {
                        mu: after,
                        sigma: covariance,
                        distance,
                    } => {
                        (mu, sigma) = (after, covariance);
                        Use::Used { distance }
                    }
                    Updated::Rejected { distance } => Use::Gated { distance },
                }
            }
        };
        out.push(Estimate {
            pose: mu.into(),
            sigma: sigma.transpose().into(),
            measurement,
            reading,
        });
    }
    out
}

/// Whether `truth` lies inside the 3-sigma ellipse of the position of the estimate `pose`
/// with covariance `s` (rows): `e' Sigma_xy^-1 e <= 9` (98.9 % of a Gaussian's mass).
pub fn inside_three_sigma(pose: [f64; 3], s: &[[f64; 3]; 3], truth: [f64; 3]) -> bool {
    let e = Vector2::new(truth[0] - pose[0], truth[1] - pose[1]);
    Matrix2::new(s[0][0], s[0][1], s[1][0], s[1][1])
        .try_inverse()
        .is_some_and(|inv| (e.transpose() * inv * e)[0] <= 9.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2inv_3_has_the_tables_values() {
        for (p, x) in [
            (0.95, 7.8147),
            (0.99, 11.3449),
            (0.999, 16.2662),
            (0.5, 2.3660),
        ] {
            assert!((chi2inv_3(p) - x).abs() < 1e-4, "{p}: {}", chi2inv_3(p));
        }
        assert_eq!(chi2inv_3(1.0), f64::INFINITY);
    }

    #[test]
    fn the_increment_is_applied_in_the_filtered_frame() {
        // The odometry turned left by 90 degrees and drove 1 m ahead of itself; the filter
        // believes the robot heads along -x, so it moves 1 m along -x... rotated: +90.
        let inc = increment([1.0, 1.0, std::f64::consts::FRAC_PI_2], [1.0, 2.0, 3.0]);
        assert!(
            (inc - Vector3::new(1.0, 0.0, wrap(3.0 - std::f64::consts::FRAC_PI_2))).norm() < 1e-12
        );
        let (mu, _) = predict(
            &Vector3::new(0.0, 0.0, std::f64::consts::PI),
            &Matrix3::zeros(),
            &Vector3::new(1.0, 0.0, 0.0),
            &Settings::default(),
        );
        assert!((mu - Vector3::new(-1.0, 0.0, -std::f64::consts::PI)).norm() < 1e-12);
    }

    #[test]
    fn standing_still_gains_no_uncertainty_and_a_jacobian_checks_out() {
        let settings = Settings::default();
        let sigma = Matrix3::from_diagonal(&Vector3::new(0.01, 0.02, 0.03));
        let (_, same) = predict(
            &Vector3::new(1.0, 2.0, 0.3),
            &sigma,
            &Vector3::zeros(),
            &settings,
        );
        assert!((same - sigma).norm() < 1e-15);
        // G against finite differences of the mean.
        let inc = Vector3::new(0.3, -0.1, 0.2);
        let mu = Vector3::new(0.5, -0.2, 1.1);
        let h = 1e-7;
        let (_, spread) = predict(
            &mu,
            &Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 1.0)),
            &inc,
            &Settings {
                process_xy: 0.0,
                process_theta: 0.0,
                ..settings
            },
        );
        let (plus, _) = predict(
            &(mu + Vector3::new(0.0, 0.0, h)),
            &Matrix3::zeros(),
            &inc,
            &settings,
        );
        let (minus, _) = predict(
            &(mu - Vector3::new(0.0, 0.0, h)),
            &Matrix3::zeros(),
            &inc,
            &settings,
        );
        let column = (plus - minus) / (2.0 * h);
        assert!((spread[(0, 0)] - column.x.powi(2)).abs() < 1e-6);
        assert!((spread[(1, 1)] - column.y.powi(2)).abs() < 1e-6);
    }

    #[test]
    fn the_heading_innovation_is_wrapped_and_the_gate_rejects() {
        let mu = Vector3::new(0.0, 0.0, 3.1);
        let sigma = Matrix3::identity() * 0.01;
        let q = Matrix3::identity() * 0.01;
        let z = Vector3::new(0.0, 0.0, -3.1);
        let Updated::Corrected {
            mu: after,
            distance,
            ..
        } = update(&mu, &sigma, &z, &q, 16.0)
        else {
            panic!("rejected")
        };
        // Halfway along the short way round, across +-pi.
        assert!((after.z - wrap(3.1 + (std::f64::consts::TAU - 6.2) / 2.0)).abs() < 1e-12);
        assert!(distance < 1.0);
        let far = Vector3::new(1.0, 0.0, 3.1);
        assert!(matches!(
            update(&mu, &sigma, &far, &q, 16.0),
            Updated::Rejected { .. }
        ));
        assert!(matches!(
            update(&mu, &sigma, &far, &q, f64::INFINITY),
            Updated::Corrected { .. }
        ));
    }

    #[test]
    fn the_boundary_of_the_field_of_view_is_inside() {
        let at = |x: f64, y: f64| Measurement {
            pose: [x, y, 0.0],
            sigma_xy: 0.1,
            sigma_theta: 0.1,
        };
        assert!(in_view(&at(0.0, 2.0), 2.0));
        assert!(!in_view(&at(0.0, 2.0 + 1e-12), 2.0));
    }
}
