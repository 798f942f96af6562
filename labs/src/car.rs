//! The warm-up (EL2320 Lab 1, section 3.1): a car on a line, state `[position,
//! velocity]`, driven by a known input and seen through noisy position measurements, and
//! the linear Kalman filter that estimates it.
//!
//! x_k = A x_{k-1} + B u + w_k,  z_k = C x_k + v_k,  A = [1 dt; 0 1], B = [0; dt], C = [1 0].
//!
//! What the filter is told about the noise (R, Q, the initial belief) is separate from the
//! noise the simulation draws: the exercise is to see what happens when they disagree.

use crate::Error;
use crate::rng::Rng;
use nalgebra::{Matrix1x2, Matrix2, Vector2};
use serde::{Deserialize, Serialize};

/// Everything a warm-up run depends on, with the lab script's defaults.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CarParams {
    /// Time step, seconds.
    pub dt: f64,
    pub steps: usize,
    /// The control input (an acceleration), the same at every step.
    pub u: f64,
    /// The true initial state.
    pub x0: [f64; 2],
    /// Standard deviations of the simulated process noise (position, velocity).
    pub process_std: [f64; 2],
    /// Standard deviation of the simulated measurement noise.
    pub measurement_std: f64,
    /// R, the process noise covariance the filter assumes.
    pub r: [[f64; 2]; 2],
    /// Q, the measurement noise variance the filter assumes.
    pub q: f64,
    /// The filter's initial estimate and covariance.
    pub mu0: [f64; 2],
    pub sigma0: [[f64; 2]; 2],
    pub seed: u64,
}

impl Default for CarParams {
    fn default() -> Self {
        CarParams {
            dt: 0.1,
            steps: 100,
            u: 0.0,
            x0: [1.0, 0.5],
            process_std: [0.01, 0.1],
            measurement_std: 0.1,
            r: [[0.01 * 0.01, 0.0], [0.0, 0.1 * 0.1]],
            q: 0.1 * 0.1,
            mu0: [-2.0, 0.0],
            sigma0: [[1.0, 0.0], [0.0, 1.0]],
            seed: 1,
        }
    }
}

/// One step of a run: the truth, what was measured, and what the filter made of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CarStep {
    pub t: f64,
    pub truth: Vector2<f64>,
    pub z: f64,
    pub mu: Vector2<f64>,
    pub sigma: Matrix2<f64>,
    /// The Kalman gain K (2 x 1).
    pub gain: Vector2<f64>,
}

impl CarStep {
    /// The estimation error `mu - truth` (position, velocity).
    pub fn error(&self) -> Vector2<f64> {
        self.mu - self.truth
    }

    /// The filter's own standard deviations of position and velocity: sqrt(P11), sqrt(P22).
    pub fn std_dev(&self) -> [f64; 2] {
        [self.sigma[(0, 0)].sqrt(), self.sigma[(1, 1)].sqrt()]
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CarRun {
    pub steps: Vec<CarStep>,
    /// Sample standard deviation of the position and velocity errors (estimate - truth)
    /// over the second half of the run.
    pub error_std: [f64; 2],
}

impl CarParams {
    /// Checks every parameter, naming the first that is out of its domain.
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(Error::invalid("dt", "must be a positive number"));
        }
        if !(2..=100_000).contains(&self.steps) {
            return Err(Error::invalid(
                "steps",
                format!("must lie in 2..=100000, got {}", self.steps),
            ));
        }
        let finite = [self.u, self.x0[0], self.x0[1], self.mu0[0], self.mu0[1]];
        if !finite.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid("u, x0, mu0", "must be finite"));
        }
        for (field, std) in [
            ("process_std", self.process_std[0]),
            ("process_std", self.process_std[1]),
            ("measurement_std", self.measurement_std),
        ] {
            if !(std.is_finite() && std >= 0.0) {
                return Err(Error::invalid(field, "must be finite and >= 0"));
            }
        }
        covariance("R", &self.r)?;
        covariance("sigma0", &self.sigma0)?;
        if !(self.q.is_finite() && self.q > 0.0) {
            return Err(Error::invalid("Q", "must be a positive variance"));
        }
        Ok(())
    }
}

