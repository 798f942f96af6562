//! The student functions of the odometry exercise, in the shapes of its contract
//! (`web/starter.js`): the pose is `[x, y, theta]`, matrices are arrays of
//! rows, the wheels come right first. A [`Call`] is one call of one function with its
//! arguments; [`reference`] answers it with the model of [`crate::odometry`].

use super::hints::{HintKind, diagnose};
use crate::grading::{Contract, Hint, Kind, Mismatch, Shape, matrix, matrix_of, rows};
use crate::odometry::{
    Increment, increment_jacobian, pose_jacobian, propagate_through, step, wheel_noise,
};
use crate::{Error, Exercise};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use serde_json::Value;

pub type Vec3 = [f64; 3];
pub type Mat2 = [[f64; 2]; 2];
pub type Mat3 = [[f64; 3]; 3];
pub type Mat3x2 = [[f64; 2]; 3];

/// What a student function returns, in the contract's shapes; as JSON the bare value.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Answer {
    /// `odometry_step`'s p_next.
    Pose(Vec3),
    /// `pose_jacobian`'s F_p, `propagate`'s Sigma_p_next.
    Matrix3(Mat3),
    /// `increment_jacobian`'s F_delta.
    Matrix3x2(Mat3x2),
    /// `wheel_noise`'s Sigma_delta.
    Matrix2(Mat2),
}

/// One call of a student function, arguments named and ordered as in the contract.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "function", content = "args", rename_all = "snake_case")]
pub enum Call {
    OdometryStep {
        p: Vec3,
        ds_r: f64,
        ds_l: f64,
        b: f64,
    },
    PoseJacobian {
        p: Vec3,
        ds_r: f64,
        ds_l: f64,
        b: f64,
    },
    IncrementJacobian {
        p: Vec3,
        ds_r: f64,
        ds_l: f64,
        b: f64,
    },
    WheelNoise {
        ds_r: f64,
        ds_l: f64,
        k_r: f64,
        k_l: f64,
    },
    Propagate {
        #[serde(rename = "Sigma_p")]
        sigma_p: Mat3,
        #[serde(rename = "F_p")]
        f_p: Mat3,
        #[serde(rename = "F_delta")]
        f_delta: Mat3x2,
        #[serde(rename = "Sigma_delta")]
        sigma_delta: Mat2,
    },
}

/// The student functions, in the order the exercise introduces them.
pub const FUNCTIONS: &[&str] = &[
    "odometry_step",
    "pose_jacobian",
    "increment_jacobian",
    "wheel_noise",
    "propagate",
];

impl Contract for Call {
    const EXERCISE: Exercise = Exercise::Odometry;
    const FUNCTIONS: &'static [&'static str] = FUNCTIONS;
    type Answer = Answer;
    type Mistake = HintKind;
    const KEEPS_STATE: HintKind = HintKind::KeepsState;

    fn function(&self) -> &'static str {
        FUNCTIONS[match self {
            Call::OdometryStep { .. } => 0,
            Call::PoseJacobian { .. } => 1,
            Call::IncrementJacobian { .. } => 2,
            Call::WheelNoise { .. } => 3,
            Call::Propagate { .. } => 4,
        }]
    }

    fn output_shape(&self) -> (&'static str, Shape) {
        output_shape(self)
    }

    fn reference(&self) -> Result<Answer, Error> {
        Ok(reference(self))
    }

    fn diagnose(&self, expected: &Answer, got: &Value, mismatches: &[Mismatch]) -> Option<Hint> {
        diagnose(self, expected, got, mismatches)
    }
}

/// The name of a function's output in the contract (the root of every path into it) and
/// its shape: the new pose with its heading wrapped, the Jacobians, the wheel noise, and
/// the propagated covariance, which must be exactly symmetric (the model symmetrises it).
pub fn output_shape(call: &Call) -> (&'static str, Shape) {
    match call {
        Call::OdometryStep { .. } => (
            "p_next",
            Shape::Array(vec![
                Shape::Scalar(Kind::Number),
                Shape::Scalar(Kind::Number),
                Shape::Scalar(Kind::Bearing),
            ]),
        ),
        Call::PoseJacobian { .. } => ("F_p", matrix(3, 3)),
        Call::IncrementJacobian { .. } => ("F_delta", matrix(3, 2)),
        Call::WheelNoise { .. } => ("Sigma_delta", matrix(2, 2)),
        Call::Propagate { .. } => ("Sigma_p_next", Shape::Symmetric(3)),
    }
}

/// The reference answer to a call, from [`crate::odometry`], in the contract's shapes.
/// Every call has one: the model is defined for any numbers.
pub fn reference(call: &Call) -> Answer {
    match call {
        Call::OdometryStep { p, ds_r, ds_l, b } => {
            Answer::Pose(step(&Vector3::from(*p), Increment::new(*ds_r, *ds_l), *b).into())
        }
        Call::PoseJacobian { p, ds_r, ds_l, b } => Answer::Matrix3(rows(&pose_jacobian(
            &Vector3::from(*p),
            Increment::new(*ds_r, *ds_l),
            *b,
        ))),
        Call::IncrementJacobian { p, ds_r, ds_l, b } => Answer::Matrix3x2(rows(
            &increment_jacobian(&Vector3::from(*p), Increment::new(*ds_r, *ds_l), *b),
        )),
        Call::WheelNoise {
            ds_r,
            ds_l,
            k_r,
            k_l,
        } => Answer::Matrix2(rows(&wheel_noise(Increment::new(*ds_r, *ds_l), *k_r, *k_l))),
        Call::Propagate {
            sigma_p,
            f_p,
            f_delta,
            sigma_delta,
        } => Answer::Matrix3(rows(&propagate_through(
            &matrix_of(sigma_p),
            &matrix_of(f_p),
            &matrix_of(f_delta),
            &matrix_of(sigma_delta),
        ))),
    }
}
