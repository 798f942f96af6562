//! Hints for the classic mistakes of the sensor-fusion exercise: when a failing output is
//! exactly what a mistake gives, say which. Each check recomputes the answer with the
//! mistake made, with the model of [`crate::fusion`] on changed arguments (the other
//! platform's intensity, an increment in the wrong frame) or from the expected output and
//! its parts (a term left out, a square root taken, a sign), and compares the student's
//! output with it.

use super::contract::{Answer, Call, Posterior, Prediction, measured, platform};
use crate::angle::wrap;
use crate::fusion::Settings;
use crate::fusion::filter::{increment, innovation, predict};
use crate::grading::{Contract, Hint, Mismatch, Mistake, form_hint, matrix_of, rows, the_only};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;

/// A classic mistake of the sensor-fusion exercise, named uniquely across the exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantArray)]
#[strum(serialize_all = "snake_case")]
pub enum HintKind {
    /// I_1 x_1 + I_2 x_2 without dividing by I_1 + I_2.
    WeightsNotNormalised,
    /// (x_1 + x_2) / 2: the intensities ignored.
    UnweightedMean,
    /// atan2(y_2 - y_1, x_2 - x_1): the heading points backwards.
    PlatformsReversed,
    /// atan2(dx, dy).
    #[strum(serialize = "atan2_arguments_swapped")]
    AtanArgumentsSwapped,
    /// Only one platform's partial derivatives.
    HeadingSigmaOnePlatform,
    /// Only the x (or only the y) partial derivatives.
    HeadingSigmaOneAxis,
    /// The partial derivatives over L (or L^3) where L^2 belongs.
    HeadingSigmaPartials,
    /// sigma_theta^2 returned.
    HeadingVariance,
    /// Both platforms given the weaker one's sigma.
    HeadingSigmaWeakerBoth,
    /// Q = diag(sigma_xy, sigma_xy, sigma_theta).
    DeviationAsVariance,
    /// sigma_xy from the stronger platform.
    StrongerPlatformNoise,
    /// Q's heading variance sigma_xy^2 instead of sigma_theta^2.
    HeadingNoiseFromPosition,
    /// d < radius: the boundary left out.
    FieldOfViewBoundary,
    /// x^2 + y^2 <= radius.
    FieldOfViewRadiusNotSquared,
    /// |x| <= radius and |y| <= radius.
    FieldOfViewSquare,
    /// mu_bar = the odometry's own pose.
    OdometryAsPrediction,
    /// The odometry's displacement not rotated into the frame of its previous pose (or
    /// rotated by mu's heading): mu_bar = mu + Rot(theta) (odom - odom_prev), or mu_bar =
    /// mu + (odom - odom_prev).
    IncrementNotRotated,
    /// R = diag(k_xy s, k_xy s, k_theta (s + |dtheta|)), not squared.
    ProcessDeviationAsVariance,
    /// G's third column with the signs flipped.
    PredictJacobianSign,
    /// Sigma_bar = Sigma + R: the Jacobian left out.
    PredictJacobianMissing,
    /// An angle out of [-pi, pi) in a returned pose.
    FusionHeadingNotWrapped,
    /// The heading's innovation not wrapped.
    FusionInnovationNotWrapped,
    /// d2 with S = Sigma_bar alone.
    MahalanobisWithoutQ,
    /// sqrt(d2).
    MahalanobisSquareRoot,
    /// K = Q S^-1: the measurement's covariance on top of the gain.
    GainWithQ,
    /// Sigma = (I + K) Sigma_bar.
    PosteriorSign,
    #[strum(serialize = "fusion_keeps_state")]
    KeepsState,
}

