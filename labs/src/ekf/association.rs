use super::observation::{jacobian_observation_model, observation_model};
use super::{Belief, Map};
use crate::angle::wrap;
use nalgebra::{Matrix2, Matrix2x3, Vector2};

/// What one landmark predicts about one reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// The innovation `nu = z - z_hat`, bearing wrapped.
    pub nu: Vector2<f64>,
    /// The innovation covariance `S = H Sigma_bar H' + Q`.
    pub s: Matrix2<f64>,
    /// The observation Jacobian `H`.
    pub h: Matrix2x3<f64>,
    /// The squared Mahalanobis distance `D = nu' S^-1 nu` (eq. 8).
    pub mahalanobis: f64,
}

/// The full association of one reading (EL2320 Alg. 2), as the student function returns
/// it: the winner and what every landmark predicts.
#[derive(Clone, Debug, PartialEq)]
pub struct Association {
    /// `c`: the index of the most likely landmark.
    pub c: usize,
    pub outlier: bool,
    /// One per landmark, in map order.
    pub candidates: Vec<Candidate>,
}

/// The association of one reading as the filter needs it: only the winner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Match {
    pub c: usize,
    pub outlier: bool,
    pub candidate: Candidate,
}

/// `Lambda_M = chi2inv(delta_M, 2) = -2 ln(1 - delta_M)`, the outlier threshold on the
/// squared Mahalanobis distance; infinite (no rejection) for `delta_M = 1`.
pub fn lambda_m(delta_m: f64) -> f64 {
    -2.0 * libm::log(1.0 - delta_m)
}

/// Maximum-likelihood data association with outlier detection (EL2320 Alg. 2, eqs. 7-8),
/// for every landmark:
///
/// S_j = H_j Sigma_bar H_j' + Q,  nu_j = z - z_hat_j,  D_j = nu_j' S_j^-1 nu_j,
/// psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2),  c = argmax_j psi_j,
/// outlier = D_c >= Lambda_M.
///
/// The argmax is taken on [`score`], which neither underflows nor changes the winner;
/// ties go to the first landmark.
pub fn associate(
    bar: &Belief,
    z: &Vector2<f64>,
    map: &Map,
    lambda_m: f64,
    q: &Matrix2<f64>,
) -> Association {
    let candidates: Vec<Candidate> = map
        .landmarks()
        .iter()
        .map(|landmark| candidate(bar, z, &landmark.position, q))
        .collect();
    let det_q = q.determinant();
    let mut c = 0;
    for (j, cand) in candidates.iter().enumerate().skip(1) {
        if score(cand, det_q) < score(&candidates[c], det_q) {
            c = j;
        }
    }
    Association {
        c,
        outlier: candidates[c].mahalanobis >= lambda_m,
        candidates,
    }
}

