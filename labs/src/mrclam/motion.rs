//! The robot's motion: the unicycle's arc under a commanded (v, omega), its Jacobians,
//! and the control noise the filters assume.
//!
//! Over a step of `dt` at constant v and omega the robot turns by delta = omega dt along a
//! circle of radius v / omega:
//!
//!   x' = x + v/omega (-sin theta + sin(theta + delta))
//!   y' = y + v/omega ( cos theta - cos(theta + delta))
//!   theta' = theta + delta
//!
//! Written as v dt (cos theta S(delta) - sin theta C(delta)) and v dt (sin theta S(delta) +
//! cos theta C(delta)) with S = sin(delta)/delta and C = (1 - cos delta)/delta, the
//! straight line delta -> 0 (S -> 1, C -> 0) needs no division by omega.

use super::grid::Control;
use crate::angle;
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector3};
use serde::{Deserialize, Serialize};

/// Below this turn [rad] the arc's ratios come from their Taylor series, exact there to
/// the last bit (the first term left out is below 1e-21 of the sum); at 50 Hz a robot
/// turns less than this in a step unless it spins at 5 rad/s.
const SMALL_TURN: f64 = 0.1;
/// Below this turn the first four terms of the series are as exact (the first term left
/// out is below 2e-18 of the sum): the turns of nearly every step at 50 Hz, under
/// 1.5 rad/s, which the particle filter makes thousands of times a step.
const SMALLER_TURN: f64 = 0.03;

/// The Taylor coefficients, in delta^2, of S(delta) = sin(delta) / delta:
/// (-1)^k / (2k + 1)!.
const S_SERIES: [f64; 6] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
];
/// The same of C(delta) / delta, C(delta) = (1 - cos delta) / delta: (-1)^k / (2k + 2)!.
const C_SERIES: [f64; 6] = [
    1.0 / 2.0,
    -1.0 / 24.0,
    1.0 / 720.0,
    -1.0 / 40_320.0,
    1.0 / 3_628_800.0,
    -1.0 / 479_001_600.0,
];

/// The polynomial with `coefficients` (lowest first) at `x`, by Horner's scheme.
#[inline(always)]
fn horner<const N: usize>(coefficients: &[f64; N], x: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |sum, c| sum * x + c)
}

/// The polynomial with `coefficients` (lowest first, an even count) at `x`, by Estrin's
/// scheme: the pairs c_2k + c_2k+1 x, independent of each other, summed by Horner's scheme
/// in x^2. Its chain of dependent operations is about half as long as Horner's, and the
/// particle filter's motion waits on that chain.
#[inline(always)]
fn estrin<const N: usize>(coefficients: &[f64; N], x: f64) -> f64 {
    const { assert!(N.is_multiple_of(2) && N > 0) };
    let x2 = x * x;
    let mut pairs = coefficients
        .chunks_exact(2)
        .rev()
        .map(|pair| pair[0] + pair[1] * x);
    let highest = pairs.next().expect("at least one pair");
    pairs.fold(highest, |sum, pair| sum * x2 + pair)
}

/// S(delta) = sin(delta) / delta and C(delta) = (1 - cos delta) / delta.
#[inline(always)]
fn arc_ratios(delta: f64) -> (f64, f64) {
    let d2 = delta * delta;
    if delta.abs() < SMALLER_TURN {
        let [s, c] = [&S_SERIES, &C_SERIES].map(|series| {
            let first: &[f64; 4] = series.first_chunk().expect("six terms");
            estrin(first, d2)
        });
        (s, delta * c)
    } else if delta.abs() < SMALL_TURN {
        (estrin(&S_SERIES, d2), delta * estrin(&C_SERIES, d2))
    } else {
        let (sin, cos) = libm::sincos(delta);
        (sin / delta, (1.0 - cos) / delta)
    }
}

/// The derivatives S'(delta) and C'(delta).
fn arc_ratio_slopes(delta: f64) -> (f64, f64) {
    if delta.abs() < SMALL_TURN {
        let d2 = delta * delta;
        // Term by term: S = sum s_k delta^2k gives S' = delta sum 2(k+1) s_(k+1) delta^2k,
        // and C = sum c_k delta^(2k+1) gives C' = sum (2k+1) c_k delta^2k.
        let s_slope: [f64; 5] = std::array::from_fn(|k| S_SERIES[k + 1] * (2 * k + 2) as f64);
        let c_slope: [f64; 6] = std::array::from_fn(|k| C_SERIES[k] * (2 * k + 1) as f64);
        (delta * horner(&s_slope, d2), horner(&c_slope, d2))
    } else {
        let (sin, cos) = libm::sincos(delta);
        let d2 = delta * delta;
        ((delta * cos - sin) / d2, (delta * sin - (1.0 - cos)) / d2)
    }
}

