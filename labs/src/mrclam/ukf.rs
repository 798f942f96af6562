//! The unscented Kalman filter: the belief carried through the arc and the camera by
//! 2n + 1 sigma points rather than by Jacobians, the noise added to the carried
//! covariances (R1 = V M V^T in the prediction, R2 in the update), headings and bearings
//! averaged as angles.
//!
//! With n = 3, lambda = alpha^2 (n + kappa) - n, the points are mu and mu +- the columns of
//! the lower Cholesky factor of (n + lambda) Sigma; their weights for the mean are
//! lambda / (n + lambda) for mu and 1 / (2 (n + lambda)) for the rest; for the covariance
//! mu's is lambda / (n + lambda) + (1 - alpha^2 + beta).

use super::belief::{Belief, Filter, Readings};
use super::grid::{Control, Reading};
use super::motion::{self, Noise};
use super::sensor::{self, GATE};
use crate::angle;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};

/// The dimension of the state.
const N: usize = 3;
/// How many sigma points: 2n + 1.
pub const POINTS: usize = 2 * N + 1;

/// The spread of the sigma points (alpha, kappa) and what is known of the distribution
/// (beta = 2 for a Gaussian).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub alpha: f64,
    pub beta: f64,
    pub kappa: f64,
}

/// alpha = 1 and kappa = 1 put the points 2 standard deviations out, every mean weight
/// positive (1/4 for the centre, 1/8 for the rest).
pub const SPREAD: Spread = Spread {
    alpha: 1.0,
    beta: 2.0,
    kappa: 1.0,
};

impl Spread {
    fn lambda(&self) -> f64 {
        self.alpha * self.alpha * (N as f64 + self.kappa) - N as f64
    }

    /// The weights of the points for the mean and for the covariance.
    pub fn weights(&self) -> ([f64; POINTS], [f64; POINTS]) {
        let lambda = self.lambda();
        let scale = N as f64 + lambda;
        let mut mean = [1.0 / (2.0 * scale); POINTS];
        let mut covariance = mean;
        mean[0] = lambda / scale;
        covariance[0] = mean[0] + (1.0 - self.alpha * self.alpha + self.beta);
        (mean, covariance)
    }

    /// The sigma points of `belief`; `None` when its covariance is not positive definite.
    pub fn points(&self, belief: &Belief) -> Option<[Vector3<f64>; POINTS]> {
        let root = (belief.covariance * (N as f64 + self.lambda()))
            .cholesky()?
            .l();
        let mut points = [belief.mean; POINTS];
        for i in 0..N {
            points[1 + i] += root.column(i);
            points[1 + N + i] -= root.column(i);
        }
        Some(points)
    }
}

/// The weighted mean of `points`, the component `angle` (if any) as an angle:
/// atan2(sum w sin, sum w cos).
pub fn mean<const D: usize>(
    points: &[SVector<f64, D>; POINTS],
    weights: &[f64; POINTS],
    angle: Option<usize>,
) -> SVector<f64, D> {
    let mut mean: SVector<f64, D> = points.iter().zip(weights).map(|(p, w)| p * *w).sum();
    if let Some(a) = angle {
        let (sin, cos) = points
            .iter()
            .zip(weights)
            .fold((0.0, 0.0), |(s, c), (p, w)| {
                let (sin, cos) = libm::sincos(p[a]);
                (s + w * sin, c + w * cos)
            });
        mean[a] = libm::atan2(sin, cos);
    }
    mean
}

/// `point - mean`, the component `angle` (if any) wrapped.
fn deviation<const D: usize>(
    point: &SVector<f64, D>,
    mean: &SVector<f64, D>,
    angle: Option<usize>,
) -> SVector<f64, D> {
    let mut d = point - mean;
    if let Some(a) = angle {
        d[a] = angle::wrap(d[a]);
    }
    d
}

/// sum w_c (a_i - a_mean)(b_i - b_mean)^T, deviations of angles wrapped.
pub fn cross_covariance<const A: usize, const B: usize>(
    (a, a_mean, a_angle): (&[SVector<f64, A>; POINTS], &SVector<f64, A>, Option<usize>),
    (b, b_mean, b_angle): (&[SVector<f64, B>; POINTS], &SVector<f64, B>, Option<usize>),
    weights: &[f64; POINTS],
) -> SMatrix<f64, A, B> {
    (0..POINTS)
        .map(|i| {
            deviation(&a[i], a_mean, a_angle)
                * deviation(&b[i], b_mean, b_angle).transpose()
                * weights[i]
        })
        .sum()
}

