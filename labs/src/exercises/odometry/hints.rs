//! Hints for the classic mistakes of the odometry exercise: when a failing output is
//! exactly what a mistake gives, say which. Each check recomputes the answer with the
//! mistake made, with the model of [`crate::odometry`] on changed arguments (another
//! heading, wheel base or order of the wheels, a transposed Jacobian) or from the
//! expected output (a sign, a term left out), and compares the student's output with it.

use super::contract::{Answer, Call};
use crate::grading::{
    Contract, Hint, Mismatch, Mistake, form_hint, matrix_of, negated, rows, the_only,
};
use crate::odometry::{
    Increment, increment_jacobian, pose_jacobian, propagate_through, step, wheel_noise,
};
use nalgebra::{Matrix2, Matrix3x2, Vector3};
use serde_json::Value;

/// A classic mistake of the odometry exercise, named uniquely across the exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantArray)]
#[strum(serialize_all = "snake_case")]
pub enum HintKind {
    /// The step taken along theta or theta + dtheta instead of theta + dtheta/2.
    MidpointHeading,
    /// dtheta divided by 2b or b/2: b taken for the distance from the centre to a wheel.
    HalfAxle,
    HeadingNotWrapped,
    /// dtheta = (ds_l - ds_r) / b.
    TurnReversed,
    PoseJacobianSign,
    PoseJacobianTransposed,
    IncrementJacobianSign,
    IncrementJacobianTransposed,
    /// F_delta with phi held fixed: the ds/(2b) terms left out.
    IncrementJacobianTurn,
    /// F_delta's turn terms ds/b where ds/(2b) belongs.
    IncrementJacobianTurnDoubled,
    /// F_delta's columns in the order (ds_l, ds_r).
    IncrementJacobianColumnsSwapped,
    /// k |ds| without the absolute value.
    NegativeWheelVariance,
    /// sqrt(k |ds|): the wheel's standard deviation in place of its variance.
    WheelDeviation,
    /// k ds^2: the variance growing with the distance squared.
    WheelVarianceSquared,
    /// A wheel's distance with the other wheel's constant, or the wheels in the other order.
    WheelConstantsSwapped,
    /// F_p^T Sigma_p F_p.
    PropagateTransposed,
    /// Sigma_delta padded to 3 x 3 and added as it is, or left out.
    WheelNoiseNotMapped,
    #[strum(serialize = "odometry_keeps_state")]
    KeepsState,
}

