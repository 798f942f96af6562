//! What an odometry experiment depends on, with defaults, and its checks.

use super::covariance::check_covariance;
use super::path::{Path, Shape};
use crate::Error;
use serde::{Deserialize, Serialize};

/// The largest wheel noise constant, metres (a wheel's distance off by a metre per metre
/// rolled is already no odometry at all).
pub const MAX_K: f64 = 1.0;
/// The largest entry of the initial covariance.
pub const MAX_SIGMA0: f64 = 1e6;

/// A path, the robot that drives it, and what its odometry knows at the start.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct OdometryParams {
    pub shape: Shape,
    /// Metres per step: the most the robot's centre moves in a step (on a turn on the
    /// spot, each wheel).
    pub speed: f64,
    /// `b`, the distance between the wheels, metres.
    pub wheel_base: f64,
    /// `k_r`, `k_l`: each wheel's distance variance per metre it rolls, metres.
    pub k_r: f64,
    pub k_l: f64,
    /// `Sigma_p0`, the covariance of the start pose (x, y, theta), rows. Zero: the start
    /// is known exactly; a large heading variance makes the cloud bend into a banana.
    pub sigma0: [[f64; 3]; 3],
}

impl Default for OdometryParams {
    fn default() -> Self {
        OdometryParams {
            shape: Shape::default(),
            speed: 0.05,
            wheel_base: 0.35,
            k_r: 1e-4,
            k_l: 1e-4,
            sigma0: [[0.0; 3]; 3],
        }
    }
}

impl OdometryParams {
    /// Checks every parameter, naming the first that is out of its domain.
    pub fn validate(&self) -> Result<(), Error> {
        self.path().map(|_| ())
    }

    /// The path, once every parameter is checked.
    pub fn path(&self) -> Result<Path, Error> {
        check_noise(self.k_r, self.k_l)?;
        check_covariance("sigma0", &self.sigma0)?;
        if self.sigma0.iter().flatten().any(|v| v.abs() > MAX_SIGMA0) {
            return Err(Error::invalid(
                "sigma0",
                format!("entries must be at most {MAX_SIGMA0:e} in size"),
            ));
        }
        Path::new(&self.shape, self.speed, self.wheel_base)
    }
}

/// Checks the wheel noise constants, naming the field.
pub(crate) fn check_noise(k_r: f64, k_l: f64) -> Result<(), Error> {
    for (field, k) in [("k_r", k_r), ("k_l", k_l)] {
        if !(k.is_finite() && (0.0..=MAX_K).contains(&k)) {
            return Err(Error::invalid(
                field,
                format!("must lie in [0, {MAX_K}] metres, got {k}"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_read_from_partial_json() {
        OdometryParams::default().validate().unwrap();
        let params: OdometryParams =
            serde_json::from_str(r#"{"k_r": 2e-4, "shape": {"kind": "line", "length": 3}}"#)
                .unwrap();
        assert_eq!(params.k_r, 2e-4);
        assert_eq!(params.k_l, OdometryParams::default().k_l);
        assert_eq!(params.shape, Shape::Line { length: 3.0 });
        let text = serde_json::to_string(&OdometryParams::default()).unwrap();
        assert_eq!(
            serde_json::from_str::<OdometryParams>(&text).unwrap(),
            OdometryParams::default()
        );
    }

    #[test]
    fn bad_noise_and_initial_covariances_are_named() {
        let message = |params: OdometryParams| params.validate().unwrap_err().to_string();
        let d = OdometryParams::default;
        assert_eq!(
            message(OdometryParams { k_r: -1e-4, ..d() }),
            "k_r: must lie in [0, 1] metres, got -0.0001"
        );
        assert_eq!(
            message(OdometryParams {
                k_l: f64::NAN,
                ..d()
            }),
            "k_l: must lie in [0, 1] metres, got NaN"
        );
        assert_eq!(
            message(OdometryParams {
                sigma0: [[0.0; 3], [0.0; 3], [0.0, 0.0, -1.0]],
                ..d()
            }),
            "sigma0: must be positive semi-definite"
        );
        assert_eq!(
            message(OdometryParams {
                sigma0: [[1e7, 0.0, 0.0], [0.0; 3], [0.0; 3]],
                ..d()
            }),
            "sigma0: entries must be at most 1e6 in size"
        );
        assert_eq!(
            message(OdometryParams {
                wheel_base: -0.3,
                ..d()
            }),
            "wheel_base: must lie in [0.001, 1000] metres, got -0.3"
        );
    }
}
