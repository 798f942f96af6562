//! Runs that record a belief, a pose and its covariance, after every step, held to the
//! reference's step by step: what the run tests of the odometry and sensor-fusion
//! exercises share.

use super::compare::{Mismatch, Tolerance, compare, matrix, pose};
use serde_json::json;

/// The poses and covariances of a run, step by step.
#[derive(Clone, Copy, Debug)]
pub struct Beliefs<'a> {
    pub poses: &'a [[f64; 3]],
    pub covariances: &'a [[[f64; 3]; 3]],
}

/// How close a run's beliefs must be to the reference's: the pose within `pose`, the
/// covariance within `covariance_share` of the largest element of the reference's at that
/// step (whose elements span orders of magnitude), or within `covariance_floor`, where
/// that is more.
#[derive(Clone, Copy, Debug)]
pub struct BeliefTolerance {
    pub pose: Tolerance,
    pub covariance_share: f64,
    /// What a covariance may differ by however small the reference's is: a particle
    /// cloud resampled to copies of one particle has a covariance of rounding alone
    /// (1e-30), which another order of the same sums gives otherwise.
    pub covariance_floor: f64,
}

/// How close the beliefs of a run of the odometry, sensor-fusion and UKF and particle
/// filter exercises must be to the reference's at every step: x and y within 1e-6 m, the
/// heading within 1e-6 rad (modulo 2 pi), covariances within 1e-6 of their largest
/// element or 1e-12 (the square of the position's tolerance), whichever is more. The
/// student's arithmetic may round otherwise than the reference's; over a few hundred
/// steps that stays below 1e-12, and the filters forget such differences rather than
/// growing them.
pub const STEP_BY_STEP: BeliefTolerance = BeliefTolerance {
    pose: Tolerance {
        absolute: 1e-6,
        relative: 0.0,
    },
    covariance_share: 1e-6,
    covariance_floor: 1e-12,
};

/// What the pose and the covariance are called in messages: `p` and `Sigma_p`.
pub type Names = [&'static str; 2];

/// The first step (counted from 1) at which `got` leaves `expected`, with the first
/// element that differs there; none while it follows as far as it goes.
pub fn first_departure(
    names: Names,
    got: Beliefs,
    expected: Beliefs,
    tolerance: BeliefTolerance,
) -> Option<(usize, Mismatch)> {
    let steps = got.poses.iter().zip(got.covariances);
    let reference = expected.poses.iter().zip(expected.covariances);
    steps
        .zip(reference)
        .enumerate()
        .find_map(|(k, ((p, sigma), (expected_p, expected_sigma)))| {
            let largest = expected_sigma
                .iter()
                .flatten()
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            let mut mismatches = compare(
                &(names[0], pose()),
                &json!(expected_p),
                &json!(p),
                tolerance.pose,
            );
            mismatches.extend(compare(
                &(names[1], matrix(3, 3)),
                &json!(expected_sigma),
                &json!(sigma),
                Tolerance {
                    absolute: (tolerance.covariance_share * largest)
                        .max(tolerance.covariance_floor),
                    relative: 0.0,
                },
            ));
            mismatches.into_iter().next().map(|first| (k + 1, first))
        })
}

/// Nothing when `got` follows `expected` at every one of its steps; otherwise where it
/// first departs (or that it reported another number of steps), in words.
pub fn follows(
    names: Names,
    got: Beliefs,
    expected: Beliefs,
    tolerance: BeliefTolerance,
) -> Result<(), String> {
    let steps = expected.poses.len();
    if got.poses.len() != steps || got.covariances.len() != steps {
        return Err(format!(
            "the run reported {} poses and {} covariances for {steps} steps",
            got.poses.len(),
            got.covariances.len()
        ));
    }
    match first_departure(names, got, expected, tolerance) {
        None => Ok(()),
        Some((step, first)) => Err(format!(
            "from step {step} of {steps} on, the run departs from the reference: {} is {} \
             where the reference's is {}{}.",
            first.path,
            first.got,
            first.expected,
            first.problem.explanation()
        )),
    }
}
