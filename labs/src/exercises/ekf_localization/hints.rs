//! Hints: when a failing output is exactly what a classic mistake would give, say which
//! mistake. Each check recomputes the reference with the mistake made (wheels swapped, an
//! index off by one, a product transposed, ...) and compares the student's output with it.

use super::contract::{Answer, Association, BatchAssociation, Call, reference};
use crate::angle::wrap;
use crate::ekf::motion_jacobian;
use crate::grading::{
    Contract, Hint, Mismatch, Mistake, form_hint, holds_non_finite, matrix_of, negated, rows,
};
use nalgebra::Vector2;
use serde_json::Value;
use std::f64::consts::TAU;

#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantArray)]
#[strum(serialize_all = "snake_case")]
pub enum HintKind {
    BearingNotWrapped,
    JacobianSign,
    JacobianTransposed,
    OneBasedIndex,
    ThresholdStrict,
    WheelsSwapped,
    FirstStep,
    PredictTransposed,
    #[strum(serialize = "r_q_swapped")]
    RQSwapped,
    StaleAssociation,
    NearestMahalanobis,
    NearestInnovation,
    OutlierOtherLandmark,
    OdometryHeading,
    AbsoluteHeading,
    BatchQBar,
}

impl Mistake for HintKind {
    fn text(self) -> &'static str {
        match self {
            HintKind::BearingNotWrapped => {
                "A bearing lies outside [-pi, pi): wrap every angle you compute, for example \
                 as ((b + pi) mod 2 pi) - pi, minding that JavaScript's % keeps the sign of \
                 its left operand."
            }
            HintKind::JacobianSign => {
                "Some elements of H have the right size and the wrong sign: differentiate \
                 with respect to the robot's x, y and theta (not the landmark's), e.g. \
                 d range / dx = -(m_x - x) / range."
            }
            HintKind::JacobianTransposed => {
                "H came back 3 x 2, the transpose of what it should be: H is 2 x 3, a row \
                 per measurement component (range, bearing) and a column per state \
                 component (x, y, theta)."
            }
            HintKind::OneBasedIndex => {
                "The result belongs to the neighbouring landmark: indices are 0-based in \
                 JavaScript (landmark j is M[0][j], M[1][j], and c counts from 0), not \
                 1-based as in MATLAB."
            }
            HintKind::ThresholdStrict => {
                "A reading exactly on the threshold (D_M = Lambda_M) is an outlier: the \
                 test is D_M >= Lambda_M, not >."
            }
            HintKind::WheelsSwapped => {
                "The control is what the two wheels swapped would give: e_R and R_R belong \
                 to the right wheel, and omega = (omega_R R_R - omega_L R_L) / B."
            }
            HintKind::FirstStep => {
                "At the first step delta_t is 0: return u = [0, 0, 0] then, instead of \
                 dividing by delta_t."
            }
            HintKind::PredictTransposed => {
                "sigma_bar is what G^T Sigma G + R gives: the product goes the other way \
                 round, G Sigma G^T + R."
            }
            HintKind::RQSwapped => {
                "init returned R as a 2 x 2 and Q as a 3 x 3 matrix: in this lab (as in \
                 Probabilistic Robotics) R is the process noise (3 x 3) and Q the \
                 measurement noise (2 x 2); the lectures use the letters the other way \
                 round."
            }
            HintKind::StaleAssociation => {
                "The same call gave another answer in a fresh copy of your file: the \
                 function keeps state between calls (a stale association from an earlier \
                 reading?). Compute every result from its arguments alone."
            }
            HintKind::NearestMahalanobis => {
                "c is the landmark of the smallest Mahalanobis distance D_j, which is not the \
                 most likely one: the likelihood psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2) \
                 also weighs the normalisation, which favours a landmark with a smaller S_j. \
                 Take the largest psi_j, or the smallest D_j + ln det(2 pi S_j)."
            }
            HintKind::NearestInnovation => {
                "c is the landmark of the shortest innovation nu_j, counting metres and \
                 radians alike: an innovation is only small or large relative to its \
                 covariance S_j. Take the largest likelihood psi_j = det(2 pi S_j)^(-1/2) \
                 exp(-D_j / 2), D_j = nu_j^T S_j^-1 nu_j."
            }
            HintKind::OutlierOtherLandmark => {
                "The outlier flag was decided on another landmark's distance (the first, the \
                 last, the smallest or any D_j): a reading is an outlier when the distance \
                 of the landmark it is associated with reaches the gate, D_c >= Lambda_M."
            }
            HintKind::OdometryHeading => {
                "The x and y of u follow another heading than the lab's: eq. 4 moves the \
                 robot along the heading of mu before the step, [v dt cos(theta), v dt \
                 sin(theta)] with theta = mu[2], not the heading after the step or halfway \
                 through it."
            }
            HintKind::AbsoluteHeading => {
                "u[2] is the new heading theta + omega dt: u is the change of the pose over \
                 the step, u[2] = omega dt, which predict adds to mu."
            }
            HintKind::BatchQBar => {
                "The result is what S = H_bar Sigma_bar H_bar^T + q I gives, with the range \
                 variance q all along the diagonal: add the whole Q_bar = blkdiag(Q, ..., \
                 Q), whose bearing entries hold the bearing variance."
            }
        }
    }
}