impl Mistake for HintKind {
    fn text(self) -> &'static str {
        match self {
            HintKind::WeightsNotNormalised => {
                "The position is the intensities times the positions without dividing by the \
                 sum of the intensities: the weights w_i = I_i / (I_1 + I_2) must sum to one, \
                 or the mean lands far from both platforms."
            }
            HintKind::UnweightedMean => {
                "The position is the plain mean of the two platforms: the brighter platform \
                 is read more precisely and weighs more, w_i = I_i / (I_1 + I_2)."
            }
            HintKind::PlatformsReversed => {
                "The heading points backwards: platform 1 is the front one, so the robot \
                 faces along the line from platform 2 to platform 1, theta = atan2(y_1 - y_2, \
                 x_1 - x_2)."
            }
            HintKind::AtanArgumentsSwapped => {
                "atan2 takes its arguments the other way round: atan2(y, x), the y \
                 difference first, theta = atan2(y_1 - y_2, x_1 - x_2)."
            }
            HintKind::HeadingSigmaOnePlatform => {
                "sigma_theta leaves out one platform: the heading depends on both platforms' \
                 positions, so error propagation sums the squared terms of all four \
                 coordinates, (d theta / d x_i sigma_i)^2 + (d theta / d y_i sigma_i)^2 for \
                 i = 1 and 2."
            }
            HintKind::HeadingSigmaOneAxis => {
                "sigma_theta leaves out the terms of one coordinate: the heading moves with \
                 the platforms' x and y alike, d theta / d x_1 = -dy / L^2 and d theta / d y_1 \
                 = dx / L^2 (the opposite for platform 2), and every one of the four terms \
                 counts."
            }
            HintKind::HeadingSigmaPartials => {
                "The partial derivatives of atan2(dy, dx) are over the squared distance \
                 between the platforms: d theta / d x_1 = -dy / L^2, d theta / d y_1 = dx / \
                 L^2, with L^2 = dx^2 + dy^2. Over L (or L^3) sigma_theta comes out L times \
                 too large (or too small)."
            }
            HintKind::HeadingVariance => {
                "The result is sigma_theta squared: error propagation sums squared terms to a \
                 variance; sigma_theta is its square root."
            }
            HintKind::HeadingSigmaWeakerBoth => {
                "sigma_theta gives both platforms the weaker one's standard deviation: for \
                 the heading each platform counts with its own, sigma_i = c_xy / I_i. (It is \
                 x and y of the mean that take the larger of the two.)"
            }
            HintKind::DeviationAsVariance => {
                "Q holds standard deviations where variances belong: the diagonal is \
                 sigma_xy^2, sigma_xy^2 and sigma_theta^2."
            }
            HintKind::StrongerPlatformNoise => {
                "sigma_xy comes from the stronger platform: the report takes the larger of \
                 the two platforms' standard deviations, the one of the weaker intensity, \
                 sigma_xy = c_xy / min(I_1, I_2)."
            }
            HintKind::HeadingNoiseFromPosition => {
                "Q's heading variance is the position's: the heading has its own standard \
                 deviation, sigma_theta from heading_sigma, and Q = diag(sigma_xy^2, \
                 sigma_xy^2, sigma_theta^2)."
            }
            HintKind::FieldOfViewBoundary => {
                "A pose exactly on the edge of the field of view is left out: the boundary \
                 belongs inside, sqrt(x^2 + y^2) <= radius."
            }
            HintKind::FieldOfViewRadiusNotSquared => {
                "The squared distance is compared with the radius itself: either compare \
                 x^2 + y^2 with radius^2, or the distance sqrt(x^2 + y^2) with the radius."
            }
            HintKind::FieldOfViewSquare => {
                "The field of view is a circle around the point under the detector, not a \
                 square: a pose is in view when its distance sqrt(x^2 + y^2) is at most the \
                 radius, not when |x| and |y| each are."
            }
            HintKind::OdometryAsPrediction => {
                "mu_bar is the odometry's own pose: that throws away every correction the \
                 sensor made, snapping the estimate back onto the odometry's drifting path. \
                 Apply the odometry's increment, the motion from odom_prev to odom in the \
                 robot's own frame, to mu."
            }
            HintKind::IncrementNotRotated => {
                "The odometry's displacement is not taken into the robot's frame: the \
                 increment is the motion in the frame of the odometry's previous pose, (dx, \
                 dy) = Rot(-theta_odom_prev) (odom - odom_prev), rotated by the odometry's \
                 heading (not the filter's), and it moves the estimate along the estimate's \
                 heading, mu += Rot(theta) (dx, dy). Where the filter's heading differs from \
                 the odometry's, the displacement added as it is goes astray."
            }
            HintKind::ProcessDeviationAsVariance => {
                "R holds standard deviations where variances belong: with s the distance \
                 moved, R = diag((k_xy s)^2, (k_xy s)^2, (k_theta (s + |dtheta|))^2)."
            }
            HintKind::PredictJacobianSign => {
                "G's heading column has the wrong signs: moving (dx, dy) along the heading \
                 theta, d x'/d theta = -sin(theta) dx - cos(theta) dy and d y'/d theta = \
                 cos(theta) dx - sin(theta) dy."
            }
            HintKind::PredictJacobianMissing => {
                "sigma_bar is sigma + R: the prediction carries the old uncertainty through \
                 the motion's Jacobian first, G sigma G^T + R, and a heading error turns into \
                 a position error as the robot moves."
            }
            HintKind::FusionHeadingNotWrapped => {
                "A returned heading lies outside [-pi, pi): wrap it, for example as a - 2 pi \
                 floor((a + pi) / (2 pi)), minding that JavaScript's % keeps the sign of its \
                 left operand (atan2 itself may return +pi)."
            }
            HintKind::FusionInnovationNotWrapped => {
                "The heading's innovation is not wrapped: z_theta - mu_theta of 3.1 and -3.1 \
                 is 0.08 the short way round, not -6.2. Wrap it to [-pi, pi) before using it."
            }
            HintKind::MahalanobisWithoutQ => {
                "d2 uses sigma_bar alone: the innovation's covariance is S = sigma_bar + Q, \
                 the prediction's uncertainty and the measurement's together, d2 = nu^T S^-1 \
                 nu."
            }
            HintKind::MahalanobisSquareRoot => {
                "The result is the Mahalanobis distance itself; the gate compares its square, \
                 d2 = nu^T S^-1 nu, with a chi-square quantile."
            }
            HintKind::GainWithQ => {
                "The gain weighs the innovation by the measurement's noise: K = sigma_bar \
                 S^-1, the prediction's covariance over S = sigma_bar + Q, so a noisy reading \
                 moves the estimate little. The Northstar report writes R for the measurement \
                 noise and Q for the process noise, the lab the other way round: a formula \
                 copied across swaps them."
            }
            HintKind::PosteriorSign => {
                "sigma grew in the update: the posterior covariance is (I - K) sigma_bar, \
                 smaller than sigma_bar, not (I + K) sigma_bar."
            }
            HintKind::KeepsState => {
                "The function answered a call differently when it was made again in a fresh \
                 copy of your file: it keeps something between calls (a belief, the last \
                 odometry). Work out every result from its arguments alone; the loop passes \
                 the belief and the odometry back in at every step."
            }
        }
    }
}

