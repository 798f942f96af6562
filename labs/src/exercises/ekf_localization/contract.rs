//! The student functions of the EKF localization exercise, in the shapes of the public
//! contract (`DESIGN.md`, "The student contract"): vectors are arrays, matrices arrays of rows, the map `M` is
//! 2 x N, indices are 0-based. A [`Call`] is one call of one function with its arguments;
//! [`reference`] answers it with the reference implementation, in the same shapes.

use super::hints::{HintKind, diagnose};
use crate::ekf::{self, Belief, Landmark, Map, Robot};
use crate::grading::{
    self, Contract, Hint, Kind, Mismatch, Shape, matrix, matrix_of, pose, range_bearing, repeat,
    rows,
};
use crate::{Error, Exercise};
use nalgebra::{Matrix2, Matrix2x3, Vector2, Vector3};
use serde::{Deserialize, Serialize};
use serde_json::Value;

pub type Vec2 = [f64; 2];
pub type Vec3 = [f64; 3];
pub type Mat2 = [[f64; 2]; 2];
pub type Mat3 = [[f64; 3]; 3];
pub type Mat2x3 = [[f64; 3]; 2];
/// A 2 x n matrix: row 0 and row 1 (the landmark map `M`; the readings `z`).
pub type TwoRows = [Vec<f64>; 2];

/// What a student function returns, in the contract's shapes; as JSON the bare value.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Answer {
    /// `calculate_odometry`'s u = [dx, dy, dtheta].
    Odometry(Vec3),
    /// `observation_model`'s z_hat = [range, bearing].
    Observation(Vec2),
    /// `jacobian_observation_model`'s H, 2 x 3.
    Jacobian(Mat2x3),
    Prediction(Prediction),
    Association(Association),
    BatchAssociation(BatchAssociation),
    /// What `update` and `batch_update` return.
    Posterior(Posterior),
}

/// `predict`'s belief before the readings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Prediction {
    pub mu_bar: Vec3,
    pub sigma_bar: Mat3,
}

/// `associate`'s landmark for one reading, whether it is an outlier, and what every
/// landmark predicts (its innovation, its covariance and its Jacobian).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Association {
    pub c: usize,
    pub outlier: bool,
    pub nu: Vec<Vec2>,
    #[serde(rename = "S")]
    pub s: Vec<Mat2>,
    #[serde(rename = "H")]
    pub h: Vec<Mat2x3>,
}

/// `batch_associate`'s landmark and outlier flag of every reading, and the stacked
/// innovations (2n) and Jacobians (2n x 3) of the readings' landmarks.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BatchAssociation {
    pub c: Vec<usize>,
    pub outlier: Vec<bool>,
    pub nu_bar: Vec<f64>,
    #[serde(rename = "H_bar")]
    pub h_bar: Vec<Vec3>,
}

/// The belief after the readings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Posterior {
    pub mu: Vec3,
    pub sigma: Mat3,
}

impl Posterior {
    fn of(belief: &Belief) -> Answer {
        Answer::Posterior(Posterior {
            mu: belief.mu.into(),
            sigma: rows(&belief.sigma),
        })
    }
}

/// One call of a student function, arguments named and ordered as in the contract.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "function", content = "args", rename_all = "snake_case")]
pub enum Call {
    CalculateOdometry {
        #[serde(rename = "e_R")]
        e_r: f64,
        #[serde(rename = "e_L")]
        e_l: f64,
        #[serde(rename = "E_T")]
        e_t: f64,
        #[serde(rename = "B")]
        b: f64,
        #[serde(rename = "R_R")]
        r_r: f64,
        #[serde(rename = "R_L")]
        r_l: f64,
        delta_t: f64,
        mu: Vec3,
    },
    Predict {
        mu: Vec3,
        sigma: Mat3,
        u: Vec3,
        #[serde(rename = "R")]
        r: Mat3,
    },
    ObservationModel {
        x: Vec3,
        #[serde(rename = "M")]
        m: TwoRows,
        j: usize,
    },
    JacobianObservationModel {
        x: Vec3,
        #[serde(rename = "M")]
        m: TwoRows,
        j: usize,
        z_hat: Vec2,
    },
    Associate {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        z_i: Vec2,
        #[serde(rename = "M")]
        m: TwoRows,
        #[serde(rename = "Lambda_M", with = "grading::infinity")]
        lambda_m: f64,
        #[serde(rename = "Q")]
        q: Mat2,
    },
    BatchAssociate {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        z: TwoRows,
        #[serde(rename = "M")]
        m: TwoRows,
        #[serde(rename = "Lambda_M", with = "grading::infinity")]
        lambda_m: f64,
        #[serde(rename = "Q")]
        q: Mat2,
    },
    Update {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        #[serde(rename = "H")]
        h: Mat2x3,
        #[serde(rename = "S")]
        s: Mat2,
        nu: Vec2,
    },
    BatchUpdate {
        mu_bar: Vec3,
        sigma_bar: Mat3,
        #[serde(rename = "H_bar")]
        h_bar: Vec<Vec3>,
        #[serde(rename = "Q_bar")]
        q_bar: Vec<Vec<f64>>,
        nu_bar: Vec<f64>,
    },
}