/// A 2 x 2 covariance: finite, symmetric, positive semi-definite.
fn covariance(field: &str, a: &[[f64; 2]; 2]) -> Result<(), Error> {
    let [[a, b], [c, d]] = *a;
    if ![a, b, c, d].iter().all(|v| v.is_finite()) || b != c {
        return Err(Error::invalid(field, "must be a finite symmetric matrix"));
    }
    if a < 0.0 || d < 0.0 || a * d - b * c < 0.0 {
        return Err(Error::invalid(field, "must be positive semi-definite"));
    }
    Ok(())
}

/// Simulates the car and runs the Kalman filter on its measurements:
///
/// predict:  mu_bar = A mu + B u,  Sigma_bar = A Sigma A' + R
/// update:   K = Sigma_bar C' (C Sigma_bar C' + Q)^-1,  mu = mu_bar + K (z - C mu_bar),
///           Sigma = (I - K C) Sigma_bar
pub fn run(params: &CarParams) -> Result<CarRun, Error> {
    params.validate()?;
    let dt = params.dt;
    let a = Matrix2::new(1.0, dt, 0.0, 1.0);
    let b = Vector2::new(0.0, dt);
    let c = Matrix1x2::new(1.0, 0.0);
    let r = Matrix2::from_fn(|i, j| params.r[i][j]);
    let sigma0 = Matrix2::from_fn(|i, j| params.sigma0[i][j]);

    let mut rng = Rng::new(params.seed);
    let mut truth = Vector2::from(params.x0);
    let mut mu = Vector2::from(params.mu0);
    let mut sigma = sigma0;
    let mut steps = Vec::with_capacity(params.steps);
    for k in 1..=params.steps {
        let w = Vector2::new(
            rng.normal(0.0, params.process_std[0]),
            rng.normal(0.0, params.process_std[1]),
        );
        truth = a * truth + b * params.u + w;
        let z = truth.x + rng.normal(0.0, params.measurement_std);

        let mu_bar = a * mu + b * params.u;
        let sigma_bar = a * sigma * a.transpose() + r;
        let innovation_variance = (c * sigma_bar * c.transpose()).x + params.q;
        let gain = sigma_bar * c.transpose() / innovation_variance;
        mu = mu_bar + gain * (z - (c * mu_bar).x);
        sigma = (Matrix2::identity() - gain * c) * sigma_bar;
        steps.push(CarStep {
            t: k as f64 * dt,
            truth,
            z,
            mu,
            sigma,
            gain,
        });
    }
    let error_std = second_half_error_std(&steps);
    Ok(CarRun { steps, error_std })
}

/// The same car and filter run with many seeds: how the estimation error actually spreads
/// over time, beside the spread the filter believes in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MonteCarlo {
    pub runs: usize,
    pub t: Vec<f64>,
    /// Per step, over the runs: the mean of the error (estimate - truth), position and
    /// velocity; a mean far from zero is a bias.
    pub error_mean: Vec<[f64; 2]>,
    /// Per step, over the runs: the sample standard deviation of the error.
    pub error_std: Vec<[f64; 2]>,
    /// Per step: sqrt(P11), sqrt(P22). The covariance of a linear Kalman filter does not
    /// depend on the measurements, so it is the same in every run.
    pub filter_std: Vec<[f64; 2]>,
}