/// The classic mistake that explains a failing output, if one does.
pub fn diagnose(
    call: &Call,
    expected: &Answer,
    got: &Value,
    mismatches: &[Mismatch],
) -> Option<Hint> {
    let gives =
        |alternative: Option<Answer>| alternative.is_some_and(|alt| call.answers(&alt, got));
    if holds_non_finite(got) {
        match call {
            Call::CalculateOdometry { delta_t, .. } if *delta_t == 0.0 => {
                return Some(HintKind::FirstStep.hint());
            }
            Call::ObservationModel { j: 0, .. } | Call::JacobianObservationModel { j: 0, .. } => {
                return Some(HintKind::OneBasedIndex.hint());
            }
            _ => {}
        }
    }
    let transposed = matches!(call, Call::JacobianObservationModel { .. })
        .then_some(HintKind::JacobianTransposed.kind());
    let not_wrapped = HintKind::BearingNotWrapped.kind();
    if let Some(hint) = form_hint(call, expected, got, mismatches, transposed, not_wrapped) {
        return Some(hint);
    }
    let kind = match call {
        Call::CalculateOdometry { delta_t, .. } if *delta_t == 0.0 => Some(HintKind::FirstStep),
        Call::CalculateOdometry { .. } => {
            if gives(reference(&swap_wheels(call)).ok()) {
                Some(HintKind::WheelsSwapped)
            } else if gives(absolute_heading(call, expected)) {
                Some(HintKind::AbsoluteHeading)
            } else {
                // The heading after the step (theta + omega dt) or halfway through it.
                [1.0, 0.5]
                    .iter()
                    .any(|&k| gives(reference(&heading_moved(call, k)).ok()))
                    .then_some(HintKind::OdometryHeading)
            }
        }
        Call::ObservationModel { j, .. } | Call::JacobianObservationModel { j, .. } => (*j > 0
            && gives(reference(&with_landmark(call, j - 1)).ok()))
        .then_some(HintKind::OneBasedIndex)
        .or_else(|| {
            (matches!(call, Call::JacobianObservationModel { .. })
                && mismatches.iter().all(|m| negated(&m.expected, &m.got)))
            .then_some(HintKind::JacobianSign)
        }),
        Call::Associate { lambda_m, .. } => {
            let Answer::Association(expected) = expected else {
                return None;
            };
            if mismatches.iter().any(|m| m.path == "outlier")
                && mahalanobis_of_choice(expected).is_some_and(|d| d == *lambda_m)
            {
                Some(HintKind::ThresholdStrict)
            } else {
                association_hint(mismatches, |rule| {
                    gives(rule.associate(expected, *lambda_m).map(Answer::Association))
                })
            }
        }
        Call::BatchAssociate { .. } => association_hint(mismatches, |rule| {
            gives(rule.batch_associate(call).map(Answer::BatchAssociation))
        }),
        Call::Predict { .. } => {
            gives(transposed_prediction(call)).then_some(HintKind::PredictTransposed)
        }
        Call::Update { .. } => None,
        Call::BatchUpdate { .. } => {
            gives(reference(&range_variance_only(call)).ok()).then_some(HintKind::BatchQBar)
        }
    };
    kind.map(HintKind::hint)
}

fn swap_wheels(call: &Call) -> Call {
    let mut swapped = call.clone();
    if let Call::CalculateOdometry {
        e_r, e_l, r_r, r_l, ..
    } = &mut swapped
    {
        std::mem::swap(e_r, e_l);
        std::mem::swap(r_r, r_l);
    }
    swapped
}

