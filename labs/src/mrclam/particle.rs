//! The particle filter: the belief as a weighted cloud of poses. Each particle moves
//! under the commanded control plus a draw of the control noise, is weighted by the
//! likelihood of the step's readings seen from it, and the cloud is drawn anew by
//! low-variance resampling when its effective size falls below a share of its count.
//!
//! Every random number comes from a [`Draws`]: the reference draws from the seeded
//! generator; a graded student's filter is handed the same numbers, in the same order, so
//! its cloud can be held to the reference's step by step.

use super::belief::{Belief, Filter, Readings};
use super::grid::{Control, Reading};
use super::motion::{self, Noise};
use super::sensor::{self, GATE};
use crate::angle;
use crate::rng::Rng;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

/// Where a particle filter's random numbers come from.
pub trait Draws {
    /// A standard normal deviate.
    fn normal(&mut self) -> f64;
    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64;
}

impl Draws for Rng {
    #[inline(always)]
    fn normal(&mut self) -> f64 {
        self.ziggurat_normal()
    }

    fn uniform(&mut self) -> f64 {
        Rng::uniform(self)
    }
}

/// The particle filter's own settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub particles: usize,
    /// The cloud is resampled when its effective sample size 1 / sum w^2 falls below this
    /// share of `particles`.
    pub resample_below: f64,
    /// The gate on a reading's squared Mahalanobis distance from the cloud's mean and
    /// covariance (infinite: no gate).
    pub gate: f64,
}

/// The particles of the reference's runs on the real data.
pub const PARTICLES: usize = 2000;

impl Default for Settings {
    /// `PARTICLES`, resampled below half, the gate at 99.9 %.
    fn default() -> Self {
        Settings {
            particles: PARTICLES,
            resample_below: 0.5,
            gate: GATE,
        }
    }
}

/// A particle: a pose, and the cosine and sine of its heading, carried along with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    pub pose: Vector3<f64>,
    heading: [f64; 2],
}

impl Particle {
    pub fn new(pose: Vector3<f64>) -> Particle {
        let (sin, cos) = libm::sincos(pose.z);
        Particle {
            pose,
            heading: [cos, sin],
        }
    }
}

#[derive(Clone, Debug)]
pub struct ParticleFilter<D> {
    particles: Vec<Particle>,
    /// Normalised: they sum to 1.
    weights: Vec<f64>,
    noise: Noise,
    settings: Settings,
    draws: D,
    /// How often the cloud was resampled.
    resamplings: usize,
}

impl<D: Draws> ParticleFilter<D> {
    /// A cloud drawn from the Gaussian `start` (its covariance taken as diagonal), each
    /// particle's x, y and heading drawn in that order.
    pub fn new(start: Belief, noise: Noise, settings: Settings, mut draws: D) -> Self {
        let sd = start.covariance.diagonal().map(f64::sqrt);
        let particles = (0..settings.particles)
            .map(|_| {
                let x = start.mean.x + sd.x * draws.normal();
                let y = start.mean.y + sd.y * draws.normal();
                let theta = start.mean.z + sd.z * draws.normal();
                Particle::new(Vector3::new(x, y, angle::wrap(theta)))
            })
            .collect();
        ParticleFilter {
            particles,
            weights: vec![1.0 / settings.particles as f64; settings.particles],
            noise,
            settings,
            draws,
            resamplings: 0,
        }
    }

    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    pub fn resamplings(&self) -> usize {
        self.resamplings
    }

    /// 1 / sum w^2: how many equally weighted particles the cloud is worth.
    pub fn effective_size(&self) -> f64 {
        effective_size(&self.weights)
    }

    /// Where its random numbers come from.
    pub fn draws_mut(&mut self) -> &mut D {
        &mut self.draws
    }
}

/// 1 / sum w^2 of normalised weights: how many equally weighted particles they are worth.
pub fn effective_size(weights: &[f64]) -> f64 {
    1.0 / weights.iter().map(|w| w * w).sum::<f64>()
}

/// Whether a cloud of these normalised weights is to be resampled: its effective size
/// below the share `below` of its count.
pub fn needs_resampling(weights: &[f64], below: f64) -> bool {
    effective_size(weights) < below * weights.len() as f64
}

/// `particle` moved for `dt` under the control `u` plus noise: (v + sd_v n_v,
/// omega + sd_omega n_omega), with the noise's standard deviations `sd` and the standard
/// normal draws `normals`. (Its distance and turn are taken as v dt + sd_v dt n_v and
/// omega dt + sd_omega dt n_omega, whose products by dt the filter's loop makes once a
/// step.)
#[inline(always)]
pub fn moved(
    particle: &Particle,
    u: Control,
    [sd_v, sd_omega]: [f64; 2],
    [n_v, n_omega]: [f64; 2],
    dt: f64,
) -> Particle {
    let distance = u.v * dt + sd_v * dt * n_v;
    let delta = u.omega * dt + sd_omega * dt * n_omega;
    let (pose, heading) = motion::advance(&particle.pose, particle.heading, distance, delta);
    Particle { pose, heading }
}