/// The classic mistake that explains a failing output, if one does (and only one).
pub fn diagnose(
    call: &Call,
    expected: &Answer,
    got: &Value,
    mismatches: &[Mismatch],
) -> Option<Hint> {
    if mismatches.is_empty() {
        return None;
    }
    let not_wrapped = HintKind::FusionHeadingNotWrapped.kind();
    if let Some(hint) = form_hint(call, expected, got, mismatches, None, not_wrapped) {
        return Some(hint);
    }
    the_only(
        mistakes(call, expected)
            .into_iter()
            .filter(|(_, alternative)| alternative != expected && call.answers(alternative, got))
            .map(|(kind, _)| kind),
    )
}

/// What each classic mistake makes of this call's answer.
fn mistakes(call: &Call, expected: &Answer) -> Vec<(HintKind, Answer)> {
    match (call, expected) {
        (Call::CombinePlatforms { p1, p2 }, Answer::Pose(right)) => {
            let (a, b) = (platform(p1), platform(p2));
            let theta = right[2];
            let (dx, dy) = (a.x - b.x, a.y - b.y);
            vec![
                (
                    HintKind::WeightsNotNormalised,
                    Answer::Pose([
                        a.intensity * a.x + b.intensity * b.x,
                        a.intensity * a.y + b.intensity * b.y,
                        theta,
                    ]),
                ),
                (
                    HintKind::UnweightedMean,
                    Answer::Pose([(a.x + b.x) / 2.0, (a.y + b.y) / 2.0, theta]),
                ),
                (
                    HintKind::PlatformsReversed,
                    Answer::Pose([right[0], right[1], libm::atan2(-dy, -dx)]),
                ),
                (
                    HintKind::AtanArgumentsSwapped,
                    Answer::Pose([right[0], right[1], wrap(libm::atan2(dx, dy))]),
                ),
            ]
        }
        (Call::HeadingSigma { p1, p2, c_xy }, Answer::Number(right)) => {
            let (a, b) = (platform(p1), platform(p2));
            let (s1, s2) = (c_xy / a.intensity, c_xy / b.intensity);
            let (dx, dy) = (a.x - b.x, a.y - b.y);
            let l2 = dx * dx + dy * dy;
            let both = (s1 * s1 + s2 * s2).sqrt();
            let number = Answer::Number;
            vec![
                (HintKind::HeadingSigmaOnePlatform, number(s1 / l2.sqrt())),
                (HintKind::HeadingSigmaOnePlatform, number(s2 / l2.sqrt())),
                (HintKind::HeadingSigmaOneAxis, number(both * dy.abs() / l2)),
                (HintKind::HeadingSigmaOneAxis, number(both * dx.abs() / l2)),
                (HintKind::HeadingSigmaPartials, number(both)),
                (HintKind::HeadingSigmaPartials, number(both / l2)),
                (HintKind::HeadingVariance, number(right * right)),
                (
                    HintKind::HeadingSigmaWeakerBoth,
                    number(2f64.sqrt() * s1.max(s2) / l2.sqrt()),
                ),
            ]
        }
        (Call::MeasurementNoise { p1, p2, c_xy }, Answer::Matrix3(_)) => {
            let m = measured(p1, p2, *c_xy);
            let stronger = c_xy / p1[2].max(p2[2]);
            let diagonal = |xy: f64, theta: f64| {
                Answer::Matrix3(rows(&Matrix3::from_diagonal(&Vector3::new(xy, xy, theta))))
            };
            // measurement_noise may call the student's own heading_sigma: each of its
            // mistakes shows in Q's heading variance.
            let heading = Call::HeadingSigma {
                p1: *p1,
                p2: *p2,
                c_xy: *c_xy,
            };
            let through_heading_sigma = mistakes(&heading, &Answer::Number(m.sigma_theta))
                .into_iter()
                .filter_map(|(kind, answer)| match answer {
                    Answer::Number(s) => Some((kind, diagonal(m.sigma_xy.powi(2), s * s))),
                    _ => None,
                });
            let mut own = vec![
                (
                    HintKind::DeviationAsVariance,
                    diagonal(m.sigma_xy, m.sigma_theta),
                ),
                (
                    HintKind::StrongerPlatformNoise,
                    diagonal(stronger * stronger, m.sigma_theta.powi(2)),
                ),
                (
                    HintKind::HeadingNoiseFromPosition,
                    diagonal(m.sigma_xy.powi(2), m.sigma_xy.powi(2)),
                ),
            ];
            own.extend(through_heading_sigma);
            own
        }
        (Call::InFieldOfView { z, radius }, _) => {
            let d2 = z[0] * z[0] + z[1] * z[1];
            vec![
                (
                    HintKind::FieldOfViewBoundary,
                    Answer::Flag(d2.sqrt() < *radius),
                ),
                (
                    HintKind::FieldOfViewRadiusNotSquared,
                    Answer::Flag(d2 <= *radius),
                ),
                (
                    HintKind::FieldOfViewSquare,
                    Answer::Flag(z[0].abs() <= *radius && z[1].abs() <= *radius),
                ),
            ]
        }
        (
            Call::Predict {
                mu,
                sigma,
                odom_prev,
                odom,
                k_xy,
                k_theta,
            },
            Answer::Prediction(right),
        ) => predict_mistakes(mu, sigma, *odom_prev, *odom, *k_xy, *k_theta, right),
        (
            Call::Mahalanobis {
                mu_bar,
                sigma_bar,
                z,
                q,
            },
            Answer::Number(right),
        ) => {
            let (mu, sigma, q) = (Vector3::from(*mu_bar), matrix_of(sigma_bar), matrix_of(q));
            let distance = |nu: Vector3<f64>, s: Matrix3<f64>| {
                s.try_inverse()
                    .map_or(f64::NAN, |inv| (nu.transpose() * inv * nu)[0])
            };
            let unwrapped = Vector3::from(*z) - mu;
            vec![
                (
                    HintKind::FusionInnovationNotWrapped,
                    Answer::Number(distance(unwrapped, sigma + q)),
                ),
                (
                    HintKind::MahalanobisWithoutQ,
                    Answer::Number(distance(innovation(&mu, &Vector3::from(*z)), sigma)),
                ),
                (
                    HintKind::MahalanobisSquareRoot,
                    Answer::Number(right.sqrt()),
                ),
            ]
        }
        (
            Call::Update {
                mu_bar,
                sigma_bar,
                z,
                q,
            },
            _,
        ) => update_mistakes(mu_bar, sigma_bar, z, q),
        // An answer of another function's shape: no call of the exercise gives one.
        _ => Vec::new(),
    }
}

