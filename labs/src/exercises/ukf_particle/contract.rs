//! The student functions of the exercise on the unscented Kalman filter and the particle
//! filter, in the shapes of its contract (`web/starter.js`): a pose is `[x, y, theta]`, a
//! control `[v, omega]`, a reading `[range, bearing]`, a post `[x, y]`; a cloud of
//! particles is an array of poses, matrices are arrays of rows. A [`Call`] is one call of
//! one function with its arguments; [`reference`] answers it with the model of
//! [`crate::mrclam`].

use super::hints::{HintKind, diagnose};
use crate::grading::{
    Contract, Hint, Kind, Mismatch, Shape, matrix, matrix_of, numbers, repeat, rows,
};
use crate::mrclam::belief::Belief;
use crate::mrclam::grid::Control;
use crate::mrclam::motion::{self, Noise};
use crate::mrclam::particle::{self, Particle};
use crate::mrclam::ukf::{self, BEARING, HEADING, SPREAD, Spread};
use crate::mrclam::{learn, sensor};
use crate::{Error, Exercise};
use nalgebra::{Matrix2, Vector2, Vector3};
use serde::{Deserialize, Serialize};
use serde_json::Value;

pub type Vec2 = [f64; 2];
pub type Vec3 = [f64; 3];
pub type Mat2 = [[f64; 2]; 2];
pub type Mat3 = [[f64; 3]; 3];

/// The sigma points and their weights.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SigmaPoints {
    /// The 2n + 1 points, one pose a row: mu first, then mu plus each column of the
    /// lower Cholesky factor of (n + lambda) Sigma, then mu minus each.
    #[serde(rename = "X")]
    pub x: Vec<Vec3>,
    pub wm: Vec<f64>,
    pub wc: Vec<f64>,
}

/// A belief after the prediction.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Prediction {
    pub mu_bar: Vec3,
    pub sigma_bar: Mat3,
}

/// A belief after the unscented update, and the reading's squared Mahalanobis distance.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Corrected {
    pub mu: Vec3,
    pub sigma: Mat3,
    pub d2: f64,
}

/// A cloud's mean and covariance.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Estimate {
    pub mu: Vec3,
    pub sigma: Mat3,
}

/// What a student function returns, in the contract's shapes; as JSON the bare value.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Answer {
    /// `motion`'s pose.
    Pose(Vec3),
    /// `process_noise`'s R.
    Matrix3(Mat3),
    SigmaPoints(SigmaPoints),
    Prediction(Prediction),
    Corrected(Corrected),
    /// `sample_motion`'s particles.
    Particles(Vec<Vec3>),
    /// `particle_weights`' weights.
    Weights(Vec<f64>),
    /// `needs_resampling`'s answer.
    Flag(bool),
    /// `low_variance_resample`'s indices.
    Indices(Vec<usize>),
    Estimate(Estimate),
    /// `measurement_noise`'s Q.
    Matrix2(Mat2),
    /// `learn_alphas`' alphas.
    Alphas([f64; 4]),
}

/// One call of a student function, arguments named and ordered as in the contract.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "function", content = "args", rename_all = "snake_case")]
pub enum Call {
    Motion {
        pose: Vec3,
        u: Vec2,
        dt: f64,
    },
    ProcessNoise {
        mu: Vec3,
        u: Vec2,
        dt: f64,
        alphas: [f64; 4],
    },
    SigmaPoints {
        mu: Vec3,
        sigma: Mat3,
        alpha: f64,
        beta: f64,
        kappa: f64,
    },
    UkfPredict {
        mu: Vec3,
        sigma: Mat3,
        u: Vec2,
        dt: f64,
        #[serde(rename = "R")]
        r: Mat3,
    },
    UkfUpdate {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        z: Vec2,
        landmark: Vec2,
        #[serde(rename = "Q")]
        q: Mat2,
    },
    SampleMotion {
        particles: Vec<Vec3>,
        u: Vec2,
        dt: f64,
        alphas: [f64; 4],
        normals: Vec<Vec2>,
    },
    ParticleWeights {
        particles: Vec<Vec3>,
        weights: Vec<f64>,
        z: Vec2,
        landmark: Vec2,
        #[serde(rename = "Q")]
        q: Mat2,
    },
    NeedsResampling {
        weights: Vec<f64>,
    },
    LowVarianceResample {
        weights: Vec<f64>,
        r: f64,
    },
    ParticleEstimate {
        particles: Vec<Vec3>,
        weights: Vec<f64>,
    },
    MeasurementNoise {
        residuals: Vec<Vec2>,
    },
    LearnAlphas {
        commanded: Vec<Vec2>,
        implied: Vec<Vec2>,
    },
}

/// The student functions, in the order the exercise introduces them.
pub const FUNCTIONS: &[&str] = &[
    "motion",
    "process_noise",
    "sigma_points",
    "ukf_predict",
    "ukf_update",
    "sample_motion",
    "particle_weights",
    "needs_resampling",
    "low_variance_resample",
    "particle_estimate",
    "measurement_noise",
    "learn_alphas",
];

