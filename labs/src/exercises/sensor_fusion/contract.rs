//! The student functions of the sensor-fusion exercise, in the shapes of its contract
//! (`web/starter.js`): a pose is `[x, y, theta]`, a platform's reading `[x, y, I]`,
//! matrices are arrays of rows. A [`Call`] is one call of one function with its
//! arguments; [`reference`] answers it with the model of [`crate::fusion`].

use super::hints::{HintKind, diagnose};
use crate::fusion::Settings;
use crate::fusion::filter::{self, Updated, in_view, increment, measurement_noise};
use crate::fusion::sensor::{self, Measurement, NoiseModel, Platform};
use crate::grading::{Contract, Hint, Kind, Mismatch, Shape, matrix, matrix_of, pose, rows};
use crate::{Error, Exercise};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use serde_json::Value;

pub type Vec3 = [f64; 3];
pub type Mat3 = [[f64; 3]; 3];
/// A platform's reading: `[x, y, I]`, its position (metres) and intensity.
pub type PlatformReading = [f64; 3];

/// A belief after the prediction.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Prediction {
    pub mu_bar: Vec3,
    pub sigma_bar: Mat3,
}

/// A belief after the update.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Posterior {
    pub mu: Vec3,
    pub sigma: Mat3,
}

/// What a student function returns, in the contract's shapes; as JSON the bare value.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Answer {
    /// `combine_platforms`' z.
    Pose(Vec3),
    /// `heading_sigma`'s sigma_theta, `mahalanobis`' d2.
    Number(f64),
    /// `measurement_noise`'s Q.
    Matrix3(Mat3),
    /// `in_field_of_view`'s answer.
    Flag(bool),
    Prediction(Prediction),
    Posterior(Posterior),
}

/// One call of a student function, arguments named and ordered as in the contract.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "function", content = "args", rename_all = "snake_case")]
pub enum Call {
    CombinePlatforms {
        p1: PlatformReading,
        p2: PlatformReading,
    },
    HeadingSigma {
        p1: PlatformReading,
        p2: PlatformReading,
        c_xy: f64,
    },
    MeasurementNoise {
        p1: PlatformReading,
        p2: PlatformReading,
        c_xy: f64,
    },
    InFieldOfView {
        z: Vec3,
        radius: f64,
    },
    Predict {
        mu: Vec3,
        sigma: Mat3,
        odom_prev: Vec3,
        odom: Vec3,
        k_xy: f64,
        k_theta: f64,
    },
    Mahalanobis {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        z: Vec3,
        #[serde(rename = "Q")]
        q: Mat3,
    },
    Update {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        z: Vec3,
        #[serde(rename = "Q")]
        q: Mat3,
    },
}

/// The student functions, in the order the exercise introduces them.
pub const FUNCTIONS: &[&str] = &[
    "combine_platforms",
    "heading_sigma",
    "measurement_noise",
    "in_field_of_view",
    "predict",
    "mahalanobis",
    "update",
];