/// The prediction's mistakes: the odometry's pose taken for the prediction, its
/// displacement added in its own frame, the process noise's deviations taken for
/// variances, the Jacobian's signs flipped or the Jacobian left out.
fn predict_mistakes(
    mu: &[f64; 3],
    sigma: &[[f64; 3]; 3],
    odom_prev: [f64; 3],
    odom: [f64; 3],
    k_xy: f64,
    k_theta: f64,
    right: &Prediction,
) -> Vec<(HintKind, Answer)> {
    let settings = Settings {
        process_xy: k_xy,
        process_theta: k_theta,
        ..Settings::default()
    };
    let (mu, sigma) = (Vector3::from(*mu), matrix_of(sigma));
    let u = increment(odom_prev, odom);
    let answer = |mu_bar: Vector3<f64>, sigma_bar: Matrix3<f64>| {
        Answer::Prediction(Prediction {
            mu_bar: mu_bar.into(),
            sigma_bar: rows(&sigma_bar),
        })
    };
    // The odometry's displacement in the world taken for the increment, not rotated into
    // the frame of its previous pose; and rotated by mu's heading instead, which adds the
    // displacement to mu as it is (as does a student's mu + (odom - odom_prev) with the
    // covariance right).
    let (sin, cos) = libm::sincos(mu.z);
    let world = Vector3::new(odom[0] - odom_prev[0], odom[1] - odom_prev[1], u.z);
    let (unrotated_mu, unrotated_sigma) = predict(&mu, &sigma, &world, &settings);
    let in_mu_frame = Vector3::new(
        cos * world.x + sin * world.y,
        -sin * world.x + cos * world.y,
        u.z,
    );
    let (added_mu, added_sigma) = predict(&mu, &sigma, &in_mu_frame, &settings);
    // R and G as the reference makes them.
    let moved = libm::hypot(u.x, u.y);
    let deviations = Vector3::new(k_xy * moved, k_xy * moved, k_theta * (moved + u.z.abs()));
    let r = Matrix3::from_diagonal(&deviations.component_mul(&deviations));
    let mut g = Matrix3::identity();
    g[(0, 2)] = -sin * u.x - cos * u.y;
    g[(1, 2)] = cos * u.x - sin * u.y;
    let mut flipped = g;
    flipped[(0, 2)] = -g[(0, 2)];
    flipped[(1, 2)] = -g[(1, 2)];
    let right_mu = Vector3::from(right.mu_bar);
    let propagated = |g: &Matrix3<f64>, r: &Matrix3<f64>| {
        let s = g * sigma * g.transpose() + r;
        (s + s.transpose()) / 2.0
    };
    vec![
        (
            HintKind::OdometryAsPrediction,
            answer(Vector3::from(odom), matrix_of(&right.sigma_bar)),
        ),
        (
            HintKind::IncrementNotRotated,
            answer(unrotated_mu, unrotated_sigma),
        ),
        (HintKind::IncrementNotRotated, answer(added_mu, added_sigma)),
        (
            HintKind::IncrementNotRotated,
            answer(added_mu, matrix_of(&right.sigma_bar)),
        ),
        (
            HintKind::ProcessDeviationAsVariance,
            answer(
                right_mu,
                propagated(&g, &Matrix3::from_diagonal(&deviations)),
            ),
        ),
        (
            HintKind::PredictJacobianSign,
            answer(right_mu, propagated(&flipped, &r)),
        ),
        (
            HintKind::PredictJacobianMissing,
            answer(right_mu, propagated(&Matrix3::identity(), &r)),
        ),
    ]
}