/// The share of the particles' count under which the effective sample size calls for
/// resampling.
pub const RESAMPLE_BELOW: f64 = 0.5;

impl Contract for Call {
    const EXERCISE: Exercise = Exercise::UkfParticle;
    const FUNCTIONS: &'static [&'static str] = FUNCTIONS;
    type Answer = Answer;
    type Mistake = HintKind;
    const KEEPS_STATE: HintKind = HintKind::KeepsState;

    fn function(&self) -> &'static str {
        FUNCTIONS[match self {
            Call::Motion { .. } => 0,
            Call::ProcessNoise { .. } => 1,
            Call::SigmaPoints { .. } => 2,
            Call::UkfPredict { .. } => 3,
            Call::UkfUpdate { .. } => 4,
            Call::SampleMotion { .. } => 5,
            Call::ParticleWeights { .. } => 6,
            Call::NeedsResampling { .. } => 7,
            Call::LowVarianceResample { .. } => 8,
            Call::ParticleEstimate { .. } => 9,
            Call::MeasurementNoise { .. } => 10,
            Call::LearnAlphas { .. } => 11,
        }]
    }

    fn output_shape(&self) -> (&'static str, Shape) {
        output_shape(self)
    }

    fn reference(&self) -> Result<Answer, Error> {
        reference(self)
    }

    fn diagnose(&self, expected: &Answer, got: &Value, mismatches: &[Mismatch]) -> Option<Hint> {
        diagnose(self, expected, got, mismatches)
    }
}

/// The name of a function's output in the contract and its shape: poses whose heading is
/// wrapped where the contract wraps it (after a step, after an update) and compared
/// modulo 2 pi where it is an atan2 (which may give +pi) or a sigma point's; the
/// covariances the UKF symmetrises exactly symmetric.
pub fn output_shape(call: &Call) -> (&'static str, Shape) {
    let number = Shape::Scalar(Kind::Number);
    match call {
        Call::Motion { .. } => ("pose", wrapped_pose()),
        Call::ProcessNoise { .. } => ("R", matrix(3, 3)),
        Call::SigmaPoints { .. } => (
            "",
            Shape::Object(vec![
                ("X", repeat(ukf::POINTS, pose())),
                ("wm", numbers(ukf::POINTS)),
                ("wc", numbers(ukf::POINTS)),
            ]),
        ),
        Call::UkfPredict { .. } => (
            "",
            Shape::Object(vec![("mu_bar", pose()), ("sigma_bar", Shape::Symmetric(3))]),
        ),
        Call::UkfUpdate { .. } => (
            "",
            Shape::Object(vec![
                ("mu", wrapped_pose()),
                ("sigma", Shape::Symmetric(3)),
                ("d2", number),
            ]),
        ),
        Call::SampleMotion { particles, .. } => ("particles", repeat(particles.len(), pose())),
        Call::ParticleWeights { weights, .. } => ("weights", numbers(weights.len())),
        Call::NeedsResampling { .. } => ("resample", Shape::Scalar(Kind::Flag)),
        Call::LowVarianceResample { weights, .. } => {
            ("indices", repeat(weights.len(), Shape::Scalar(Kind::Index)))
        }
        Call::ParticleEstimate { .. } => (
            "",
            Shape::Object(vec![("mu", pose()), ("sigma", matrix(3, 3))]),
        ),
        Call::MeasurementNoise { .. } => ("Q", matrix(2, 2)),
        Call::LearnAlphas { .. } => ("alphas", numbers(4)),
    }
}

/// A pose or sigma point: its heading compared modulo 2 pi.
fn pose() -> Shape {
    crate::grading::pose()
}

/// A pose whose heading the contract wraps to [-pi, pi).
fn wrapped_pose() -> Shape {
    let number = Shape::Scalar(Kind::Number);
    Shape::Array(vec![number.clone(), number, Shape::Scalar(Kind::Bearing)])
}

/// A control of the model from the contract's `[v, omega]`.
pub fn control(u: &Vec2) -> Control {
    Control {
        v: u[0],
        omega: u[1],
    }
}

/// The control noise of `alphas` (the camera's plays no part).
pub fn control_noise(alphas: &[f64; 4]) -> Noise {
    Noise {
        alphas: *alphas,
        measurement: Matrix2::zeros(),
    }
}

/// A belief of the model.
pub fn belief(mu: &Vec3, sigma: &Mat3) -> Belief {
    Belief {
        mean: Vector3::from(*mu),
        covariance: matrix_of(sigma),
    }
}

/// The particles of the model at the contract's poses.
pub fn cloud(poses: &[Vec3]) -> Vec<Particle> {
    poses
        .iter()
        .map(|p| Particle::new(Vector3::from(*p)))
        .collect()
}

/// The spread of the sigma points of a call.
pub fn spread(alpha: f64, beta: f64, kappa: f64) -> Spread {
    Spread { alpha, beta, kappa }
}