/// The weights after the reading `z` of the post at `landmark`: each multiplied by the
/// likelihood exp(-nu^T R2^-1 nu / 2) of the reading seen from its particle (the bearing's
/// residual wrapped), then normalised; all alike when every one has vanished.
pub fn weigh(
    particles: &[Particle],
    weights: &mut [f64],
    (z, landmark): (&Vector2<f64>, &Vector2<f64>),
    r_inverse: &Matrix2<f64>,
) {
    let distances: Vec<f64> = particles
        .iter()
        .map(|particle| {
            let nu = sensor::innovation(z, &sensor::expected(&particle.pose, landmark));
            sensor::mahalanobis(&nu, r_inverse)
        })
        .collect();
    // Scaled by the likeliest particle's likelihood, which normalising cancels, so that no
    // weight underflows to zero all at once.
    let closest = distances.iter().copied().fold(f64::INFINITY, f64::min);
    for (weight, d) in weights.iter_mut().zip(&distances) {
        *weight *= libm::exp(-0.5 * (d - closest));
    }
    let total: f64 = weights.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        weights.fill(1.0 / particles.len() as f64);
    } else {
        weights.iter_mut().for_each(|w| *w /= total);
    }
}

/// The weighted mean of a cloud (the heading as an angle, atan2 of the weighted sines and
/// cosines) and the weighted covariance about it, headings' deviations wrapped.
pub fn estimate(particles: &[Particle], weights: &[f64]) -> Belief {
    let (mut x, mut y, mut sin, mut cos) = (0.0, 0.0, 0.0, 0.0);
    for (particle, w) in particles.iter().zip(weights) {
        let [c, s] = particle.heading;
        x += w * particle.pose.x;
        y += w * particle.pose.y;
        sin += w * s;
        cos += w * c;
    }
    let mean = Vector3::new(x, y, libm::atan2(sin, cos));
    // The six distinct sums of w d d^T, accumulated apart.
    let mut sums = [0.0; 6];
    for (particle, w) in particles.iter().zip(weights) {
        let pose = &particle.pose;
        let d = [
            pose.x - mean.x,
            pose.y - mean.y,
            angle::difference(pose.z, mean.z),
        ];
        let wd = d.map(|d| w * d);
        sums[0] += wd[0] * d[0];
        sums[1] += wd[0] * d[1];
        sums[2] += wd[0] * d[2];
        sums[3] += wd[1] * d[1];
        sums[4] += wd[1] * d[2];
        sums[5] += wd[2] * d[2];
    }
    let [xx, xy, xt, yy, yt, tt] = sums;
    let covariance = Matrix3::new(xx, xy, xt, xy, yy, yt, xt, yt, tt);
    Belief { mean, covariance }
}

/// Low-variance resampling: one draw `offset` in [0, 1), and the teeth of a comb at
/// (offset + m) / N for m = 0..N-1, each keeping the first particle whose cumulative weight
/// reaches it (the last, where rounding leaves a tooth above the total); the indices of
/// the particles kept.
pub fn low_variance(weights: &[f64], offset: f64) -> Vec<usize> {
    let n = weights.len();
    let step = 1.0 / n as f64;
    let mut kept = Vec::with_capacity(n);
    let (mut i, mut cumulative) = (0, weights[0]);
    for m in 0..n {
        let u = offset * step + m as f64 * step;
        while u > cumulative && i + 1 < n {
            i += 1;
            cumulative += weights[i];
        }
        kept.push(i);
    }
    kept
}

impl<D: Draws> Filter for ParticleFilter<D> {
    /// Each particle moves under (v + sd_v n1, omega + sd_omega n2), the two draws taken
    /// particle by particle in that order. Standing still (no command), nothing moves.
    fn predict(&mut self, u: Control, dt: f64) {
        if u.v == 0.0 && u.omega == 0.0 {
            return;
        }
        let sd = self.noise.control_sd(u);
        for particle in &mut self.particles {
            let normals = [self.draws.normal(), self.draws.normal()];
            *particle = moved(particle, u, sd, normals, dt);
        }
    }

    /// Each reading the gate lets through (judged against the cloud's mean and covariance)
    /// multiplies every particle's weight by exp(-nu^T R2^-1 nu / 2), its bearing residual
    /// wrapped; then the weights are normalised, and the cloud resampled if its effective
    /// size has fallen below the threshold.
    fn update(&mut self, readings: &[Reading]) -> Readings {
        let mut counts = Readings::default();
        let Some(r_inverse) = self.noise.measurement.try_inverse() else {
            counts.rejected += readings.len();
            return counts;
        };
        for reading in readings {
            let belief = self.belief();
            let h = sensor::jacobian(&belief.mean, &reading.landmark);
            let s = h * belief.covariance * h.transpose() + self.noise.measurement;
            let z = sensor::observed(reading);
            let nu = sensor::innovation(&z, &sensor::expected(&belief.mean, &reading.landmark));
            match s.try_inverse() {
                Some(inverse) if sensor::mahalanobis(&nu, &inverse) <= self.settings.gate => {}
                _ => {
                    counts.rejected += 1;
                    continue;
                }
            }
            weigh(
                &self.particles,
                &mut self.weights,
                (&z, &reading.landmark),
                &r_inverse,
            );
            counts.used += 1;
        }
        if counts.used > 0 && needs_resampling(&self.weights, self.settings.resample_below) {
            let kept = low_variance(&self.weights, self.draws.uniform());
            self.particles = kept.iter().map(|&i| self.particles[i]).collect();
            self.weights.fill(1.0 / self.particles.len() as f64);
            self.resamplings += 1;
        }
        counts
    }