/// The update's mistakes: the heading's innovation not wrapped, the gain with Q on top,
/// the posterior's covariance grown.
fn update_mistakes(
    mu_bar: &[f64; 3],
    sigma_bar: &[[f64; 3]; 3],
    z: &[f64; 3],
    q: &[[f64; 3]; 3],
) -> Vec<(HintKind, Answer)> {
    let (mu, sigma, z, q) = (
        Vector3::from(*mu_bar),
        matrix_of(sigma_bar),
        Vector3::from(*z),
        matrix_of(q),
    );
    let Some(s_inv) = (sigma + q).try_inverse() else {
        return Vec::new();
    };
    let posterior = |gain: Matrix3<f64>, nu: Vector3<f64>, sign: f64| {
        let mut after = mu + gain * nu;
        after.z = wrap(after.z);
        let s = (Matrix3::identity() + sign * gain) * sigma;
        Answer::Posterior(Posterior {
            mu: after.into(),
            sigma: rows(&((s + s.transpose()) / 2.0)),
        })
    };
    let k = sigma * s_inv;
    let nu = innovation(&mu, &z);
    vec![
        (
            HintKind::FusionInnovationNotWrapped,
            posterior(k, z - mu, -1.0),
        ),
        (HintKind::GainWithQ, posterior(q * s_inv, nu, -1.0)),
        (HintKind::PosteriorSign, posterior(k, nu, 1.0)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exercises::sensor_fusion::generate;
    use crate::grading::testing::each_mistake_gets_its_hint;
    use strum::VariantArray;

    /// Every mistake made in a case gets its own hint, unless another mistake gives the
    /// same answer there (then none); every mistake shows in the cases of every seed; and
    /// a right answer gets no hint. (A heading out of [-pi, pi) is told by its form, and a
    /// function that keeps state by its repeat: neither is an answer made here.)
    #[test]
    fn each_mistake_gets_its_hint_and_a_right_answer_none() {
        let shown_in_every_seed: Vec<HintKind> = HintKind::VARIANTS
            .iter()
            .copied()
            .filter(|kind| {
                !matches!(
                    kind,
                    HintKind::FusionHeadingNotWrapped | HintKind::KeepsState
                )
            })
            .collect();
        each_mistake_gets_its_hint(
            generate,
            1..=40,
            mistakes,
            |_, _, _| false,
            &shown_in_every_seed,
        );
    }
}