/// The pose after moving from `pose` under `u` for `dt`; the heading wrapped.
pub fn step(pose: &Vector3<f64>, u: Control, dt: f64) -> Vector3<f64> {
    let (sin, cos) = libm::sincos(pose.z);
    advance(pose, [cos, sin], u.v * dt, u.omega * dt).0
}

/// `step` for a pose whose heading's cosine and sine are known, giving theirs after the
/// step too, over a `distance` v dt and a turn `delta` = omega dt. With a = cos S - sin C
/// and b = sin S + cos C, the step moves the robot by v dt (a, b), and (cos, sin) rotated by delta, with sin(delta) = delta S and
/// cos(delta) = 1 - delta C, is (cos - delta b, sin + delta a). (What a particle filter
/// carries, to spare two sines a particle a step.)
#[inline(always)]
pub fn advance(
    pose: &Vector3<f64>,
    [cos, sin]: [f64; 2],
    distance: f64,
    delta: f64,
) -> (Vector3<f64>, [f64; 2]) {
    let (s, c) = arc_ratios(delta);
    let (a, b) = (cos * s - sin * c, sin * s + cos * c);
    let moved = Vector3::new(
        pose.x + distance * a,
        pose.y + distance * b,
        angle::wrap(pose.z + delta),
    );
    (moved, [cos - delta * b, sin + delta * a])
}

/// How far the arc carries the robot from heading `theta`: (x' - x, y' - y).
fn displacement(theta: f64, u: Control, dt: f64) -> (f64, f64) {
    let moved = step(&Vector3::new(0.0, 0.0, theta), u, dt);
    (moved.x, moved.y)
}

/// G, the Jacobian of `step` with respect to the pose: the heading swings the
/// displacement (dx, dy) round, so d x'/d theta = -dy and d y'/d theta = dx.
pub fn jacobian_pose(pose: &Vector3<f64>, u: Control, dt: f64) -> Matrix3<f64> {
    let (dx, dy) = displacement(pose.z, u, dt);
    Matrix3::new(1.0, 0.0, -dy, 0.0, 1.0, dx, 0.0, 0.0, 1.0)
}

/// V, the Jacobian of `step` with respect to the control (v, omega):
/// d x'/d v = dt (cos S - sin C), d x'/d omega = v dt^2 (cos S' - sin C'), and alike for y;
/// the heading moves by dt per rad/s.
pub fn jacobian_control(pose: &Vector3<f64>, u: Control, dt: f64) -> Matrix3x2<f64> {
    let delta = u.omega * dt;
    let (s, c) = arc_ratios(delta);
    let (ds, dc) = arc_ratio_slopes(delta);
    let (sin, cos) = libm::sincos(pose.z);
    let turn = u.v * dt * dt;
    Matrix3x2::new(
        dt * (cos * s - sin * c),
        turn * (cos * ds - sin * dc),
        dt * (sin * s + cos * c),
        turn * (sin * ds + cos * dc),
        0.0,
        dt,
    )
}

/// The noise of the robot's motion and of its camera, as the filters assume it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "MrclamNoise")]
pub struct Noise {
    /// alpha1..alpha4: the standard deviation of the actual v is alpha1 |v| + alpha2 |omega|,
    /// of the actual omega alpha3 |v| + alpha4 |omega|.
    pub alphas: [f64; 4],
    /// R2: the covariance of a reading's (range, bearing) error (in JSON its elements
    /// column by column).
    #[ts(type = "[number, number, number, number]")]
    pub measurement: Matrix2<f64>,
}

impl Noise {
    /// M, the covariance of the actual control about the commanded one:
    /// diag((alpha1 |v| + alpha2 |omega|)^2, (alpha3 |v| + alpha4 |omega|)^2).
    pub fn control(&self, u: Control) -> Matrix2<f64> {
        let [sd_v, sd_omega] = self.control_sd(u);
        Matrix2::new(sd_v * sd_v, 0.0, 0.0, sd_omega * sd_omega)
    }

    /// The standard deviations of the actual v and omega.
    pub fn control_sd(&self, u: Control) -> [f64; 2] {
        let [a1, a2, a3, a4] = self.alphas;
        let (v, omega) = (u.v.abs(), u.omega.abs());
        [a1 * v + a2 * omega, a3 * v + a4 * omega]
    }

    /// R1 = V M V^T: the control noise carried into the pose by the step's Jacobian.
    pub fn process(&self, pose: &Vector3<f64>, u: Control, dt: f64) -> Matrix3<f64> {
        let v = jacobian_control(pose, u, dt);
        v * self.control(u) * v.transpose()
    }