/// Runs the car with the seeds `params.seed`, `params.seed + 1`, ... (`runs` of them).
pub fn monte_carlo(params: &CarParams, runs: usize) -> Result<MonteCarlo, Error> {
    if !(2..=10_000).contains(&runs) {
        return Err(Error::invalid(
            "runs",
            format!("must lie in 2..=10000, got {runs}"),
        ));
    }
    let results = (0..runs as u64)
        .map(|k| {
            run(&CarParams {
                seed: params.seed.wrapping_add(k),
                ..params.clone()
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let n = runs as f64;
    let steps = results[0].steps.len();
    let mut monte_carlo = MonteCarlo {
        runs,
        t: results[0].steps.iter().map(|s| s.t).collect(),
        error_mean: Vec::with_capacity(steps),
        error_std: Vec::with_capacity(steps),
        filter_std: results[0].steps.iter().map(CarStep::std_dev).collect(),
    };
    for k in 0..steps {
        let error = |r: &CarRun, i: usize| r.steps[k].error()[i];
        let mean: [f64; 2] =
            std::array::from_fn(|i| results.iter().map(|r| error(r, i)).sum::<f64>() / n);
        let std = std::array::from_fn(|i| {
            let squares = results
                .iter()
                .map(|r| (error(r, i) - mean[i]).powi(2))
                .sum::<f64>();
            (squares / (n - 1.0)).sqrt()
        });
        monte_carlo.error_mean.push(mean);
        monte_carlo.error_std.push(std);
    }
    Ok(monte_carlo)
}

/// The sample standard deviation of each error component over the second half.
fn second_half_error_std(steps: &[CarStep]) -> [f64; 2] {
    let half = &steps[steps.len() / 2..];
    let n = half.len() as f64;
    std::array::from_fn(|i| {
        let errors = half.iter().map(|s| s.error()[i]);
        let mean = errors.clone().sum::<f64>() / n;
        (errors.map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_run() {
        let params = CarParams::default();
        assert_eq!(run(&params).unwrap(), run(&params).unwrap());
        let other = CarParams {
            seed: 2,
            ..params.clone()
        };
        assert_ne!(
            run(&params).unwrap().steps[5].z,
            run(&other).unwrap().steps[5].z
        );
    }

    #[test]
    fn the_filter_converges_from_a_wrong_start() {
        let result = run(&CarParams::default()).unwrap();
        let last = result.steps.last().unwrap();
        assert!(
            (last.mu - last.truth).norm() < 0.5,
            "{:?} vs {:?}",
            last.mu,
            last.truth
        );
        // The error spread over the second half is of the order of the noise.
        assert!(
            result.error_std[0] < 0.1 && result.error_std[1] < 0.3,
            "{:?}",
            result.error_std
        );
    }

    #[test]
    fn a_small_modelled_measurement_noise_makes_the_filter_follow_the_measurements() {
        let trusting = CarParams {
            q: 1e-8,
            ..CarParams::default()
        };
        let result = run(&trusting).unwrap();
        for step in &result.steps {
            assert!((step.mu.x - step.z).abs() < 1e-3);
            assert!(step.gain.x > 0.99);
        }
    }

    #[test]
    fn covariances_stay_symmetric_and_positive() {
        for step in run(&CarParams::default()).unwrap().steps {
            let s = step.sigma;
            assert!((s[(0, 1)] - s[(1, 0)]).abs() < 1e-12);
            assert!(s[(0, 0)] > 0.0 && s.determinant() > 0.0);
        }
    }

    #[test]
    fn a_well_tuned_filter_believes_the_spread_it_shows() {
        let mc = monte_carlo(&CarParams::default(), 400).unwrap();
        // Over the second half the actual error spread matches the filter's sigma.
        for k in 50..100 {
            for i in 0..2 {
                let ratio = mc.error_std[k][i] / mc.filter_std[k][i];
                assert!(
                    (0.8..1.25).contains(&ratio),
                    "step {k}, component {i}: ratio {ratio}"
                );
            }
        }
    }

    #[test]
    fn an_overconfident_filter_underestimates_the_spread() {
        let overconfident = CarParams {
            r: [[1e-8, 0.0], [0.0, 1e-6]],
            ..CarParams::default()
        };
        let mc = monte_carlo(&overconfident, 200).unwrap();
        let k = 99;
        assert!(
            mc.error_std[k][1] > 3.0 * mc.filter_std[k][1],
            "{:?} vs {:?}",
            mc.error_std[k],
            mc.filter_std[k]
        );
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = CarParams {
            q: 0.0,
            ..CarParams::default()
        };
        assert_eq!(
            run(&bad).unwrap_err().to_string(),
            "Q: must be a positive variance"
        );
        let bad = CarParams {
            r: [[1.0, 2.0], [2.0, 1.0]],
            ..CarParams::default()
        };
        assert_eq!(
            run(&bad).unwrap_err().to_string(),
            "R: must be positive semi-definite"
        );
        let bad = CarParams {
            steps: 1,
            ..CarParams::default()
        };
        assert_eq!(
            run(&bad).unwrap_err().to_string(),
            "steps: must lie in 2..=100000, got 1"
        );
    }
}