/// The student functions, in the order the exercise introduces them.
pub const FUNCTIONS: &[&str] = &[
    "calculate_odometry",
    "predict",
    "observation_model",
    "jacobian_observation_model",
    "associate",
    "batch_associate",
    "update",
    "batch_update",
];

impl Contract for Call {
    const EXERCISE: Exercise = Exercise::EkfLocalization;
    const FUNCTIONS: &'static [&'static str] = FUNCTIONS;
    type Answer = Answer;
    type Mistake = HintKind;
    const KEEPS_STATE: HintKind = HintKind::StaleAssociation;

    fn function(&self) -> &'static str {
        FUNCTIONS[match self {
            Call::CalculateOdometry { .. } => 0,
            Call::Predict { .. } => 1,
            Call::ObservationModel { .. } => 2,
            Call::JacobianObservationModel { .. } => 3,
            Call::Associate { .. } => 4,
            Call::BatchAssociate { .. } => 5,
            Call::Update { .. } => 6,
            Call::BatchUpdate { .. } => 7,
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

/// The name of a function's output in the contract (the root of every path into it), and
/// its shape for this call.
fn output_shape(call: &Call) -> (&'static str, Shape) {
    match call {
        Call::CalculateOdometry { .. } => ("u", pose()),
        Call::Predict { .. } => (
            "",
            Shape::Object(vec![("mu_bar", pose()), ("sigma_bar", matrix(3, 3))]),
        ),
        Call::ObservationModel { .. } => ("z_hat", range_bearing()),
        Call::JacobianObservationModel { .. } => ("H", matrix(2, 3)),
        Call::Associate { m, .. } => {
            let n = m[0].len();
            (
                "",
                Shape::Object(vec![
                    ("c", Shape::Scalar(Kind::Index)),
                    ("outlier", Shape::Scalar(Kind::Flag)),
                    ("nu", repeat(n, range_bearing())),
                    ("S", repeat(n, matrix(2, 2))),
                    ("H", repeat(n, matrix(2, 3))),
                ]),
            )
        }
        Call::BatchAssociate { z, .. } => {
            let n = z[0].len();
            let nu_bar = (0..n)
                .flat_map(|_| [Shape::Scalar(Kind::Number), Shape::Scalar(Kind::Bearing)])
                .collect();
            (
                "",
                Shape::Object(vec![
                    ("c", repeat(n, Shape::Scalar(Kind::Index))),
                    ("outlier", repeat(n, Shape::Scalar(Kind::Flag))),
                    ("nu_bar", Shape::Array(nu_bar)),
                    ("H_bar", matrix(2 * n, 3)),
                ]),
            )
        }
        Call::Update { .. } | Call::BatchUpdate { .. } => (
            "",
            Shape::Object(vec![("mu", pose()), ("sigma", Shape::Symmetric(3))]),
        ),
    }
}

/// The reference answer to a call, in the contract's shapes.
pub fn reference(call: &Call) -> Result<Answer, Error> {
    Ok(match call {
        Call::CalculateOdometry {
            e_r,
            e_l,
            e_t,
            b,
            r_r,
            r_l,
            delta_t,
            mu,
        } => {
            let robot = Robot {
                ticks_per_revolution: *e_t,
                wheel_base: *b,
                right_radius: *r_r,
                left_radius: *r_l,
            };
            let u = ekf::calculate_odometry(*e_r, *e_l, &robot, *delta_t, &vector3(mu));
            Answer::Odometry(u.into())
        }
        Call::Predict { mu, sigma, u, r } => {
            let bar = ekf::predict(
                &Belief::new(vector3(mu), matrix_of(sigma)),
                &vector3(u),
                &matrix_of(r),
            );
            Answer::Prediction(Prediction {
                mu_bar: bar.mu.into(),
                sigma_bar: rows(&bar.sigma),
            })
        }
        Call::ObservationModel { x, m, j } => {
            let landmark = landmark_at(m, *j)?;
            Answer::Observation(ekf::observation_model(&vector3(x), &landmark).into())
        }
        Call::JacobianObservationModel { x, m, j, z_hat } => {
            let landmark = landmark_at(m, *j)?;
            let h = ekf::jacobian_observation_model(&vector3(x), &landmark, &Vector2::from(*z_hat));
            Answer::Jacobian(rows(&h))
        }
        Call::Associate {
            mu_bar,
            sigma_bar,
            z_i,
            m,
            lambda_m,
            q,
        } => {
            let bar = Belief::new(vector3(mu_bar), matrix_of(sigma_bar));
            let a = ekf::associate(
                &bar,
                &Vector2::from(*z_i),
                &map(m)?,
                *lambda_m,
                &matrix_of(q),
            );
            Answer::Association(Association {
                c: a.c,
                outlier: a.outlier,
                nu: a.candidates.iter().map(|cand| cand.nu.into()).collect(),
                s: a.candidates.iter().map(|cand| rows(&cand.s)).collect(),
                h: a.candidates.iter().map(|cand| rows(&cand.h)).collect(),
            })
        }
        Call::BatchAssociate {
            mu_bar,
            sigma_bar,
            z,
            m,
            lambda_m,
            q,
        } => {
            let bar = Belief::new(vector3(mu_bar), matrix_of(sigma_bar));
            let readings = two_rows("z", z)?;
            let matches = ekf::batch_associate(&bar, &readings, &map(m)?, *lambda_m, &matrix_of(q));
            Answer::BatchAssociation(BatchAssociation {
                c: matches.iter().map(|m| m.c).collect(),
                outlier: matches.iter().map(|m| m.outlier).collect(),
                nu_bar: matches
                    .iter()
                    .flat_map(|m| m.candidate.nu.iter().copied())
                    .collect(),
                h_bar: matches.iter().flat_map(|m| rows(&m.candidate.h)).collect(),
            })
        }
        Call::Update {
            mu_bar,
            sigma_bar,
            h,
            s,
            nu,
        } => {
            let bar = Belief::new(vector3(mu_bar), matrix_of(sigma_bar));
            let h = matrix_of(h);
            let posterior = ekf::update(&bar, &h, &matrix_of(s), &Vector2::from(*nu))
                .ok_or_else(|| Error::invalid("S", "is singular"))?;
            Posterior::of(&posterior)
        }
        Call::BatchUpdate {
            mu_bar,
            sigma_bar,
            h_bar,
            q_bar,
            nu_bar,
        } => {
            let bar = Belief::new(vector3(mu_bar), matrix_of(sigma_bar));
            let n = h_bar.len();
            if n % 2 != 0 || nu_bar.len() != n {
                return Err(Error::invalid(
                    "H_bar",
                    format!(
                        "has {n} rows and nu_bar {} elements; both must be 2n for n readings",
                        nu_bar.len()
                    ),
                ));
            }
            let q = repeated_block(q_bar, n / 2)?;
            let h: Vec<Matrix2x3<f64>> = h_bar
                .chunks(2)
                .map(|pair| Matrix2x3::from_fn(|i, j| pair[i][j]))
                .collect();
            let nu: Vec<Vector2<f64>> = nu_bar.chunks(2).map(Vector2::from_column_slice).collect();
            let posterior = ekf::batch_update(&bar, h.iter().zip(&nu), &q)
                .ok_or_else(|| Error::invalid("Q_bar", "has a singular block"))?;
            Posterior::of(&posterior)
        }
    })
}

pub(crate) fn vector3(v: &Vec3) -> Vector3<f64> {
    Vector3::from(*v)
}

/// The columns of a 2 x n matrix, both rows of the same length.
fn two_rows(field: &str, a: &TwoRows) -> Result<Vec<Vector2<f64>>, Error> {
    if a[0].len() != a[1].len() {
        return Err(Error::invalid(
            field,
            format!(
                "rows have {} and {} elements; a 2 x n matrix needs equal rows",
                a[0].len(),
                a[1].len()
            ),
        ));
    }
    Ok(a[0]
        .iter()
        .zip(&a[1])
        .map(|(&x, &y)| Vector2::new(x, y))
        .collect())
}

/// The map `M`; its landmarks get ids 1..N as in the lab's test cases.
pub(crate) fn map(m: &TwoRows) -> Result<Map, Error> {
    let landmarks = two_rows("M", m)?
        .into_iter()
        .zip(1..)
        .map(|(position, id)| Landmark { id, position })
        .collect();
    Map::new(landmarks)
}

fn landmark_at(m: &TwoRows, j: usize) -> Result<Vector2<f64>, Error> {
    let positions = two_rows("M", m)?;
    positions.get(j).copied().ok_or_else(|| {
        Error::invalid(
            "j",
            format!("is {j}, but M has {} landmarks (0-based)", positions.len()),
        )
    })
}

/// The block Q of `Q_bar = blkdiag(Q, ..., Q)` (n blocks), which is what the filter loop
/// passes to `batch_update`.
fn repeated_block(q_bar: &[Vec<f64>], n: usize) -> Result<Matrix2<f64>, Error> {
    let size = 2 * n;
    if q_bar.len() != size || q_bar.iter().any(|row| row.len() != size) {
        return Err(Error::invalid(
            "Q_bar",
            format!("must be {size} x {size} for {n} readings"),
        ));
    }
    if n == 0 {
        return Ok(Matrix2::identity());
    }
    let q = Matrix2::from_fn(|i, j| q_bar[i][j]);
    for (i, row) in q_bar.iter().enumerate() {
        for (j, &value) in row.iter().enumerate() {
            let expected = if i / 2 == j / 2 {
                q[(i % 2, j % 2)]
            } else {
                0.0
            };
            if value != expected {
                return Err(Error::invalid("Q_bar", "must be blkdiag(Q, ..., Q)"));
            }
        }
    }
    Ok(q)
}