    /// The same noise with R2 scaled by `rho`: the one knob that sets how far the filters
    /// trust the camera against the odometry (det M / det(rho R2) falls as rho grows).
    pub fn with_measurement_scale(self, rho: f64) -> Noise {
        Noise {
            measurement: self.measurement * rho,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn numeric_jacobians(
        pose: Vector3<f64>,
        u: Control,
        dt: f64,
    ) -> (Matrix3<f64>, Matrix3x2<f64>) {
        let h = 1e-6;
        let mut g = Matrix3::zeros();
        for j in 0..3 {
            let mut plus = pose;
            let mut minus = pose;
            plus[j] += h;
            minus[j] -= h;
            let d = step(&plus, u, dt) - step(&minus, u, dt);
            g.set_column(j, &Vector3::new(d.x, d.y, angle::wrap(d.z)).scale(0.5 / h));
        }
        let mut v = Matrix3x2::zeros();
        for (j, (dv, domega)) in [(h, 0.0), (0.0, h)].into_iter().enumerate() {
            let plus = Control {
                v: u.v + dv,
                omega: u.omega + domega,
            };
            let minus = Control {
                v: u.v - dv,
                omega: u.omega - domega,
            };
            let d = step(&pose, plus, dt) - step(&pose, minus, dt);
            v.set_column(j, &Vector3::new(d.x, d.y, angle::wrap(d.z)).scale(0.5 / h));
        }
        (g, v)
    }

    proptest! {
        /// The arc as published (v/omega form) wherever omega is not small, and the
        /// Jacobians the derivatives of the step, the straight line and its neighbours
        /// included.
        #[test]
        fn the_arc_and_its_jacobians(
            x in -5.0..5.0f64, y in -5.0..5.0f64, theta in -3.1..3.1f64,
            v in -0.5..0.5f64, omega in prop_oneof![-2.0..2.0f64, Just(0.0), -1e-5..1e-5f64, 5.0..12.0f64, -12.0..-5.0f64],
        ) {
            let dt = 0.02;
            let pose = Vector3::new(x, y, theta);
            let u = Control { v, omega };
            let next = step(&pose, u, dt);
            if omega.abs() > 0.1 {
                let r = v / omega;
                let turned = theta + omega * dt;
                prop_assert!((next.x - (x + r * (-theta.sin() + turned.sin()))).abs() < 1e-12);
                prop_assert!((next.y - (y + r * (theta.cos() - turned.cos()))).abs() < 1e-12);
            }
            prop_assert!(angle::difference(next.z, theta + omega * dt).abs() < 1e-12);
            let (g, vj) = numeric_jacobians(pose, u, dt);
            prop_assert!((jacobian_pose(&pose, u, dt) - g).amax() < 1e-8);
            prop_assert!((jacobian_control(&pose, u, dt) - vj).amax() < 1e-8);
        }
    }

    /// The series and the closed forms meet where they hand over, and the series hold
    /// all the way down.
    #[test]
    fn the_series_meet_the_closed_forms() {
        for delta in [SMALL_TURN * 0.999_999, -SMALL_TURN * 0.999_999, 0.05, 0.003] {
            let (s, c) = arc_ratios(delta);
            let (ds, dc) = arc_ratio_slopes(delta);
            let (sin, cos) = (delta.sin(), delta.cos());
            assert!((s - sin / delta).abs() < 1e-15);
            assert!((c - (1.0 - cos) / delta).abs() < 1e-13);
            assert!((delta * s - sin).abs() <= f64::EPSILON * sin.abs());
            assert!((1.0 - delta * c - cos).abs() <= f64::EPSILON);
            assert!((ds - (delta * cos - sin) / (delta * delta)).abs() < 1e-10);
            assert!((dc - (delta * sin - (1.0 - cos)) / (delta * delta)).abs() < 1e-10);
        }
        // Four terms and six agree where they hand over.
        for delta in [SMALLER_TURN * 0.999_999, -SMALLER_TURN * 0.999_999] {
            let (s, c) = arc_ratios(delta);
            let d2 = delta * delta;
            assert!((s - horner(&S_SERIES, d2)).abs() <= f64::EPSILON);
            assert!((c - delta * horner(&C_SERIES, d2)).abs() <= f64::EPSILON * c.abs());
        }
        // Continuous across the hand-over: just below (series) and just above (closed).
        let (below, above) = (SMALL_TURN * (1.0 - 1e-9), SMALL_TURN * (1.0 + 1e-9));
        let [b, a] = [below, above].map(|d| (arc_ratios(d), arc_ratio_slopes(d)));
        for (x, y) in [
            (b.0.0, a.0.0),
            (b.0.1, a.0.1),
            (b.1.0, a.1.0),
            (b.1.1, a.1.1),
        ] {
            assert!((x - y).abs() < 1e-9, "{x} below, {y} above");
        }
    }
}
