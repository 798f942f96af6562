use super::association::{Match, candidate, lambda_m, most_likely};
use super::{Belief, Robot, batch_update, calculate_odometry, predict, update};
use crate::Error;
use crate::angle::{difference, wrap};
use crate::dataset::{Dataset, Step};
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How the readings of one time step update the belief.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpdateMode {
    /// One reading after the other, each associated against the belief the previous one
    /// left (EL2320 Alg. 3).
    Sequential,
    /// All readings associated against the same predicted belief, then one stacked update
    /// (EL2320 Alg. 4).
    Batch,
}

/// Everything the filter loop is told besides the data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub mode: UpdateMode,
    /// Use the landmark ids in the sensor file instead of maximum-likelihood association.
    pub known_associations: bool,
    /// R, the process noise covariance (per time step).
    pub r: Matrix3<f64>,
    /// Q, the measurement noise covariance of one reading (range, bearing).
    pub q: Matrix2<f64>,
    /// delta_M, the probability mass of the chi-square outlier gate; 1 disables rejection.
    pub delta_m: f64,
    /// The initial belief.
    pub mu0: Vector3<f64>,
    pub sigma0: Matrix3<f64>,
    pub robot: Robot,
}

impl Settings {
    /// The lab's settings for `so_o3_ie`: R = diag(0.01^2, 0.01^2, (1 deg)^2),
    /// Q = diag(0.01^2, (1 deg)^2), delta_M = 0.999, sequential.
    pub fn lab_o3() -> Self {
        let deg = PI / 180.0;
        Settings {
            mode: UpdateMode::Sequential,
            known_associations: false,
            r: Matrix3::from_diagonal(&Vector3::new(0.01_f64.powi(2), 0.01_f64.powi(2), deg * deg)),
            q: Matrix2::from_diagonal(&Vector2::new(0.01_f64.powi(2), deg * deg)),
            delta_m: 0.999,
            mu0: Vector3::zeros(),
            sigma0: Matrix3::identity() * 1e-10,
            robot: Robot::EL2320,
        }
    }

    /// The lab's settings for `so_pb_10_outlier`: R as for o3, Q = diag(0.2^2, 0.2^2).
    pub fn lab_outliers() -> Self {
        Settings {
            q: Matrix2::identity() * 0.2_f64.powi(2),
            ..Settings::lab_o3()
        }
    }

    /// The lab's settings for `so_pb_40_no`: R = I, Q = 0.1^2 I, delta_M = 1, batch.
    pub fn lab_no_odometry() -> Self {
        Settings {
            mode: UpdateMode::Batch,
            r: Matrix3::identity(),
            q: Matrix2::identity() * 0.1_f64.powi(2),
            delta_m: 1.0,
            ..Settings::lab_o3()
        }
    }

    /// These settings with diagonal R and Q given as variances (x, y, theta; range,
    /// bearing), as the command line and the browser set them.
    pub fn with_diagonals(self, r: [f64; 3], q: [f64; 2]) -> Self {
        Settings {
            r: Matrix3::from_diagonal(&Vector3::from(r)),
            q: Matrix2::from_diagonal(&Vector2::from(q)),
            ..self
        }
    }

    /// Checks every setting, naming the first that is out of its domain.
    pub fn validate(&self) -> Result<(), Error> {
        positive_semidefinite("R", self.r.as_slice(), 3)?;
        positive_semidefinite("Sigma0", self.sigma0.as_slice(), 3)?;
        positive_semidefinite("Q", self.q.as_slice(), 2)?;
        if self.q.determinant() <= 0.0 {
            return Err(Error::invalid(
                "Q",
                "must be positive definite (invertible)",
            ));
        }
        if !(self.delta_m > 0.0 && self.delta_m <= 1.0) {
            return Err(Error::invalid(
                "delta_M",
                format!("must lie in (0, 1], got {}", self.delta_m),
            ));
        }
        if !self.mu0.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid("mu0", "must be finite"));
        }
        let robot = &self.robot;
        for (field, value) in [
            ("E_T", robot.ticks_per_revolution),
            ("B", robot.wheel_base),
            ("R_R", robot.right_radius),
            ("R_L", robot.left_radius),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(
                    field,
                    format!("must be a positive number, got {value}"),
                ));
            }
        }
        Ok(())
    }
}

fn positive_semidefinite(field: &str, a: &[f64], n: usize) -> Result<(), Error> {
    if !a.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(field, "must be finite"));
    }
    for i in 0..n {
        for j in 0..i {
            if a[i * n + j] != a[j * n + i] {
                return Err(Error::invalid(field, "must be symmetric"));
            }
        }
    }
    let eigenvalues = nalgebra::DMatrix::from_column_slice(n, n, a).symmetric_eigenvalues();
    if eigenvalues.iter().any(|&e| e < 0.0) {
        return Err(Error::invalid(field, "must be positive semi-definite"));
    }
    Ok(())
}

