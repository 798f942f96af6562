//! The extended Kalman filter: the arc and the camera linearised at the current mean,
//! one reading at a time.

use super::belief::{Belief, Filter, Readings};
use super::grid::{Control, Reading};
use super::motion::{self, Noise};
use super::sensor::{self, GATE};
use crate::angle;
use nalgebra::{Matrix3, Vector3};

#[derive(Clone, Debug)]
pub struct Ekf {
    belief: Belief,
    noise: Noise,
}

impl Ekf {
    pub fn new(start: Belief, noise: Noise) -> Self {
        Ekf {
            belief: start,
            noise,
        }
    }
}

impl Filter for Ekf {
    /// mu' = g(u, mu), Sigma' = G Sigma G^T + V M V^T.
    fn predict(&mut self, u: Control, dt: f64) {
        let Belief { mean, covariance } = self.belief;
        let g = motion::jacobian_pose(&mean, u, dt);
        self.belief = Belief {
            mean: motion::step(&mean, u, dt),
            covariance: g * covariance * g.transpose() + self.noise.process(&mean, u, dt),
        };
    }

    /// For each reading: S = H Sigma H^T + R2, K = Sigma H^T S^-1, mu += K nu,
    /// Sigma = (I - K H) Sigma; unless nu^T S^-1 nu is beyond the gate.
    fn update(&mut self, readings: &[Reading]) -> Readings {
        let mut counts = Readings::default();
        for reading in readings {
            let Belief { mean, covariance } = self.belief;
            let h = sensor::jacobian(&mean, &reading.landmark);
            let s = h * covariance * h.transpose() + self.noise.measurement;
            let nu = sensor::innovation(
                &sensor::observed(reading),
                &sensor::expected(&mean, &reading.landmark),
            );
            let Some(inverse) = s.try_inverse() else {
                counts.rejected += 1;
                continue;
            };
            // (A distance that is no number, from a mean standing on the post, fails too.)
            let distance = sensor::mahalanobis(&nu, &inverse);
            if distance.is_nan() || distance > GATE {
                counts.rejected += 1;
                continue;
            }
            let k = covariance * h.transpose() * inverse;
            let moved = mean + k * nu;
            let covariance = (Matrix3::identity() - k * h) * covariance;
            self.belief = Belief {
                mean: Vector3::new(moved.x, moved.y, angle::wrap(moved.z)),
                covariance: (covariance + covariance.transpose()) * 0.5,
            };
            counts.used += 1;
        }
        counts
    }

    fn belief(&self) -> Belief {
        self.belief
    }
}