fn with_landmark(call: &Call, index: usize) -> Call {
    let mut other = call.clone();
    if let Call::ObservationModel { j, .. } | Call::JacobianObservationModel { j, .. } = &mut other
    {
        *j = index;
    }
    other
}

/// Every differing index is one more than the expected one.
fn index_plus_one(mismatches: &[Mismatch]) -> bool {
    let indices: Vec<&Mismatch> = mismatches
        .iter()
        .filter(|m| m.path == "c" || m.path.starts_with("c["))
        .collect();
    !indices.is_empty()
        && indices
            .iter()
            .all(|m| match (m.expected.as_u64(), m.got.as_u64()) {
                (Some(e), Some(g)) => g == e + 1,
                _ => false,
            })
}

/// D_M of the landmark the reference chose: nu^T S^-1 nu from the expected output.
fn mahalanobis_of_choice(expected: &Association) -> Option<f64> {
    candidates(expected)?
        .get(expected.c)
        .map(|cand| cand.mahalanobis)
}

/// What one landmark predicts in the expected output of `associate`.
struct Predicted {
    nu: Vector2<f64>,
    /// D_j = nu_j^T S_j^-1 nu_j.
    mahalanobis: f64,
}

/// Every landmark's innovation and distance, from the expected output of `associate`.
fn candidates(expected: &Association) -> Option<Vec<Predicted>> {
    expected
        .nu
        .iter()
        .zip(&expected.s)
        .map(|(nu, s)| {
            let nu = Vector2::from(*nu);
            let s = matrix_of(s);
            Some(Predicted {
                nu,
                mahalanobis: nu.dot(&(s.try_inverse()? * nu)),
            })
        })
        .collect()
}

/// A classic mistake in choosing the landmark of a reading, or in deciding whether it is
/// an outlier.
#[derive(Clone, Copy)]
enum Rule {
    /// c = argmin_j D_j, the likelihood without its normalisation det(2 pi S_j)^(-1/2).
    NearestMahalanobis,
    /// c = argmin_j |nu_j|^2, metres and radians added up.
    NearestInnovation,
    /// The outlier flag D_k >= Lambda_M of another landmark k than c, or of any.
    OutlierOf(Other),
}

#[derive(Clone, Copy)]
enum Other {
    First,
    Last,
    /// The landmark of the smallest D_j: an outlier only if no landmark is within the gate.
    Nearest,
    /// Any landmark: an outlier if any D_j reaches the gate.
    Any,
}

const RULES: [Rule; 6] = [
    Rule::NearestMahalanobis,
    Rule::NearestInnovation,
    Rule::OutlierOf(Other::First),
    Rule::OutlierOf(Other::Last),
    Rule::OutlierOf(Other::Nearest),
    Rule::OutlierOf(Other::Any),
];

impl Rule {
    fn hint(self) -> HintKind {
        match self {
            Rule::NearestMahalanobis => HintKind::NearestMahalanobis,
            Rule::NearestInnovation => HintKind::NearestInnovation,
            Rule::OutlierOf(_) => HintKind::OutlierOtherLandmark,
        }
    }

    /// What `associate` returns with the mistake made, from its expected output: the
    /// rule's c, and the outlier flag that goes with it.
    fn associate(self, expected: &Association, lambda_m: f64) -> Option<Association> {
        let cands = candidates(expected)?;
        let c = expected.c;
        let first_smallest = |rank: &dyn Fn(&Predicted) -> f64| {
            (1..cands.len()).fold(0, |best, j| {
                if rank(&cands[j]) < rank(&cands[best]) {
                    j
                } else {
                    best
                }
            })
        };
        let gate = |k: usize| cands.get(k).map(|cand| cand.mahalanobis >= lambda_m);
        let (c, outlier) = match self {
            Rule::NearestMahalanobis | Rule::NearestInnovation => {
                let nearest = first_smallest(&|cand: &Predicted| match self {
                    Rule::NearestInnovation => cand.nu.norm_squared(),
                    _ => cand.mahalanobis,
                });
                (nearest, gate(nearest)?)
            }
            Rule::OutlierOf(other) => (
                c,
                match other {
                    Other::First => gate(0)?,
                    Other::Last => gate(cands.len().checked_sub(1)?)?,
                    Other::Nearest => gate(first_smallest(&|cand| cand.mahalanobis))?,
                    Other::Any => cands.iter().any(|cand| cand.mahalanobis >= lambda_m),
                },
            ),
        };
        Some(Association {
            c,
            outlier,
            ..expected.clone()
        })
    }