/// The filter's belief after one time step, beside the truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepEstimate {
    pub t: f64,
    pub mu: Vector3<f64>,
    pub sigma: Matrix3<f64>,
    pub truth: Vector3<f64>,
    /// `mu - truth`, heading difference wrapped.
    pub error: Vector3<f64>,
    /// Where the encoder odometry alone puts the robot (dead reckoning from `mu0`).
    pub odometry: Vector3<f64>,
}

impl StepEstimate {
    /// The filter's standard deviations of x, y and theta: the square roots of the
    /// diagonal of Sigma.
    pub fn std_dev(&self) -> Vector3<f64> {
        self.sigma.diagonal().map(f64::sqrt)
    }
}

/// What the filter made of one reading.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadingOutcome {
    /// The index of the time step.
    pub step: usize,
    /// The landmark (map index) the reading was associated with.
    pub c: usize,
    /// The landmark (map index) that truly produced it, from the sensor file.
    pub truth: usize,
    /// The reading, `[range, bearing]`.
    pub z: Vector2<f64>,
    /// The squared Mahalanobis distance to the associated landmark.
    pub mahalanobis: f64,
    pub outlier: bool,
}

/// The figures the lab's script printed, plus the rejection count.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Mean of `mu - truth` over the run, heading difference wrapped.
    pub mean_error: Vector3<f64>,
    /// Mean of `|mu - truth|`: the lab's pass criterion.
    pub mean_absolute_error: Vector3<f64>,
    pub max_absolute_error: Vector3<f64>,
    pub steps: usize,
    pub readings: usize,
    pub rejected: usize,
    /// Accepted readings associated with another landmark than the one that produced them.
    pub misassociated: usize,
    /// `Lambda_M`, the outlier threshold used.
    pub lambda_m: f64,
}

impl Summary {
    /// The figures as the lab's script printed them, and the rejections.
    pub fn report(&self) -> String {
        let triple = |v: &Vector3<f64>| format!("({:.6}, {:.6}, {:.6})", v.x, v.y, v.z);
        format!(
            "mean error (x, y, theta):          {}\nmean absolute error (x, y, theta): {}\nrejected readings: {} of {}\n",
            triple(&self.mean_error),
            triple(&self.mean_absolute_error),
            self.rejected,
            self.readings
        )
    }
}

/// A whole run of the filter over a data set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Run {
    pub steps: Vec<StepEstimate>,
    pub readings: Vec<ReadingOutcome>,
    pub summary: Summary,
}

/// Runs the filter loop of the lab over a data set: odometry from the encoders (eq. 4),
/// prediction (Alg. 1), then per time step either the sequential association and update
/// of each reading (Algs. 2-3) or the batch association and update (Alg. 4).
pub fn run(data: &Dataset, settings: &Settings) -> Result<Run, Error> {
    settings.validate()?;
    let lambda = lambda_m(settings.delta_m);
    let landmarks = data.map.landmarks();
    let mut belief = Belief::new(settings.mu0, settings.sigma0);
    let mut beliefs = Vec::with_capacity(data.log.steps.len());
    let mut outcomes = Vec::with_capacity(data.log.readings());
    let mut matches: Vec<Match> = Vec::new();

    for (k, (step, (delta_right, delta_left, delta_t))) in data
        .log
        .steps
        .iter()
        .zip(increments(&data.log.steps))
        .enumerate()
    {
        let u = calculate_odometry(
            delta_right,
            delta_left,
            &settings.robot,
            delta_t,
            &belief.mu,
        );
        let mut bar = predict(&belief, &u, &settings.r);

        let associate = |bar: &Belief, z: &Vector2<f64>, truth: usize| {
            if settings.known_associations {
                let cand = candidate(bar, z, &landmarks[truth].position, &settings.q);
                Match {
                    c: truth,
                    outlier: cand.mahalanobis >= lambda,
                    candidate: cand,
                }
            } else {
                most_likely(bar, z, &data.map, lambda, &settings.q)
            }
        };
        let singular = || {
            Error::invalid(
                "data",
                format!(
                    "the innovation covariance became singular at time step {}",
                    k + 1
                ),
            )
        };

        matches.clear();
        match settings.mode {
            UpdateMode::Sequential => {
                for reading in &step.readings {
                    let m = associate(&bar, &reading.z, reading.landmark);
                    if !m.outlier {
                        let cand = &m.candidate;
                        bar = update(&bar, &cand.h, &cand.s, &cand.nu).ok_or_else(singular)?;
                    }
                    matches.push(m);
                }
            }
            UpdateMode::Batch => {
                matches.extend(
                    step.readings
                        .iter()
                        .map(|reading| associate(&bar, &reading.z, reading.landmark)),
                );
                let inliers = matches
                    .iter()
                    .filter(|m| !m.outlier)
                    .map(|m| (&m.candidate.h, &m.candidate.nu));
                bar = batch_update(&bar, inliers, &settings.q).ok_or_else(singular)?;
            }
        }
        belief = bar;
        beliefs.push(belief);
        outcomes.extend(matches.iter().map(|m| Decision {
            c: m.c,
            outlier: m.outlier,
            mahalanobis: m.candidate.mahalanobis,
        }));
    }
    Ok(assemble(
        data,
        &settings.robot,
        settings.mu0,
        lambda,
        &beliefs,
        &outcomes,
    ))
}