/// The heading's place in the state, the bearing's in a reading.
pub const HEADING: Option<usize> = Some(2);
pub const BEARING: Option<usize> = Some(1);

/// The unscented prediction: the sigma points of `belief` through `f`, their mean and
/// covariance plus `process`; the state's component `angle` (if any) as an angle. With
/// the points carried; `None` when the covariance is not positive definite.
pub fn predict(
    spread: &Spread,
    belief: &Belief,
    f: impl Fn(&Vector3<f64>) -> Vector3<f64>,
    process: &Matrix3<f64>,
    angle: Option<usize>,
) -> Option<(Belief, [Vector3<f64>; POINTS])> {
    let moved = spread.points(belief)?.map(|p| f(&p));
    let (wm, wc) = spread.weights();
    let mean = mean(&moved, &wm, angle);
    let carried = cross_covariance((&moved, &mean, angle), (&moved, &mean, angle), &wc);
    let belief = Belief {
        mean,
        covariance: symmetric(carried + process),
    };
    Some((belief, moved))
}

/// The unscented correction by the reading `z`: the points of `belief` through `h`;
/// S = their covariance + `noise`, T = the cross-covariance of state and reading,
/// K = T S^-1, mu + K nu, Sigma - K S K^T; `angles` the places of angles in the state and
/// in the reading. With the innovation's squared Mahalanobis distance, for the gate;
/// `None` when a covariance cannot be factored or inverted.
pub fn correct(
    spread: &Spread,
    belief: &Belief,
    h: impl Fn(&Vector3<f64>) -> Vector2<f64>,
    (z, noise): (&Vector2<f64>, &Matrix2<f64>),
    angles: (Option<usize>, Option<usize>),
) -> Option<(Belief, f64)> {
    let (state_angle, reading_angle) = angles;
    let points = spread.points(belief)?;
    let seen = points.map(|p| h(&p));
    let (wm, wc) = spread.weights();
    let expected: Vector2<f64> = mean(&seen, &wm, reading_angle);
    let reading = (&seen, &expected, reading_angle);
    let s = cross_covariance(reading, reading, &wc) + noise;
    let t = cross_covariance((&points, &belief.mean, state_angle), reading, &wc);
    let nu = deviation(z, &expected, reading_angle);
    let inverse = s.try_inverse()?;
    let k = t * inverse;
    let mut moved = belief.mean + k * nu;
    if let Some(a) = state_angle {
        moved[a] = angle::wrap(moved[a]);
    }
    let corrected = Belief {
        mean: moved,
        covariance: symmetric(belief.covariance - k * s * k.transpose()),
    };
    Some((corrected, sensor::mahalanobis(&nu, &inverse)))
}

#[derive(Clone, Debug)]
pub struct Ukf {
    belief: Belief,
    noise: Noise,
    spread: Spread,
    /// The sigma points of the last prediction, carried (for the experiment page).
    predicted: Option<[Vector3<f64>; POINTS]>,
}

impl Ukf {
    pub fn new(start: Belief, noise: Noise) -> Self {
        Ukf {
            belief: start,
            noise,
            spread: SPREAD,
            predicted: None,
        }
    }
}

impl Filter for Ukf {
    /// The points through the arc, plus R1 at the mean. (A covariance rounding has left
    /// not quite positive definite moves with its mean, as the EKF's would.)
    fn predict(&mut self, u: Control, dt: f64) {
        let process = self.noise.process(&self.belief.mean, u, dt);
        let arc = |p: &Vector3<f64>| motion::step(p, u, dt);
        match predict(&self.spread, &self.belief, arc, &process, HEADING) {
            Some((belief, moved)) => {
                self.belief = belief;
                self.predicted = Some(moved);
            }
            None => {
                let g = motion::jacobian_pose(&self.belief.mean, u, dt);
                self.belief = Belief {
                    mean: arc(&self.belief.mean),
                    covariance: symmetric(g * self.belief.covariance * g.transpose() + process),
                };
                self.predicted = None;
            }
        }
    }