    /// What `batch_associate` returns with the mistake made in the association of each
    /// reading (each reading's full association recomputed with the reference).
    fn batch_associate(self, call: &Call) -> Option<BatchAssociation> {
        let Call::BatchAssociate {
            mu_bar,
            sigma_bar,
            z,
            m,
            lambda_m,
            q,
        } = call
        else {
            return None;
        };
        let mut out = BatchAssociation {
            c: Vec::new(),
            outlier: Vec::new(),
            nu_bar: Vec::new(),
            h_bar: Vec::new(),
        };
        for (&range, &bearing) in z[0].iter().zip(&z[1]) {
            let single = Call::Associate {
                mu_bar: *mu_bar,
                sigma_bar: *sigma_bar,
                z_i: [range, bearing],
                m: m.clone(),
                lambda_m: *lambda_m,
                q: *q,
            };
            let Answer::Association(right) = reference(&single).ok()? else {
                return None;
            };
            let wrong = self.associate(&right, *lambda_m)?;
            out.c.push(wrong.c);
            out.outlier.push(wrong.outlier);
            out.nu_bar.extend(wrong.nu.get(wrong.c)?);
            out.h_bar.extend(wrong.h.get(wrong.c)?);
        }
        Some(out)
    }
}

/// The hint of the one association mistake that explains the output, a 1-based index or
/// a rule (`explains` tells whether a rule does); none when several do, as the case
/// cannot tell them apart.
fn association_hint(mismatches: &[Mismatch], explains: impl Fn(Rule) -> bool) -> Option<HintKind> {
    let one_based = index_plus_one(mismatches).then_some(HintKind::OneBasedIndex);
    let mut kinds: Vec<HintKind> = one_based
        .into_iter()
        .chain(
            RULES
                .iter()
                .filter(|rule| explains(**rule))
                .map(|rule| rule.hint()),
        )
        .collect();
    kinds.dedup();
    match kinds[..] {
        [kind] => Some(kind),
        _ => None,
    }
}

/// What predict returns with G^T Sigma G + R in place of G Sigma G^T + R.
fn transposed_prediction(call: &Call) -> Option<Answer> {
    let Call::Predict { sigma, u, r, .. } = call else {
        return None;
    };
    let Answer::Prediction(mut right) = reference(call).ok()? else {
        return None;
    };
    let g = motion_jacobian(&nalgebra::Vector3::from(*u));
    let sigma = matrix_of(sigma);
    let r = matrix_of(r);
    let wrong = g.transpose() * sigma * g + r;
    right.sigma_bar = rows(&wrong);
    Some(Answer::Prediction(right))
}

/// The batch update call with Q_bar = q I, q the range variance of Q_bar's first block.
fn range_variance_only(call: &Call) -> Call {
    let mut other = call.clone();
    if let Call::BatchUpdate { q_bar, .. } = &mut other {
        let q = q_bar
            .first()
            .and_then(|row| row.first())
            .copied()
            .unwrap_or(0.0);
        for (i, row) in q_bar.iter_mut().enumerate() {
            for (j, value) in row.iter_mut().enumerate() {
                *value = if i == j { q } else { 0.0 };
            }
        }
    }
    other
}

/// The odometry call with mu's heading moved on by `k` times the turn of the step,
/// omega dt = (2 pi e_R R_R / E_T - 2 pi e_L R_L / E_T) / B (EL2320 eq. 4): the heading
/// after the step for k = 1, halfway through it for k = 1/2.
fn heading_moved(call: &Call, k: f64) -> Call {
    let mut other = call.clone();
    if let Call::CalculateOdometry {
        e_r,
        e_l,
        e_t,
        b,
        r_r,
        r_l,
        mu,
        ..
    } = &mut other
    {
        let turn = (TAU * *e_r * *r_r / *e_t - TAU * *e_l * *r_l / *e_t) / *b;
        mu[2] += k * turn;
    }
    other
}

/// The odometry output with u[2] the new heading theta + omega dt instead of omega dt.
fn absolute_heading(call: &Call, expected: &Answer) -> Option<Answer> {
    let (Call::CalculateOdometry { mu, .. }, Answer::Odometry(u)) = (call, expected) else {
        return None;
    };
    Some(Answer::Odometry([u[0], u[1], wrap(mu[2] + u[2])]))
}