/// What became of one reading: the landmark it was associated with, whether it was
/// rejected, and its Mahalanobis distance (NaN when unknown).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decision {
    pub c: usize,
    pub outlier: bool,
    pub mahalanobis: f64,
}

/// The encoder ticks and the seconds since the previous step, for every step; zero for
/// the first (so that its control is zero).
pub fn increments(steps: &[Step]) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
    let previous = std::iter::once(None).chain(steps.iter().map(Some));
    steps
        .iter()
        .zip(previous)
        .map(|(step, previous)| match previous {
            Some(p) => (
                step.encoders.right - p.encoders.right,
                step.encoders.left - p.encoders.left,
                step.t - p.t,
            ),
            None => (0.0, 0.0, 0.0),
        })
}

/// A whole run from the belief after every step and the association of every reading
/// (in the order of the file), whoever computed them: the errors against the ground truth,
/// the odometry-only trajectory from `mu0` for plotting, and the summary.
pub fn assemble(
    data: &Dataset,
    robot: &Robot,
    mu0: Vector3<f64>,
    lambda_m: f64,
    beliefs: &[Belief],
    decisions: &[Decision],
) -> Run {
    let mut dead_reckoning = mu0;
    let steps: Vec<StepEstimate> = data
        .log
        .steps
        .iter()
        .zip(increments(&data.log.steps))
        .zip(beliefs)
        .map(|((step, (delta_right, delta_left, delta_t)), belief)| {
            dead_reckoning +=
                calculate_odometry(delta_right, delta_left, robot, delta_t, &dead_reckoning);
            dead_reckoning.z = wrap(dead_reckoning.z);
            StepEstimate {
                t: step.t,
                mu: belief.mu,
                sigma: belief.sigma,
                truth: step.truth,
                error: pose_error(&belief.mu, &step.truth),
                odometry: dead_reckoning,
            }
        })
        .collect();
    let readings: Vec<ReadingOutcome> = data
        .log
        .steps
        .iter()
        .enumerate()
        .flat_map(|(k, step)| step.readings.iter().map(move |reading| (k, reading)))
        .zip(decisions)
        .map(|((k, reading), a)| ReadingOutcome {
            step: k,
            c: a.c,
            truth: reading.landmark,
            z: reading.z,
            mahalanobis: a.mahalanobis,
            outlier: a.outlier,
        })
        .collect();
    let summary = summarise(&steps, &readings, lambda_m);
    Run {
        steps,
        readings,
        summary,
    }
}

/// `estimate - truth`, the heading difference wrapped.
fn pose_error(estimate: &Vector3<f64>, truth: &Vector3<f64>) -> Vector3<f64> {
    let mut error = estimate - truth;
    error.z = difference(estimate.z, truth.z);
    error
}

fn summarise(steps: &[StepEstimate], readings: &[ReadingOutcome], lambda_m: f64) -> Summary {
    let n = steps.len() as f64;
    let mut mean_error = Vector3::zeros();
    let mut mean_absolute_error = Vector3::zeros();
    let mut max_absolute_error = Vector3::<f64>::zeros();
    for step in steps {
        let abs = step.error.abs();
        mean_error += step.error / n;
        mean_absolute_error += abs / n;
        max_absolute_error = max_absolute_error.sup(&abs);
    }
    Summary {
        mean_error,
        mean_absolute_error,
        max_absolute_error,
        steps: steps.len(),
        readings: readings.len(),
        rejected: readings.iter().filter(|r| r.outlier).count(),
        misassociated: readings
            .iter()
            .filter(|r| !r.outlier && r.c != r.truth)
            .count(),
        lambda_m,
    }
}