impl Contract for Call {
    const EXERCISE: Exercise = Exercise::SensorFusion;
    const FUNCTIONS: &'static [&'static str] = FUNCTIONS;
    type Answer = Answer;
    type Mistake = HintKind;
    const KEEPS_STATE: HintKind = HintKind::KeepsState;

    fn function(&self) -> &'static str {
        FUNCTIONS[match self {
            Call::CombinePlatforms { .. } => 0,
            Call::HeadingSigma { .. } => 1,
            Call::MeasurementNoise { .. } => 2,
            Call::InFieldOfView { .. } => 3,
            Call::Predict { .. } => 4,
            Call::Mahalanobis { .. } => 5,
            Call::Update { .. } => 6,
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

/// The name of a function's output in the contract (the root of every path into it) and
/// its shape: the measured pose (its heading compared modulo 2 pi: `atan2` may give +pi),
/// the heading's standard deviation, the measurement noise, whether a pose is in view,
/// the beliefs (headings wrapped, covariances exactly symmetric, as the model makes them)
/// and the squared Mahalanobis distance.
pub fn output_shape(call: &Call) -> (&'static str, Shape) {
    let number = Shape::Scalar(Kind::Number);
    match call {
        Call::CombinePlatforms { .. } => ("z", pose()),
        Call::HeadingSigma { .. } => ("sigma_theta", number),
        Call::MeasurementNoise { .. } => ("Q", matrix(3, 3)),
        Call::InFieldOfView { .. } => ("in_view", Shape::Scalar(Kind::Flag)),
        Call::Predict { .. } => (
            "",
            Shape::Object(vec![
                ("mu_bar", wrapped_pose()),
                ("sigma_bar", Shape::Symmetric(3)),
            ]),
        ),
        Call::Mahalanobis { .. } => ("d2", number),
        Call::Update { .. } => (
            "",
            Shape::Object(vec![("mu", wrapped_pose()), ("sigma", Shape::Symmetric(3))]),
        ),
    }
}

/// A belief's pose, its heading wrapped to [-pi, pi) as the contract says.
fn wrapped_pose() -> Shape {
    let number = Shape::Scalar(Kind::Number);
    Shape::Array(vec![number.clone(), number, Shape::Scalar(Kind::Bearing)])
}

/// A platform of the model from its reading.
pub fn platform(reading: &PlatformReading) -> Platform {
    Platform {
        x: reading[0],
        y: reading[1],
        intensity: reading[2],
    }
}

/// The platforms' measurement with the noise model of `c_xy` (`c_theta` plays no part
/// where the platforms are known).
pub fn measured(p1: &PlatformReading, p2: &PlatformReading, c_xy: f64) -> Measurement {
    let noise = NoiseModel {
        c_xy,
        ..NoiseModel::default()
    };
    noise.measure(&[platform(p1), platform(p2)])
}

/// The reference answer to a call, from [`crate::fusion`], in the contract's shapes. An
/// update whose innovation covariance has no inverse has none.
pub fn reference(call: &Call) -> Result<Answer, Error> {
    Ok(match call {
        Call::CombinePlatforms { p1, p2 } => {
            Answer::Pose(sensor::combine(&[platform(p1), platform(p2)]).into())
        }
        Call::HeadingSigma { p1, p2, c_xy } => {
            let platforms = [platform(p1), platform(p2)];
            Answer::Number(sensor::heading_sigma(
                &platforms,
                platforms.map(|p| c_xy / p.intensity),
            ))
        }
        Call::MeasurementNoise { p1, p2, c_xy } => {
            Answer::Matrix3(rows(&measurement_noise(&measured(p1, p2, *c_xy))))
        }
        Call::InFieldOfView { z, radius } => Answer::Flag(in_view(
            &Measurement {
                pose: *z,
                sigma_xy: 0.0,
                sigma_theta: 0.0,
            },
            *radius,
        )),
        Call::Predict {
            mu,
            sigma,
            odom_prev,
            odom,
            k_xy,
            k_theta,
        } => {
            let settings = Settings {
                process_xy: *k_xy,
                process_theta: *k_theta,
                ..Settings::default()
            };
            let (mu_bar, sigma_bar) = filter::predict(
                &Vector3::from(*mu),
                &matrix_of(sigma),
                &increment(*odom_prev, *odom),
                &settings,
            );
            Answer::Prediction(Prediction {
                mu_bar: mu_bar.into(),
                sigma_bar: rows(&sigma_bar),
            })
        }
        Call::Mahalanobis {
            mu_bar,
            sigma_bar,
            z,
            q,
        } => Answer::Number(filter::mahalanobis(
            &Vector3::from(*mu_bar),
            &matrix_of(sigma_bar),
            &Vector3::from(*z),
            &matrix_of(q),
        )),
        Call::Update {
            mu_bar,
            sigma_bar,
            z,
            q,
        } => match filter::update(
            &Vector3::from(*mu_bar),
            &matrix_of(sigma_bar),
            &Vector3::from(*z),
            &matrix_of(q),
            f64::INFINITY,
        ) {
            Updated::Corrected { mu, sigma, .. } => Answer::Posterior(Posterior {
                mu: mu.into(),
                sigma: rows(&sigma),
            }),
            Updated::Rejected { .. } => {
                return Err(Error::invalid("S", "Sigma_bar + Q has no inverse"));
            }
        },
    })
}
