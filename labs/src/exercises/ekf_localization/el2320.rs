//! The original EL2320 test fixtures (`test_case_*.mat`, converted to JSON: each variable
//! a `{rows, cols, data}` matrix). Case i uses column i of every per-case matrix; MATLAB's
//! reshapes are column-major and its indices 1-based, and both are undone here.

use super::Case;
use super::contract::{Call, Mat2, Mat3, TwoRows, Vec3};
use crate::Error;
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::HashMap;

/// The fixture file of each student function.
pub const FIXTURE_FILES: [(&str, &str); 8] = [
    ("calculate_odometry", "test_case_odo.json"),
    ("predict", "test_case_prediction.json"),
    ("observation_model", "test_case_obs.json"),
    ("jacobian_observation_model", "test_case_jac.json"),
    ("associate", "test_case_associate.json"),
    ("batch_associate", "test_case_batch_associate.json"),
    ("update", "test_case_update.json"),
    ("batch_update", "test_case_batch_update.json"),
];

#[derive(Deserialize)]
struct Matrix {
    rows: usize,
    cols: usize,
    data: Vec<Vec<f64>>,
}

struct Fixture {
    file: String,
    variables: HashMap<String, Matrix>,
}

/// The cases of one fixture file (`file` names it in errors) for `function`.
pub fn load_fixtures(function: &str, file: &str, text: &str) -> Result<Vec<Case>, Error> {
    let variables: HashMap<String, Matrix> =
        serde_json::from_str(text).map_err(|e| Error::parse(file, e.line(), e.to_string()))?;
    let fixture = Fixture {
        file: file.to_owned(),
        variables,
    };
    let n = fixture.scalar("NUM_TEST")? as usize;
    (0..n)
        .map(|i| {
            let (call, expected) = fixture.case(function, i)?;
            Ok(Case {
                id: format!("{function}/el2320-{}", i + 1),
                note: format!("case {} of the original EL2320 test suite", i + 1),
                call,
                expected,
            })
        })
        .collect()
}

impl Fixture {
    fn variable(&self, name: &str) -> Result<&Matrix, Error> {
        let m = self
            .variables
            .get(name)
            .ok_or_else(|| Error::parse(&self.file, 0, format!("variable {name} is missing")))?;
        if m.data.len() != m.rows || m.data.iter().any(|row| row.len() != m.cols) {
            return Err(Error::parse(
                &self.file,
                0,
                format!("variable {name} is not {} x {}", m.rows, m.cols),
            ));
        }
        Ok(m)
    }

    fn scalar(&self, name: &str) -> Result<f64, Error> {
        Ok(self.variable(name)?.data[0][0])
    }

    /// Column `i` of a variable, checked to have `len` rows.
    fn column(&self, name: &str, i: usize, len: usize) -> Result<Vec<f64>, Error> {
        let m = self.variable(name)?;
        if m.rows != len || i >= m.cols {
            return Err(Error::parse(
                &self.file,
                0,
                format!(
                    "variable {name} is {} x {}, expected {len} rows and a column {}",
                    m.rows,
                    m.cols,
                    i + 1
                ),
            ));
        }
        Ok(m.data.iter().map(|row| row[i]).collect())
    }

    fn vec3(&self, name: &str, i: usize) -> Result<Vec3, Error> {
        let c = self.column(name, i, 3)?;
        Ok([c[0], c[1], c[2]])
    }

    /// `reshape(V(:, i), 3, 3)`.
    fn mat3(&self, name: &str, i: usize) -> Result<Mat3, Error> {
        let c = self.column(name, i, 9)?;
        Ok(std::array::from_fn(|r| {
            std::array::from_fn(|k| c[r + 3 * k])
        }))
    }

    /// `diag(V(:, i))` of a 2-vector.
    fn diag2(&self, name: &str, i: usize) -> Result<Mat2, Error> {
        let c = self.column(name, i, 2)?;
        Ok([[c[0], 0.0], [0.0, c[1]]])
    }

    fn map(&self) -> Result<TwoRows, Error> {
        let m = self.variable("M")?;
        if m.rows != 2 {
            return Err(Error::parse(&self.file, 0, "variable M is not 2 x N"));
        }
        Ok([m.data[0].clone(), m.data[1].clone()])
    }

    /// A 1-based index of a 1 x n variable, made 0-based.
    fn index(&self, name: &str, i: usize) -> Result<usize, Error> {
        Ok(self.column(name, i, 1)?[0] as usize - 1)
    }

