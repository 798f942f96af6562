//! Odometry and how its error grows: the propagated covariance along a path, many robots
//! whose wheels really slip, systematic errors and the UMBmark test.
//!
//! Settings come in as JSON of `labs::odometry`'s own types (missing fields take their
//! defaults); results go out series by series as typed arrays. Components of a pose are
//! 0 x, 1 y, 2 theta; a 3 x 3 matrix goes out as its 9 entries, row after row.

use super::{from_json, to_js};
use labs::ekf::covariance_ellipse;
use labs::odometry::{
    self, MonteCarloParams, OdometryParams, SystematicErrors, UmbmarkDirection, UmbmarkParams,
};
use nalgebra::{Matrix2, Vector2};
use wasm_bindgen::prelude::*;

/// The default parameters (a 4 m square, counter-clockwise), as JSON: what the page
/// starts from.
#[wasm_bindgen(js_name = odometryDefaults)]
pub fn odometry_defaults() -> String {
    serde_json::to_string(&OdometryParams::default()).expect("parameters serialise")
}

/// Drives the path of `params` (JSON of `OdometryParams`) and propagates the covariance.
#[wasm_bindgen(js_name = propagateOdometry)]
pub fn propagate_odometry(params: &str) -> Result<OdometryPropagation, JsError> {
    let params: OdometryParams = from_json("odometry parameters", params)?;
    Ok(odometry::propagate(&params).map_err(to_js)?.into())
}

/// Runs `monte_carlo` (JSON of `MonteCarloParams`: robots, seed, cloud_every) robots
/// along the path of `params`.
#[wasm_bindgen(js_name = odometryMonteCarlo)]
pub fn odometry_monte_carlo(
    params: &str,
    monte_carlo: &str,
) -> Result<OdometryMonteCarlo, JsError> {
    let params: OdometryParams = from_json("odometry parameters", params)?;
    let mc: MonteCarloParams = from_json("Monte Carlo settings", monte_carlo)?;
    Ok(OdometryMonteCarlo {
        inner: odometry::monte_carlo(&params, &mc).map_err(to_js)?,
    })
}

/// The odometry's path of `params` beside the real robot's, whose wheels and wheel base
/// differ by `errors` (JSON of `SystematicErrors`: e_d, e_b).
#[wasm_bindgen(js_name = odometrySystematic)]
pub fn odometry_systematic(params: &str, errors: &str) -> Result<OdometrySystematic, JsError> {
    let params: OdometryParams = from_json("odometry parameters", params)?;
    let errors: SystematicErrors = from_json("systematic errors", errors)?;
    Ok(OdometrySystematic {
        inner: odometry::systematic(&params, &errors).map_err(to_js)?,
    })
}

/// The UMBmark test (`test`: JSON of `UmbmarkParams`: side, runs, seed) of the robot of
/// `params` with the systematic `errors`.
#[wasm_bindgen(js_name = odometryUmbmark)]
pub fn odometry_umbmark(
    params: &str,
    errors: &str,
    test: &str,
) -> Result<OdometryUmbmark, JsError> {
    let params: OdometryParams = from_json("odometry parameters", params)?;
    let errors: SystematicErrors = from_json("systematic errors", errors)?;
    let test: UmbmarkParams = from_json("UMBmark settings", test)?;
    Ok(OdometryUmbmark {
        inner: odometry::umbmark(&params, &errors, &test).map_err(to_js)?,
    })
}

/// One component of every pose.
fn column(poses: &[[f64; 3]], component: usize) -> Vec<f64> {
    let i = component.min(2);
    poses.iter().map(|p| p[i]).collect()
}

/// The positions of poses as x, y, x, y, ...: what a scatter plot of many points takes
/// without a copy.
fn positions(poses: &[[f64; 3]]) -> Vec<f64> {
    poses.iter().flat_map(|p| [p[0], p[1]]).collect()
}

/// A matrix's entries, row after row.
fn flat(rows: &[[f64; 3]; 3]) -> Vec<f64> {
    rows.iter().flatten().copied().collect()
}

/// The `k`-sigma ellipse of the position block of `sigma` round the position of `pose`,
/// closed, as x, y pairs, then a NaN pair (which ends an outline). An ellipse whose
/// numbers overflow is left out: a student's covariance of 1e200 has none to draw.
fn push_ellipse(
    xy: &mut Vec<f64>,
    pose: &[f64; 3],
    sigma: &[[f64; 3]; 3],
    k: f64,
    segments: usize,
) {
    let block = Matrix2::new(sigma[0][0], sigma[0][1], sigma[1][0], sigma[1][1]);
    let outline = covariance_ellipse(&Vector2::new(pose[0], pose[1]), &block, k, segments.max(3));
    if !outline.iter().all(|p| p.x.is_finite() && p.y.is_finite()) {
        return;
    }
    for p in outline {
        xy.extend([p.x, p.y]);
    }
    xy.extend([f64::NAN, f64::NAN]);
}

/// The belief along a whole path: `steps + 1` entries, the k-th after k steps.
#[wasm_bindgen]
pub struct OdometryPropagation {
    inner: odometry::Propagation,
}

