//! Systematic errors: a robot that is not quite the one its odometry assumes.
//!
//! The odometry turns encoder counts into wheel distances with one nominal wheel diameter
//! for both wheels, and turns wheel distances into motion with the nominal wheel base b.
//! The real robot differs in two ways that no amount of averaging removes, because they
//! act the same way at every step:
//!
//! - **Unequal wheel diameters**, E_d = D_r / D_l. We keep the mean diameter right (a
//!   straight-line calibration of the distance would fix it), (D_r + D_l) / 2 = D, so for
//!   the distances the encoders report, the wheels really roll
//!
//!   c_r ds_r and c_l ds_l,   c_r = 2 E_d / (E_d + 1),  c_l = 2 / (E_d + 1).
//!
//!   On a straight leg the robot then curves (towards the smaller wheel) while the
//!   odometry believes it goes straight; on a turn on the spot c_r + c_l = 2 keeps the
//!   angle turned right.
//! - **A wrong wheel base**, E_b = b_real / b. The angle of every turn is really
//!   (ds_r - ds_l) / (E_b b), so every turn is 1 / E_b times what the odometry believes:
//!   too short for E_b > 1, too long for E_b < 1, whichever way the robot turns.
//!
//! The encoders report the same counts either way, so the odometry's path is the nominal
//! one; the true path is what those counts do to the real robot.

use super::motion::{Increment, step};
use super::params::OdometryParams;
use super::path::Path;
use crate::Error;
use crate::angle::wrap;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The smallest and largest E_d and E_b. A real robot is off by a few per cent at most;
/// the range lets the experiment exaggerate an error until its effect is plain to see.
pub const SYSTEMATIC_RANGE: (f64, f64) = (0.5, 2.0);

/// How the real robot differs from the nominal one. (1, 1): not at all.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SystematicErrors {
    /// E_d = D_r / D_l, the ratio of the real wheel diameters.
    pub e_d: f64,
    /// E_b = b_real / b, the real wheel base over the one the odometry assumes.
    pub e_b: f64,
}

impl Default for SystematicErrors {
    fn default() -> Self {
        SystematicErrors { e_d: 1.0, e_b: 1.0 }
    }
}

impl SystematicErrors {
    pub fn validate(&self) -> Result<(), Error> {
        let (low, high) = SYSTEMATIC_RANGE;
        for (field, value) in [("e_d", self.e_d), ("e_b", self.e_b)] {
            if !(value.is_finite() && (low..=high).contains(&value)) {
                return Err(Error::invalid(
                    field,
                    format!("must lie in [{low}, {high}], got {value}"),
                ));
            }
        }
        Ok(())
    }

    /// (c_r, c_l) = (2 E_d / (E_d + 1), 2 / (E_d + 1)): what each wheel really rolls per
    /// metre its encoder reports.
    pub fn wheel_factors(&self) -> (f64, f64) {
        (2.0 * self.e_d / (self.e_d + 1.0), 2.0 / (self.e_d + 1.0))
    }

    /// What the wheels of the real robot roll when the encoders report `increment`.
    pub fn real_increment(&self, increment: Increment) -> Increment {
        let (c_r, c_l) = self.wheel_factors();
        Increment::new(c_r * increment.right, c_l * increment.left)
    }
}

/// The odometry's path and the real robot's, from the same encoder counts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SystematicRun {
    /// The pose the odometry computes before the first step and after every step.
    pub odometry: Vec<[f64; 3]>,
    /// Where the real robot is, at the same steps.
    pub truth: Vec<[f64; 3]>,
    /// truth - odometry after the last step, the heading difference wrapped.
    pub final_error: [f64; 3],
}

/// Drives `path` by the encoders' counts with the nominal robot (b) and with the real one
/// (the wheel factors of `errors`, E_b b). Without noise: this is the systematic part
/// alone.
pub(crate) fn drive_both(
    path: &Path,
    wheel_base: f64,
    errors: &SystematicErrors,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let real_base = errors.e_b * wheel_base;
    let mut odometry = Vec::with_capacity(path.steps() + 1);
    let mut truth = Vec::with_capacity(path.steps() + 1);
    let (mut believed, mut real) = (Vector3::from(path.start), Vector3::from(path.start));
    odometry.push(path.start);
    truth.push(path.start);
    for &increment in &path.increments {
        believed = step(&believed, increment, wheel_base);
        real = step(&real, errors.real_increment(increment), real_base);
        odometry.push(believed.into());
        truth.push(real.into());
    }
    (odometry, truth)
}

/// The difference of two poses, `a - b`, the heading wrapped.
pub(crate) fn pose_error(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], wrap(a[2] - b[2])]
}

/// The odometry's path of `params` beside the real robot's (`params`' noise and initial
/// covariance play no part).
pub fn systematic(
    params: &OdometryParams,
    errors: &SystematicErrors,
) -> Result<SystematicRun, Error> {
    errors.validate()?;
    let path = params.path()?;
    let (odometry, truth) = drive_both(&path, params.wheel_base, errors);
    let final_error = pose_error(
        truth.last().expect("a path starts somewhere"),
        odometry.last().expect("a path starts somewhere"),
    );
    Ok(SystematicRun {
        odometry,
        truth,
        final_error,
    })
}