    /// Each reading in turn, unless the gate turns it away.
    fn update(&mut self, readings: &[Reading]) -> Readings {
        let mut counts = Readings::default();
        for reading in readings {
            let camera = |p: &Vector3<f64>| sensor::expected(p, &reading.landmark);
            let z = sensor::observed(reading);
            let noise = (&z, &self.noise.measurement);
            match correct(
                &self.spread,
                &self.belief,
                camera,
                noise,
                (HEADING, BEARING),
            ) {
                Some((belief, distance)) if distance <= GATE => {
                    self.belief = belief;
                    counts.used += 1;
                }
                _ => counts.rejected += 1,
            }
        }
        counts
    }

    fn belief(&self) -> Belief {
        self.belief
    }

    /// The sigma points the last prediction carried through the arc.
    fn samples(&self) -> Vec<Vector3<f64>> {
        self.predicted
            .map_or_else(Vec::new, |points| points.to_vec())
    }
}

/// The symmetric part of `m`: rounding leaves a covariance a little lopsided.
fn symmetric(m: Matrix3<f64>) -> Matrix3<f64> {
    (m + m.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Through a linear map the points give the mean and covariance exactly.
    #[test]
    fn a_linear_map_is_carried_exactly() {
        let belief = Belief {
            mean: Vector3::new(1.0, -2.0, 0.5),
            covariance: Matrix3::new(0.3, 0.05, 0.01, 0.05, 0.2, -0.02, 0.01, -0.02, 0.1),
        };
        let a = Matrix3::new(1.0, 0.2, 0.0, -0.3, 1.1, 0.4, 0.0, 0.5, 0.9);
        let b = Vector3::new(0.1, 0.2, -0.3);
        let points = SPREAD.points(&belief).unwrap();
        let (wm, wc) = SPREAD.weights();
        assert!((wm.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let moved = points.map(|p| a * p + b);
        let m = mean(&moved, &wm, None);
        let c = cross_covariance((&moved, &m, None), (&moved, &m, None), &wc);
        assert!((m - (a * belief.mean + b)).amax() < 1e-12);
        assert!((c - a * belief.covariance * a.transpose()).amax() < 1e-12);
    }

    /// With a linear motion and a linear reading the unscented filter is Kalman's: the
    /// same prediction and correction to rounding.
    #[test]
    fn on_a_linear_case_it_is_the_kalman_filter() {
        let belief = Belief {
            mean: Vector3::new(1.0, -2.0, 0.5),
            covariance: Matrix3::new(0.3, 0.05, 0.01, 0.05, 0.2, -0.02, 0.01, -0.02, 0.1),
        };
        let a = Matrix3::new(1.0, 0.02, 0.0, 0.0, 1.0, 0.02, 0.0, 0.0, 1.0);
        let b = Vector3::new(0.01, 0.0, -0.03);
        let process = Matrix3::from_diagonal(&Vector3::new(1e-3, 2e-3, 5e-4));
        let (predicted, _) = predict(&SPREAD, &belief, |x| a * x + b, &process, None).unwrap();
        let kalman_mean = a * belief.mean + b;
        let kalman_covariance = a * belief.covariance * a.transpose() + process;
        assert!((predicted.mean - kalman_mean).amax() < 1e-12);
        assert!((predicted.covariance - kalman_covariance).amax() < 1e-12);

        let c = nalgebra::Matrix2x3::new(1.0, 0.0, 0.5, 0.0, 2.0, -1.0);
        let r = Matrix2::new(0.04, 0.01, 0.01, 0.09);
        let z = Vector2::new(1.3, -4.2);
        let (corrected, distance) =
            correct(&SPREAD, &predicted, |x| c * x, (&z, &r), (None, None)).unwrap();
        let s = c * kalman_covariance * c.transpose() + r;
        let k = kalman_covariance * c.transpose() * s.try_inverse().unwrap();
        let nu = z - c * kalman_mean;
        assert!((corrected.mean - (kalman_mean + k * nu)).amax() < 1e-12);
        let updated = (Matrix3::identity() - k * c) * kalman_covariance;
        assert!((corrected.covariance - updated).amax() < 1e-12);
        assert!((distance - (nu.transpose() * s.try_inverse().unwrap() * nu).x).abs() < 1e-10);
    }
}