/// The same association as [`associate`], winner only, and faster. The range part alone
/// bounds the Mahalanobis distance from below, D_j >= nu_r^2 / S_j,rr (the Schur
/// complement), and S_j >= Q gives det S_j >= det Q, so
///
/// score_j = D_j + ln(det S_j / det Q) >= nu_r^2 / S_j,rr >= nu_r^2 / s_max,
///
/// with s_max = lambda_max(Sigma_bar,xy) + Q_rr >= S_j,rr, as the range row of H_j is a
/// unit vector in x, y. A landmark can only beat the best score so far if its distance
/// r_j from mu_bar lies within w = sqrt(best s_max) of the measured range, a test on
/// r_j^2 alone; the few that pass face their own bound nu_r^2 / S_j,rr before they are
/// scored in full. The landmark of the closest range is scored first; while no rival
/// needs it, its score is bounded by D + (x - 1) / sqrt(x), x = det S / det Q >= 1 (as
/// ln x <= (x - 1) / sqrt(x) for x >= 1) instead of taking a logarithm, unless x is so
/// large that the bound would be loose. Ties still go to the first landmark, so the
/// winner is exactly the one [`associate`] picks.
pub fn most_likely(
    bar: &Belief,
    z: &Vector2<f64>,
    map: &Map,
    lambda_m: f64,
    q: &Matrix2<f64>,
) -> Match {
    let landmarks = map.landmarks();
    let at = bar.mu.xy();
    let offset = |j: usize| landmarks[j].position - at;
    let range2 = z.x * z.x;
    let first = (0..landmarks.len())
        .map(|j| ((offset(j).norm_squared() - range2).abs(), j))
        .fold((f64::INFINITY, 0), |best, next| {
            if next.0 < best.0 { next } else { best }
        })
        .1;

    let det_q = q.determinant();
    let p = bar.sigma.fixed_view::<2, 2>(0, 0);
    let half_trace = (p[(0, 0)] + p[(1, 1)]) / 2.0;
    let half_gap = (p[(0, 0)] - p[(1, 1)]) / 2.0;
    let s_max = half_trace + (half_gap * half_gap + p[(0, 1)] * p[(0, 1)]).sqrt() + q[(0, 0)];
    // Margins far above rounding keep the pruning from ever skipping the winner.
    let beyond = |lower: f64, upper: f64| lower > upper * (1.0 + 1e-9) + 1e-9;
    // The squared distances a landmark must lie between to beat a score of `upper`.
    let window = |upper: f64| {
        let w = (upper.max(0.0) * s_max).sqrt() * (1.0 + 1e-6) + 1e-9 * (1.0 + z.x);
        ((z.x - w).max(0.0).powi(2), (z.x + w).powi(2))
    };

    let mut c = first;
    let mut best = candidate(bar, z, &landmarks[first].position, q);
    let ratio = best.s.determinant() / det_q;
    // An upper bound of the best score, exact once `exact` is set.
    let (mut upper, mut exact) = if ratio <= 64.0 {
        (best.mahalanobis + (ratio - 1.0) / ratio.sqrt(), false)
    } else {
        (score(&best, det_q), true)
    };
    let (mut low, mut high) = window(upper);
    for j in (0..landmarks.len()).filter(|&j| j != first) {
        let d = offset(j);
        let r2 = d.norm_squared();
        if r2 < low || r2 > high {
            continue;
        }
        let s_rr = (d.transpose() * p * d).x / r2 + q[(0, 0)];
        let nu_r = z.x - r2.sqrt();
        if beyond(nu_r * nu_r / s_rr, upper) {
            continue;
        }
        let cand = candidate(bar, z, &landmarks[j].position, q);
        let rival = score(&cand, det_q);
        if !exact {
            (upper, exact) = (score(&best, det_q), true);
        }
        if rival < upper || (rival == upper && j < c) {
            (c, best, upper) = (j, cand, rival);
            (low, high) = window(upper);
        }
    }
    Match {
        c,
        outlier: best.mahalanobis >= lambda_m,
        candidate: best,
    }
}

/// Batch association (EL2320 Alg. 4, first half): every reading of `z` associated on its
/// own against the same predicted belief.
pub fn batch_associate(
    bar: &Belief,
    z: &[Vector2<f64>],
    map: &Map,
    lambda_m: f64,
    q: &Matrix2<f64>,
) -> Vec<Match> {
    z.iter()
        .map(|z_i| most_likely(bar, z_i, map, lambda_m, q))
        .collect()
}

/// What the landmark at `m` predicts about the reading `z`.
pub(crate) fn candidate(
    bar: &Belief,
    z: &Vector2<f64>,
    m: &Vector2<f64>,
    q: &Matrix2<f64>,
) -> Candidate {
    let z_hat = observation_model(&bar.mu, m);
    let h = jacobian_observation_model(&bar.mu, m, &z_hat);
    let s = h * bar.sigma * h.transpose() + q;
    let nu = Vector2::new(z.x - z_hat.x, wrap(z.y - z_hat.y));
    let mahalanobis = match s.try_inverse() {
        Some(s_inv) => (nu.transpose() * s_inv * nu).x,
        None => f64::INFINITY,
    };
    Candidate {
        nu,
        s,
        h,
        mahalanobis,
    }
}

/// The association's score, lower for more likely: -2 ln psi = D + ln det(2 pi S), less
/// the same constant ln det(2 pi Q) for every landmark, so that it is never below 0.
fn score(candidate: &Candidate, det_q: f64) -> f64 {
    candidate.mahalanobis + libm::log(candidate.s.determinant() / det_q)
}