    /// The weighted mean (the heading as an angle, atan2 of the weighted sines and
    /// cosines) and the weighted covariance about it, headings' deviations wrapped.
    fn belief(&self) -> Belief {
        estimate(&self.particles, &self.weights)
    }

    fn samples(&self) -> Vec<Vector3<f64>> {
        self.particles.iter().map(|p| p.pose).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mrclam::ekf::Ekf;
    use crate::rng::Rng;

    use proptest::prelude::*;

    proptest! {
        /// Low-variance resampling keeps each particle floor(N w) or ceil(N w) times (to
        /// rounding), and over the offsets N w times on average: unbiased.
        #[test]
        fn low_variance_resampling_is_unbiased(raw in prop::collection::vec(0.0..1.0f64, 1..40)) {
            let total: f64 = raw.iter().sum();
            prop_assume!(total > 0.0);
            let weights: Vec<f64> = raw.iter().map(|w| w / total).collect();
            let n = weights.len();
            let offsets = 2000;
            let mut mean_counts = vec![0.0; n];
            for j in 0..offsets {
                let mut counts = vec![0usize; n];
                for i in low_variance(&weights, (j as f64 + 0.5) / offsets as f64) {
                    counts[i] += 1;
                }
                for (i, (&count, w)) in counts.iter().zip(&weights).enumerate() {
                    let expected = n as f64 * w;
                    prop_assert!(
                        (expected - 1e-9).floor() <= count as f64 && count as f64 <= (expected + 1e-9).ceil(),
                        "particle {i}: {count} copies for N w = {expected}"
                    );
                    mean_counts[i] += count as f64 / offsets as f64;
                }
            }
            for (mean, w) in mean_counts.iter().zip(&weights) {
                prop_assert!((mean - n as f64 * w).abs() < 2e-3, "{mean} against {}", n as f64 * w);
            }
        }
    }

    /// A linear Gaussian case inside the robot's model: it spins on the spot (no forward
    /// motion, so no position noise) with a known position, and reads the bearing of a
    /// post, which is then linear in the heading. The EKF is the Kalman filter there; the
    /// particle filter's mean and variance of the heading agree with it within sampling
    /// error.
    #[test]
    fn on_a_linear_gaussian_case_it_agrees_with_the_kalman_filter() {
        let noise = Noise {
            alphas: [0.0, 0.0, 0.0, 0.3],
            measurement: Matrix2::new(0.01, 0.0, 0.0, 0.05 * 0.05),
        };
        let start = Belief {
            mean: Vector3::zeros(),
            covariance: Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 0.1 * 0.1)),
        };
        let landmark = Vector2::new(5.0, 0.0);
        let dt = 0.02;
        let mut truth = Rng::new(5);
        let mut heading = 0.05;
        let mut ekf = Ekf::new(start, noise);
        let particles = 4000;
        let settings = Settings {
            particles,
            ..Settings::default()
        };
        let mut pf = ParticleFilter::new(start, noise, settings, Rng::new(6));
        for k in 0..300 {
            let u = Control {
                v: 0.0,
                omega: if k < 150 { 0.8 } else { -0.8 },
            };
            heading += dt * (u.omega + 0.3 * u.omega.abs() * truth.standard_normal());
            ekf.predict(u, dt);
            pf.predict(u, dt);
            let readings = if k % 5 == 0 {
                vec![Reading {
                    subject: 6,
                    landmark,
                    range: 5.0,
                    bearing: -heading + 0.05 * truth.standard_normal(),
                }]
            } else {
                Vec::new()
            };
            assert_eq!(ekf.update(&readings).used, readings.len());
            pf.update(&readings);
            let (kalman, particle) = (ekf.belief(), pf.belief());
            let variance = kalman.covariance[(2, 2)];
            // Position known exactly, by both.
            assert_eq!(particle.mean.xy(), Vector2::zeros());
            let error = (particle.mean.z - kalman.mean.z).abs();
            assert!(
                error < 0.1 * variance.sqrt(),
                "step {k}: {error} against sd {}",
                variance.sqrt()
            );
            let ratio = particle.covariance[(2, 2)] / variance;
            assert!(
                (0.85..1.15).contains(&ratio),
                "step {k}: variance ratio {ratio}"
            );
        }
        assert!(pf.resamplings() > 0);
    }
}