impl Mistake for HintKind {
    fn text(self) -> &'static str {
        match self {
            HintKind::MidpointHeading => {
                "The result follows another heading than the step's: over a step the robot \
                 drives the chord of an arc, which points halfway through the turn, phi = \
                 theta + dtheta/2, in x' = x + ds cos(phi), y' = y + ds sin(phi) and in both \
                 Jacobians; not theta, the heading before the step, nor theta + dtheta, the \
                 heading after it."
            }
            HintKind::HalfAxle => {
                "The robot turns twice or half as much as it should: dtheta = (ds_r - ds_l) \
                 / b, where b is the whole distance between the two wheels. Dividing by 2b \
                 or by b/2 takes b for the distance from the centre to a wheel, or that \
                 distance for b."
            }
            HintKind::HeadingNotWrapped => {
                "The new heading lies outside [-pi, pi): wrap theta + dtheta, for example \
                 as a - 2 pi floor((a + pi) / (2 pi)), minding that JavaScript's % keeps \
                 the sign of its left operand."
            }
            HintKind::TurnReversed => {
                "The robot turns the wrong way: when the right wheel rolls further than the \
                 left, the robot turns left (counter-clockwise) and its heading grows, \
                 dtheta = (ds_r - ds_l) / b, not (ds_l - ds_r) / b."
            }
            HintKind::PoseJacobianSign => {
                "Some elements of F_p have the right size and the wrong sign: \
                 differentiating x' = x + ds cos(phi) and y' = y + ds sin(phi) by theta \
                 gives d x'/d theta = -ds sin(phi) and d y'/d theta = +ds cos(phi), with \
                 phi = theta + dtheta/2."
            }
            HintKind::PoseJacobianTransposed => {
                "F_p came back transposed: row i holds the derivatives of x', y' or theta' \
                 and column j those by x, y or theta, so the heading's terms -ds sin(phi) \
                 and ds cos(phi) stand in the last column, F_p[0][2] and F_p[1][2]."
            }
            HintKind::IncrementJacobianSign => {
                "Some elements of F_delta have the right size and the wrong sign: the right \
                 wheel turns the robot left, so d theta'/d ds_r = +1/b and d theta'/d ds_l \
                 = -1/b, and the turn terms are -ds sin(phi)/(2b) in x' and +ds cos(phi)/(2b) \
                 in y' in the right wheel's column, with the opposite signs in the left's."
            }
            HintKind::IncrementJacobianTransposed => {
                "F_delta came back 2 x 3, the transpose of what it should be: it is 3 x 2, a \
                 row per component of the pose (x', y', theta') and a column per wheel \
                 (ds_r, then ds_l)."
            }
            HintKind::IncrementJacobianTurn => {
                "F_delta holds the direction of the step fixed: phi = theta + (ds_r - ds_l) \
                 / (2b) depends on the wheels too, which adds -ds sin(phi)/(2b) to d x'/d \
                 ds_r and +ds cos(phi)/(2b) to d y'/d ds_r, and the opposite to the left \
                 wheel's column, besides cos(phi)/2 and sin(phi)/2."
            }
            HintKind::IncrementJacobianTurnDoubled => {
                "F_delta's turn terms are twice what they should be: the heading of the \
                 step, phi = theta + (ds_r - ds_l) / (2b), moves by 1/(2b) per unit of a \
                 wheel (half of dtheta's 1/b), so the terms are -ds sin(phi)/(2b) and +ds \
                 cos(phi)/(2b) in the right wheel's column (opposite in the left's), not \
                 ds sin(phi)/b. Only theta' itself moves by 1/b."
            }
            HintKind::IncrementJacobianColumnsSwapped => {
                "F_delta's columns are the wrong way round: the first column holds the \
                 derivatives by the right wheel's distance ds_r, the second those by ds_l, \
                 so the last row reads [1/b, -1/b]. This is the order, not a sign."
            }
            HintKind::WheelDeviation => {
                "Sigma_delta holds standard deviations, not variances: a wheel's variance \
                 is proportional to the distance it rolled, Sigma_delta = diag(k_r |ds_r|, \
                 k_l |ds_l|), without a square root."
            }
            HintKind::WheelVarianceSquared => {
                "Sigma_delta grows with the square of the distance: in this model a \
                 wheel's variance grows linearly with the distance it rolled (the errors of \
                 its small pieces add up), Sigma_delta = diag(k_r |ds_r|, k_l |ds_l|), not \
                 k ds^2."
            }
            HintKind::NegativeWheelVariance => {
                "A wheel that rolled backwards got a negative variance: a wheel's error grows \
                 with the distance it rolled whichever way, Sigma_delta = diag(k_r |ds_r|, \
                 k_l |ds_l|), and no variance is negative."
            }
            HintKind::WheelConstantsSwapped => {
                "Sigma_delta pairs a wheel's distance with the other wheel's constant, or \
                 lists the wheels the other way round: the right wheel comes first, as in \
                 F_delta's columns, each with its own constant: diag(k_r |ds_r|, k_l |ds_l|)."
            }
            HintKind::PropagateTransposed => {
                "Sigma_p' is what F_p^T Sigma_p F_p + F_delta Sigma_delta F_delta^T gives: \
                 the pose's covariance goes through the step the other way round, F_p \
                 Sigma_p F_p^T."
            }
            HintKind::WheelNoiseNotMapped => {
                "The wheels' noise does not reach the pose through F_delta: Sigma_delta is \
                 the covariance of the two wheel distances (2 x 2), and what it adds to the \
                 pose's covariance is F_delta Sigma_delta F_delta^T (3 x 3). Padded with \
                 zeros it puts wheel variances on x and y; left out it adds nothing."
            }
            HintKind::KeepsState => {
                "The function answered a call differently when it was made again in a fresh \
                 copy of your file: it keeps something between calls (a pose, a covariance, \
                 a wheel base). Work out every result from its arguments alone; the path \
                 loop passes the pose and the covariance back in at every step."
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
    let gives = |alternative: &Answer| call.answers(alternative, got);
    let transposed = matches!(call, Call::IncrementJacobian { .. })
        .then_some(HintKind::IncrementJacobianTransposed.kind());
    let not_wrapped = HintKind::HeadingNotWrapped.kind();
    if let Some(hint) = form_hint(call, expected, got, mismatches, transposed, not_wrapped) {
        return Some(hint);
    }
    let kinds = mistakes(call, expected)
        .into_iter()
        .filter(|(_, alternative)| gives(alternative))
        .map(|(kind, _)| kind);
    the_only(kinds.chain(sign_flipped(call, mismatches)))
}

/// The sign mistake of a Jacobian whose every mismatch is a sign flipped. (On the spot,
/// ds = 0, F_delta's columns swapped flip the signs of its last row too: both explain the
/// answer then, and neither is said.)
fn sign_flipped(call: &Call, mismatches: &[Mismatch]) -> Option<HintKind> {
    if !mismatches.iter().all(|m| negated(&m.expected, &m.got)) {
        return None;
    }
    match call {
        Call::PoseJacobian { .. } => Some(HintKind::PoseJacobianSign),
        Call::IncrementJacobian { .. } => Some(HintKind::IncrementJacobianSign),
        _ => None,
    }
}

/// What each classic mistake makes of this call's answer.
fn mistakes(call: &Call, expected: &Answer) -> Vec<(HintKind, Answer)> {
    match (call, expected) {
        (Call::OdometryStep { p, ds_r, ds_l, b }, Answer::Pose(right)) => {
            let model = Step::new(p, *ds_r, *ds_l, *b);
            let at = |p: &Vector3<f64>, increment, b| step(p, increment, b);
            model.variants(
                // Only x' and y' follow another heading; theta' stays.
                |p| {
                    let q = at(p, model.increment, model.b);
                    Answer::Pose([q.x, q.y, right[2]])
                },
                |b| Answer::Pose(at(&model.p, model.increment, b).into()),
                Answer::Pose(at(&model.p, model.swapped(), model.b).into()),
            )
        }
        (Call::PoseJacobian { p, ds_r, ds_l, b }, Answer::Matrix3(right)) => {
            let model = Step::new(p, *ds_r, *ds_l, *b);
            let at = |p: &Vector3<f64>, increment, b| {
                Answer::Matrix3(rows(&pose_jacobian(p, increment, b)))
            };
            let mut variants = model.variants(
                |p| at(p, model.increment, model.b),
                |b| at(&model.p, model.increment, b),
                at(&model.p, model.swapped(), model.b),
            );
            variants.push((
                HintKind::PoseJacobianTransposed,
                Answer::Matrix3(rows(&matrix_of(right).transpose())),
            ));
            variants
        }
        (Call::IncrementJacobian { p, ds_r, ds_l, b }, _) => {
            let model = Step::new(p, *ds_r, *ds_l, *b);
            let at = |p: &Vector3<f64>, increment, b| increment_jacobian(p, increment, b);
            // The robot turning the other way throughout, (ds_l - ds_r) / b: the model of
            // the wheels swapped, whose first column is the derivative by ds_l.
            let reversed = at(&model.p, model.swapped(), model.b);
            let mut variants = model.variants(
                |p| Answer::Matrix3x2(rows(&at(p, model.increment, model.b))),
                |b| Answer::Matrix3x2(rows(&at(&model.p, model.increment, b))),
                Answer::Matrix3x2(rows(&Matrix3x2::from_columns(&[
                    reversed.column(1),
                    reversed.column(0),
                ]))),
            );
            // phi held fixed: each wheel moves the pose by cos(phi)/2, sin(phi)/2 alone,
            // the mean of the two columns' first rows (their turn terms cancel).
            let mut fixed = at(&model.p, model.increment, model.b);
            let mean = (fixed.column(0) + fixed.column(1)) / 2.0;
            for j in 0..2 {
                fixed[(0, j)] = mean[0];
                fixed[(1, j)] = mean[1];
            }
            variants.push((
                HintKind::IncrementJacobianTurn,
                Answer::Matrix3x2(rows(&fixed)),
            ));
            // The turn terms doubled: the right answer's distance from the fixed one, twice.
            let right = at(&model.p, model.increment, model.b);
            let doubled = fixed + (right - fixed) * 2.0;
            variants.push((
                HintKind::IncrementJacobianTurnDoubled,
                Answer::Matrix3x2(rows(&doubled)),
            ));
            variants.push((
                HintKind::IncrementJacobianColumnsSwapped,
                Answer::Matrix3x2(rows(&Matrix3x2::from_columns(&[
                    right.column(1),
                    right.column(0),
                ]))),
            ));
            variants
        }
        (
            Call::WheelNoise {
                ds_r,
                ds_l,
                k_r,
                k_l,
            },
            _,
        ) => {
            let increment = Increment::new(*ds_r, *ds_l);
            let swapped = Increment::new(*ds_l, *ds_r);
            let noise =
                |increment, k_r, k_l| Answer::Matrix2(rows(&wheel_noise(increment, k_r, k_l)));
            let signed = wheel_noise(increment, *k_r, *k_l).component_mul(&Matrix2::new(
                ds_r.signum(),
                1.0,
                1.0,
                ds_l.signum(),
            ));
            let variance = wheel_noise(increment, *k_r, *k_l);
            vec![
                (
                    HintKind::NegativeWheelVariance,
                    Answer::Matrix2(rows(&signed)),
                ),
                (
                    HintKind::WheelDeviation,
                    Answer::Matrix2(rows(&variance.map(f64::sqrt))),
                ),
                (
                    HintKind::WheelVarianceSquared,
                    Answer::Matrix2(rows(&Matrix2::new(
                        k_r * ds_r * ds_r,
                        0.0,
                        0.0,
                        k_l * ds_l * ds_l,
                    ))),
                ),
                (
                    HintKind::WheelConstantsSwapped,
                    noise(increment, *k_l, *k_r),
                ),
                (HintKind::WheelConstantsSwapped, noise(swapped, *k_r, *k_l)),
                (HintKind::WheelConstantsSwapped, noise(swapped, *k_l, *k_r)),
            ]
        }
        (
            Call::Propagate {
                sigma_p,
                f_p,
                f_delta,
                sigma_delta,
            },
            _,
        ) => {
            let (sigma_p, f_p, f_delta, sigma_delta) = (
                matrix_of(sigma_p),
                matrix_of(f_p),
                matrix_of(f_delta),
                matrix_of(sigma_delta),
            );
            let propagated = |f_p, f_delta, sigma_delta| {
                Answer::Matrix3(rows(&propagate_through(
                    &sigma_p,
                    f_p,
                    f_delta,
                    sigma_delta,
                )))
            };
            // Sigma_delta padded with zeros: what the identity's first two columns give.
            let padding = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
            vec![
                (
                    HintKind::PropagateTransposed,
                    propagated(&f_p.transpose(), &f_delta, &sigma_delta),
                ),
                (
                    HintKind::WheelNoiseNotMapped,
                    propagated(&f_p, &padding, &sigma_delta),
                ),
                (
                    HintKind::WheelNoiseNotMapped,
                    propagated(&f_p, &f_delta, &Matrix2::zeros()),
                ),
            ]
        }
        // An answer of another function's shape: no call of the exercise gives one.
        _ => Vec::new(),
    }
}

/// The arguments of one step, for the mistakes of the three functions of a step.
struct Step {
    p: Vector3<f64>,
    increment: Increment,
    b: f64,
}

impl Step {
    fn new(p: &[f64; 3], ds_r: f64, ds_l: f64, b: f64) -> Step {
        Step {
            p: Vector3::from(*p),
            increment: Increment::new(ds_r, ds_l),
            b,
        }
    }

    /// The wheels the other way round.
    fn swapped(&self) -> Increment {
        Increment::new(self.increment.left, self.increment.right)
    }

    /// The mistakes every function of a step can make, from the function's answer at
    /// another pose (`turned`: the midpoint heading moved), with another wheel base
    /// (`wheel_base`), and its answer with the robot turning the other way (`reversed`).
    fn variants(
        &self,
        turned: impl Fn(&Vector3<f64>) -> Answer,
        wheel_base: impl Fn(f64) -> Answer,
        reversed: Answer,
    ) -> Vec<(HintKind, Answer)> {
        let (_, dtheta) = self.increment.displacement(self.b);
        // The heading before the step, theta, and after it, theta + dtheta, in place of
        // theta + dtheta/2.
        let shifted = |shift: f64| Vector3::new(self.p.x, self.p.y, self.p.z + shift);
        vec![
            (HintKind::MidpointHeading, turned(&shifted(-dtheta / 2.0))),
            (HintKind::MidpointHeading, turned(&shifted(dtheta / 2.0))),
            (HintKind::HalfAxle, wheel_base(2.0 * self.b)),
            (HintKind::HalfAxle, wheel_base(self.b / 2.0)),
            (HintKind::TurnReversed, reversed),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exercises::odometry::generate;
    use crate::grading::testing::{diagnosed, each_mistake_gets_its_hint};
    use crate::grading::transpose;
    use serde_json::json;
    use std::f64::consts::TAU;

    /// Every mistake made in a case gets its own hint, unless another mistake gives the
    /// same answer there, or a sign flipped explains it (then none); every mistake shows in
    /// the cases of every seed; and a right answer gets no hint.
    #[test]
    fn each_mistake_gets_its_hint_and_a_right_answer_none() {
        each_mistake_gets_its_hint(
            generate,
            1..=40,
            mistakes,
            |call, mismatches, kind| {
                sign_flipped(call, mismatches).is_some_and(|sign| sign.kind() != kind)
            },
            &[
                HintKind::MidpointHeading,
                HintKind::HalfAxle,
                HintKind::TurnReversed,
                HintKind::PoseJacobianTransposed,
                HintKind::IncrementJacobianTurn,
                HintKind::IncrementJacobianTurnDoubled,
                HintKind::IncrementJacobianColumnsSwapped,
                HintKind::NegativeWheelVariance,
                HintKind::WheelDeviation,
                HintKind::WheelVarianceSquared,
                HintKind::WheelConstantsSwapped,
                HintKind::PropagateTransposed,
                HintKind::WheelNoiseNotMapped,
            ],
        );
    }

    /// A sign flipped, a Jacobian transposed, a heading not wrapped and a covariance not
    /// symmetrised, each in the cases where it shows.
    #[test]
    fn signs_transposes_wrapping_and_symmetry_are_recognised() {
        let hint = |kind: HintKind| Some(kind.kind());
        for seed in 1..=20 {
            for case in generate(seed, 6) {
                let mut wrong = case.expected.clone();
                match &case.call {
                    Call::PoseJacobian { ds_r, ds_l, .. } if ds_r + ds_l != 0.0 => {
                        wrong[0][2] = json!(-wrong[0][2].as_f64().unwrap());
                        assert_eq!(diagnosed(&case, &wrong), hint(HintKind::PoseJacobianSign));
                    }
                    Call::IncrementJacobian { ds_r, ds_l, .. } => {
                        // On the spot (ds = 0) the columns differ in the last row only,
                        // and this is the columns swapped too: no hint then.
                        let sign = (ds_r + ds_l != 0.0).then_some(HintKind::IncrementJacobianSign);
                        let reversed = [wrong[2][1].clone(), wrong[2][0].clone()];
                        wrong[2] = json!(reversed);
                        assert_eq!(
                            diagnosed(&case, &wrong),
                            sign.and_then(hint),
                            "seed {seed}, {}",
                            case.id
                        );
                        let transposed = transpose(&case.expected).unwrap();
                        assert_eq!(
                            diagnosed(&case, &transposed),
                            hint(HintKind::IncrementJacobianTransposed)
                        );
                    }
                    Call::OdometryStep { p, .. } => {
                        let heading = case.expected[2].as_f64().unwrap();
                        // Unwrapped, the heading stays on the side it started from.
                        if heading * p[2] < 0.0 {
                            wrong[2] = json!(heading + TAU * p[2].signum());
                            assert_eq!(diagnosed(&case, &wrong), hint(HintKind::HeadingNotWrapped));
                        }
                    }
                    Call::Propagate { .. } => {
                        let a = wrong[0][1].as_f64().unwrap();
                        wrong[0][1] = json!(a + a.abs() * f64::EPSILON);
                        assert_eq!(
                            diagnosed(&case, &wrong),
                            Some(crate::grading::Common::NotSymmetrised.kind())
                        );
                    }
                    _ => {}
                }
            }
        }
    }
}