    fn case(&self, function: &str, i: usize) -> Result<(Call, Value), Error> {
        Ok(match function {
            "calculate_odometry" => (
                Call::CalculateOdometry {
                    e_r: self.column("E_R", i, 1)?[0],
                    e_l: self.column("E_L", i, 1)?[0],
                    e_t: self.scalar("E_T")?,
                    b: self.scalar("B")?,
                    r_r: self.scalar("R_R")?,
                    r_l: self.scalar("R_L")?,
                    delta_t: self.scalar("delta_t")?,
                    mu: self.vec3("MU", i)?,
                },
                json!(self.vec3("U", i)?),
            ),
            "predict" => {
                let r = self.column("R", i, 3)?;
                (
                    Call::Predict {
                        mu: self.vec3("MU", i)?,
                        sigma: self.mat3("SIGMA", i)?,
                        u: self.vec3("U", i)?,
                        r: [[r[0], 0.0, 0.0], [0.0, r[1], 0.0], [0.0, 0.0, r[2]]],
                    },
                    json!({ "mu_bar": self.vec3("MU_BAR", i)?, "sigma_bar": self.mat3("SIGMA_BAR", i)? }),
                )
            }
            "observation_model" => (
                Call::ObservationModel {
                    x: self.vec3("X", i)?,
                    m: self.map()?,
                    j: self.index("J", i)?,
                },
                json!(self.column("Z", i, 2)?),
            ),
            "jacobian_observation_model" => {
                let z = self.column("Z", i, 2)?;
                let h = &self.variable("H")?.data;
                (
                    Call::JacobianObservationModel {
                        x: self.vec3("X", i)?,
                        m: self.map()?,
                        j: self.index("J", i)?,
                        z_hat: [z[0], z[1]],
                    },
                    json!([h[2 * i], h[2 * i + 1]]),
                )
            }
            "associate" => {
                let n = self.map()?[0].len();
                let z = self.column("Z", i, 2)?;
                let nu = self.column("NU", i, 2 * n)?;
                let s = self.column("S", i, 4 * n)?;
                let h = self.column("H", i, 6 * n)?;
                (
                    Call::Associate {
                        mu_bar: self.vec3("MU_BAR", i)?,
                        sigma_bar: self.mat3("SIGMA_BAR", i)?,
                        z_i: [z[0], z[1]],
                        m: self.map()?,
                        lambda_m: self.column("LAMBDA", i, 1)?[0],
                        q: self.diag2("Q", i)?,
                    },
                    json!({
                        "c": self.index("C", i)?,
                        "outlier": self.column("OUTLIERS", i, 1)?[0] != 0.0,
                        "nu": (0..n).map(|j| [nu[2 * j], nu[2 * j + 1]]).collect::<Vec<_>>(),
                        "S": (0..n).map(|j| column_major(&s[4 * j..], 2, 2)).collect::<Vec<_>>(),
                        "H": (0..n).map(|j| column_major(&h[6 * j..], 2, 3)).collect::<Vec<_>>(),
                    }),
                )
            }
            "batch_associate" => {
                let n = self.scalar("NUM_OBS")? as usize;
                let z = self.column("Z", i, 2 * n)?;
                (
                    Call::BatchAssociate {
                        mu_bar: self.vec3("MU_BAR", i)?,
                        sigma_bar: self.mat3("SIGMA_BAR", i)?,
                        z: [
                            (0..n).map(|k| z[2 * k]).collect(),
                            (0..n).map(|k| z[2 * k + 1]).collect(),
                        ],
                        m: self.map()?,
                        lambda_m: self.column("LAMBDA", i, 1)?[0],
                        q: self.diag2("Q", i)?,
                    },
                    json!({
                        "c": self.column("C", i, n)?.iter().map(|&c| c as usize - 1).collect::<Vec<_>>(),
                        "outlier": self.column("OUTLIER", i, n)?.iter().map(|&o| o != 0.0).collect::<Vec<_>>(),
                        "nu_bar": self.column("NU_BAR", i, 2 * n)?,
                        "H_bar": column_major(&self.column("H_BAR", i, 6 * n)?, 2 * n, 3),
                    }),
                )
            }
            "update" => {
                let h = self.column("H_BAR", i, 6)?;
                let s = self.column("S_BAR", i, 4)?;
                let nu = self.column("NU_BAR", i, 2)?;
                (
                    Call::Update {
                        mu_bar: self.vec3("MU_BAR", i)?,
                        sigma_bar: self.mat3("SIGMA_BAR", i)?,
                        h: [[h[0], h[2], h[4]], [h[1], h[3], h[5]]],
                        s: [[s[0], s[2]], [s[1], s[3]]],
                        nu: [nu[0], nu[1]],
                    },
                    json!({ "mu": self.vec3("MU_BAR_N", i)?, "sigma": self.mat3("SIGMA_BAR_N", i)? }),
                )
            }
            "batch_update" => {
                let n = self.scalar("NUM_OBS")? as usize;
                let outlier = self.column("OUTLIER", i, n)?;
                let inliers: Vec<usize> = (0..n).filter(|&k| outlier[k] == 0.0).collect();
                let nu = self.column("NU_BAR", i, 2 * n)?;
                let h = column_major(&self.column("H_BAR", i, 6 * n)?, 2 * n, 3);
                let q = self.column("Q", i, 2)?;
                // The original suite's index list [2(v-1)+1; 2(v-1)+2] takes the range rows
                // of all inliers first, then their bearing rows, while Q_bar stays
                // blkdiag(Q, ..., Q): the expected outputs are for exactly these inputs.
                let rows: Vec<usize> = inliers
                    .iter()
                    .map(|&k| 2 * k)
                    .chain(inliers.iter().map(|&k| 2 * k + 1))
                    .collect();
                let size = rows.len();
                (
                    Call::BatchUpdate {
                        mu_bar: self.vec3("MU_BAR", i)?,
                        sigma_bar: self.mat3("SIGMA_BAR", i)?,
                        h_bar: rows.iter().map(|&r| [h[r][0], h[r][1], h[r][2]]).collect(),
                        q_bar: (0..size)
                            .map(|r| {
                                (0..size)
                                    .map(|c| if r == c { q[r % 2] } else { 0.0 })
                                    .collect()
                            })
                            .collect(),
                        nu_bar: rows.iter().map(|&r| nu[r]).collect(),
                    },
                    json!({ "mu": self.vec3("MU", i)?, "sigma": self.mat3("SIGMA", i)? }),
                )
            }
            other => {
                return Err(Error::invalid(
                    "function",
                    format!("'{other}' is not a student function"),
                ));
            }
        })
    }
}

/// The `rows x cols` matrix stored column-major at the start of `data`, as rows.
fn column_major(data: &[f64], rows: usize, cols: usize) -> Vec<Vec<f64>> {
    (0..rows)
        .map(|r| (0..cols).map(|c| data[r + rows * c]).collect())
        .collect()
}