/// The (commanded, implied) controls of the model from the contract's lists.
pub fn pairs(commanded: &[Vec2], implied: &[Vec2]) -> Vec<(Control, Control)> {
    commanded
        .iter()
        .zip(implied)
        .map(|(u, m)| (control(u), control(m)))
        .collect()
}

fn not_positive_definite(field: &str) -> Error {
    Error::invalid(field, "not positive definite")
}

/// The reference answer to a call, from [`crate::mrclam`], in the contract's shapes. A
/// covariance that has no Cholesky factor, or an innovation covariance no inverse, has
/// none.
pub fn reference(call: &Call) -> Result<Answer, Error> {
    Ok(match call {
        Call::Motion { pose, u, dt } => {
            Answer::Pose(motion::step(&Vector3::from(*pose), control(u), *dt).into())
        }
        Call::ProcessNoise { mu, u, dt, alphas } => Answer::Matrix3(rows(
            &control_noise(alphas).process(&Vector3::from(*mu), control(u), *dt),
        )),
        Call::SigmaPoints {
            mu,
            sigma,
            alpha,
            beta,
            kappa,
        } => {
            let spread = spread(*alpha, *beta, *kappa);
            let points = spread
                .points(&belief(mu, sigma))
                .ok_or_else(|| not_positive_definite("sigma"))?;
            let (wm, wc) = spread.weights();
            Answer::SigmaPoints(SigmaPoints {
                x: points.iter().map(|&p| p.into()).collect(),
                wm: wm.to_vec(),
                wc: wc.to_vec(),
            })
        }
        Call::UkfPredict {
            mu,
            sigma,
            u,
            dt,
            r,
        } => {
            let arc = |p: &Vector3<f64>| motion::step(p, control(u), *dt);
            let (predicted, _) =
                ukf::predict(&SPREAD, &belief(mu, sigma), arc, &matrix_of(r), HEADING)
                    .ok_or_else(|| not_positive_definite("sigma"))?;
            Answer::Prediction(Prediction {
                mu_bar: predicted.mean.into(),
                sigma_bar: rows(&predicted.covariance),
            })
        }
        Call::UkfUpdate {
            mu_bar,
            sigma_bar,
            z,
            landmark,
            q,
        } => {
            let post = Vector2::from(*landmark);
            let camera = |p: &Vector3<f64>| sensor::expected(p, &post);
            let (corrected, d2) = ukf::correct(
                &SPREAD,
                &belief(mu_bar, sigma_bar),
                camera,
                (&Vector2::from(*z), &matrix_of(q)),
                (HEADING, BEARING),
            )
            .ok_or_else(|| not_positive_definite("sigma_bar"))?;
            Answer::Corrected(Corrected {
                mu: corrected.mean.into(),
                sigma: rows(&corrected.covariance),
                d2,
            })
        }
        Call::SampleMotion {
            particles,
            u,
            dt,
            alphas,
            normals,
        } => {
            if normals.len() != particles.len() {
                return Err(Error::invalid("normals", "one pair for each particle"));
            }
            let u = control(u);
            let sd = control_noise(alphas).control_sd(u);
            Answer::Particles(
                cloud(particles)
                    .iter()
                    .zip(normals)
                    .map(|(p, n)| particle::moved(p, u, sd, *n, *dt).pose.into())
                    .collect(),
            )
        }
        Call::ParticleWeights {
            particles,
            weights,
            z,
            landmark,
            q,
        } => {
            let r_inverse = matrix_of(q)
                .try_inverse()
                .ok_or_else(|| Error::invalid("Q", "has no inverse"))?;
            let mut weights = weights.clone();
            particle::weigh(
                &cloud(particles),
                &mut weights,
                (&Vector2::from(*z), &Vector2::from(*landmark)),
                &r_inverse,
            );
            Answer::Weights(weights)
        }
        Call::NeedsResampling { weights } => {
            Answer::Flag(particle::needs_resampling(weights, RESAMPLE_BELOW))
        }
        Call::LowVarianceResample { weights, r } => {
            Answer::Indices(particle::low_variance(weights, *r))
        }
        Call::ParticleEstimate { particles, weights } => {
            let estimate = particle::estimate(&cloud(particles), weights);
            Answer::Estimate(Estimate {
                mu: estimate.mean.into(),
                sigma: rows(&estimate.covariance),
            })
        }
        Call::MeasurementNoise { residuals } => {
            let residuals: Vec<Vector2<f64>> = residuals.iter().map(|&r| r.into()).collect();
            let q = learn::measurement(&residuals)
                .ok_or_else(|| Error::invalid("residuals", "they make no covariance"))?;
            Answer::Matrix2(rows(&q))
        }
        Call::LearnAlphas { commanded, implied } => {
            if commanded.len() != implied.len() {
                return Err(Error::invalid("implied", "one for each command"));
            }
            Answer::Alphas(learn::alphas(&pairs(commanded, implied)))
        }
    })
}