impl From<odometry::Propagation> for OdometryPropagation {
    fn from(inner: odometry::Propagation) -> OdometryPropagation {
        OdometryPropagation { inner }
    }
}

#[wasm_bindgen]
impl OdometryPropagation {
    pub fn steps(&self) -> usize {
        self.inner.path.steps()
    }
    /// One component of the odometry's pose at every step.
    pub fn pose(&self, component: usize) -> Vec<f64> {
        column(&self.inner.poses, component)
    }
    /// The entry (i, j) of the covariance at every step.
    pub fn covariance(&self, i: usize, j: usize) -> Vec<f64> {
        let (i, j) = (i.min(2), j.min(2));
        self.inner.covariances.iter().map(|s| s[i][j]).collect()
    }
    /// The square root of one diagonal entry of the covariance at every step.
    pub fn std(&self, component: usize) -> Vec<f64> {
        let i = component.min(2);
        self.inner
            .covariances
            .iter()
            .map(|s| s[i][i].max(0.0).sqrt())
            .collect()
    }
    /// The pose after the last step.
    #[wasm_bindgen(js_name = finalPose)]
    pub fn final_pose(&self) -> Vec<f64> {
        self.inner.final_pose().to_vec()
    }
    /// The covariance after the last step, 9 entries row after row.
    #[wasm_bindgen(js_name = finalCovariance)]
    pub fn final_covariance(&self) -> Vec<f64> {
        flat(&self.inner.final_covariance())
    }
    /// The `k`-sigma ellipses of the position covariance at steps 0, `every`, 2 `every`,
    /// ... before the last step, as x, y pairs, each ellipse closed and followed by a NaN
    /// pair.
    pub fn ellipses(&self, every: usize, k: f64, segments: usize) -> Vec<f64> {
        let last = self.steps();
        let mut xy = Vec::new();
        for step in (0..last).step_by(every.max(1)) {
            push_ellipse(
                &mut xy,
                &self.inner.poses[step],
                &self.inner.covariances[step],
                k,
                segments,
            );
        }
        xy
    }
    /// The `k`-sigma ellipse at `step` (the last step when beyond it), as `ellipses`
    /// gives each.
    pub fn ellipse(&self, step: usize, k: f64, segments: usize) -> Vec<f64> {
        let step = step.min(self.steps());
        let mut xy = Vec::new();
        push_ellipse(
            &mut xy,
            &self.inner.poses[step],
            &self.inner.covariances[step],
            k,
            segments,
        );
        xy
    }
}

/// Many robots along one path, beside the odometry's propagated belief.
#[wasm_bindgen]
pub struct OdometryMonteCarlo {
    inner: odometry::MonteCarlo,
}

#[wasm_bindgen]
impl OdometryMonteCarlo {
    pub fn robots(&self) -> usize {
        self.inner.robots
    }
    pub fn steps(&self) -> usize {
        self.inner.steps
    }
    /// One component of every robot's pose after the last step.
    #[wasm_bindgen(js_name = finalPoses)]
    pub fn final_poses(&self, component: usize) -> Vec<f64> {
        column(&self.inner.final_poses, component)
    }
    /// Every robot's position after the last step: x, y, x, y, ...
    #[wasm_bindgen(js_name = finalPositions)]
    pub fn final_positions(&self) -> Vec<f64> {
        positions(&self.inner.final_poses)
    }
    /// The steps at which every robot's pose was kept (`cloud_every`).
    #[wasm_bindgen(js_name = cloudSteps)]
    pub fn cloud_steps(&self) -> Vec<u32> {
        self.inner.clouds.iter().map(|c| c.step as u32).collect()
    }
    /// One component of every robot's pose in the `index`-th cloud (empty beyond the last).
    pub fn cloud(&self, index: usize, component: usize) -> Vec<f64> {
        self.inner
            .clouds
            .get(index)
            .map_or_else(Vec::new, |c| column(&c.poses, component))
    }
    /// Every robot's position in the `index`-th cloud: x, y, x, y, ... (empty beyond the
    /// last).
    #[wasm_bindgen(js_name = cloudPositions)]
    pub fn cloud_positions(&self, index: usize) -> Vec<f64> {
        self.inner
            .clouds
            .get(index)
            .map_or_else(Vec::new, |c| positions(&c.poses))
    }
    /// The odometry's final pose.
    pub fn nominal(&self) -> Vec<f64> {
        self.inner.nominal.to_vec()
    }
    /// The propagated final covariance, 9 entries row after row.
    pub fn covariance(&self) -> Vec<f64> {
        flat(&self.inner.covariance)
    }
    #[wasm_bindgen(js_name = sampleMean)]
    pub fn sample_mean(&self) -> Vec<f64> {
        self.inner.sample_mean.to_vec()
    }
    /// The sample covariance of the final poses, 9 entries row after row.
    #[wasm_bindgen(js_name = sampleCovariance)]
    pub fn sample_covariance(&self) -> Vec<f64> {
        flat(&self.inner.sample_covariance)
    }
    /// The share of final poses inside the propagated 3-sigma ellipse; undefined when
    /// the position covariance is singular.
    #[wasm_bindgen(js_name = insideThreeSigma)]
    pub fn inside_three_sigma(&self) -> Option<f64> {
        self.inner.inside_3_sigma
    }
    /// The share a Gaussian puts inside its 3-sigma ellipse, 1 - e^(-9/2).
    #[wasm_bindgen(js_name = gaussianInsideThreeSigma)]
    pub fn gaussian_inside_three_sigma(&self) -> f64 {
        self.inner.gaussian_inside_3_sigma
    }
}

/// The odometry's path and the real robot's, from the same encoder counts.
#[wasm_bindgen]
pub struct OdometrySystematic {
    inner: odometry::SystematicRun,
}

#[wasm_bindgen]
impl OdometrySystematic {
    /// One component of the pose the odometry computes, at every step.
    pub fn odometry(&self, component: usize) -> Vec<f64> {
        column(&self.inner.odometry, component)
    }
    /// One component of the real robot's pose, at every step.
    pub fn truth(&self, component: usize) -> Vec<f64> {
        column(&self.inner.truth, component)
    }
    /// True - odometry after the last step (x, y, theta wrapped).
    #[wasm_bindgen(js_name = finalError)]
    pub fn final_error(&self) -> Vec<f64> {
        self.inner.final_error.to_vec()
    }
}

/// The UMBmark test. Directions: 0 clockwise, 1 counter-clockwise.
#[wasm_bindgen]
pub struct OdometryUmbmark {
    inner: odometry::Umbmark,
}

impl OdometryUmbmark {
    fn direction(&self, direction: usize) -> &UmbmarkDirection {
        if direction == 0 {
            &self.inner.clockwise
        } else {
            &self.inner.counter_clockwise
        }
    }
}

#[wasm_bindgen]
impl OdometryUmbmark {
    /// Runs in each direction.
    pub fn runs(&self) -> usize {
        self.inner.clockwise.truths.len()
    }
    /// One component of the square as the odometry computes it.
    pub fn odometry(&self, direction: usize, component: usize) -> Vec<f64> {
        column(&self.direction(direction).odometry, component)
    }
    /// One component of every run's true path, one run after the other, each followed by
    /// a NaN (which breaks a line).
    pub fn truths(&self, direction: usize, component: usize) -> Vec<f64> {
        let mut out = Vec::new();
        for truth in &self.direction(direction).truths {
            out.extend(column(truth, component));
            out.push(f64::NAN);
        }
        out
    }
    /// One component of every run's return error (true - odometry, theta wrapped).
    pub fn errors(&self, direction: usize, component: usize) -> Vec<f64> {
        column(&self.direction(direction).errors, component)
    }
    /// The centre of gravity (x_cg, y_cg) of the position errors.
    pub fn centre(&self, direction: usize) -> Vec<f64> {
        self.direction(direction).centre.to_vec()
    }
    /// Its distance from the origin.
    pub fn r(&self, direction: usize) -> f64 {
        self.direction(direction).r
    }
    /// max(r_cw, r_ccw).
    #[wasm_bindgen(js_name = eMaxSyst)]
    pub fn e_max_syst(&self) -> f64 {
        self.inner.e_max_syst
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ellipses_are_closed_outlines_between_nans() {
        let run = propagate_odometry(r#"{"shape": {"kind": "line", "length": 1}}"#)
            .unwrap_or_else(|_| panic!("the line propagates"));
        assert_eq!(run.steps(), 20);
        let xy = run.ellipses(5, 3.0, 8);
        // Steps 0, 5, 10, 15: 9 points and a NaN pair each.
        assert_eq!(xy.len(), 4 * (9 + 1) * 2);
        assert!(xy[18].is_nan() && xy[19].is_nan());
        assert_eq!(&xy[20..22], &xy[36..38], "closed");
        let last = run.ellipse(99, 3.0, 8);
        assert_eq!(last.len(), 20);
        let sigma = run.final_covariance();
        // The final ellipse reaches 3 sigma_y sideways of the line's end, near x = 1.
        let reach = last
            .chunks(2)
            .filter(|p| !p[0].is_nan())
            .map(|p| p[1].abs())
            .fold(0.0, f64::max);
        assert!((reach - 3.0 * sigma[4].sqrt()).abs() < 1e-12, "{reach}");
    }

    #[test]
    fn umbmark_truths_are_runs_between_nans() {
        let test = propagate_odometry("{}").unwrap_or_else(|_| panic!("defaults"));
        let steps = test.steps();
        let umbmark = odometry_umbmark("{}", r#"{"e_d": 1.01}"#, r#"{"runs": 3}"#)
            .unwrap_or_else(|_| panic!("the test runs"));
        assert_eq!(umbmark.runs(), 3);
        let x = umbmark.truths(1, 0);
        assert_eq!(x.len(), 3 * (steps + 2));
        assert!(x[steps + 1].is_nan());
        assert_eq!(umbmark.errors(0, 0).len(), 3);
        assert!(umbmark.e_max_syst() >= umbmark.r(0).max(umbmark.r(1)));
    }
}
