use super::observation::{jacobian_observation_model, observation_model};
use super::{Belief, Map};
use crate::angle::wrap;
use nalgebra::{Matrix2, Matrix2x3, Vector2};
use std::f64::consts::TAU;

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
/// The argmax is taken on -2 ln psi_j, which neither underflows nor changes the winner;
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
    let mut c = 0;
    for (j, cand) in candidates.iter().enumerate().skip(1) {
        if neg_log_likelihood(cand) < neg_log_likelihood(&candidates[c]) {
            c = j;
        }
    }
    Association {
        c,
        outlier: candidates[c].mahalanobis >= lambda_m,
        candidates,
    }
}

/// The same association as [`associate`], winner only, and faster: the range part alone
/// bounds the Mahalanobis distance from below (D_j >= nu_r^2 / S_j,rr, the Schur
/// complement), and S_j >= Q gives det S_j >= det Q, so
///
/// -2 ln psi_j >= nu_r^2 / S_j,rr + ln det(2 pi Q),
///
/// and a landmark whose bound is already worse than the best so far cannot win. The
/// bound needs no arctangent and no 2 x 2 inverse. Landmarks are visited best bound
/// first, and ties still go to the first landmark, so the winner is exactly the one
/// [`associate`] picks.
pub fn most_likely(
    bar: &Belief,
    z: &Vector2<f64>,
    map: &Map,
    lambda_m: f64,
    q: &Matrix2<f64>,
) -> Match {
    let landmarks = map.landmarks();
    let floor = libm::log((q * TAU).determinant());
    let bound = |j: usize| range_bound(bar, z, &landmarks[j].position, q) + floor;

    let first = (0..landmarks.len())
        .map(|j| (bound(j), j))
        .fold((f64::INFINITY, 0), |best, next| {
            if next.0 < best.0 { next } else { best }
        })
        .1;
    let mut c = first;
    let mut best = candidate(bar, z, &landmarks[first].position, q);
    let mut best_score = neg_log_likelihood(&best);
    for j in (0..landmarks.len()).filter(|&j| j != first) {
        // A margin far above rounding keeps the pruning from ever skipping the winner.
        if bound(j) > best_score + 1e-9 * (1.0 + best_score.abs()) {
            continue;
        }
        let cand = candidate(bar, z, &landmarks[j].position, q);
        let score = neg_log_likelihood(&cand);
        if score < best_score || (score == best_score && j < c) {
            (c, best, best_score) = (j, cand, score);
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

/// -2 ln psi = D + ln det(2 pi S), the association's score (lower is more likely).
fn neg_log_likelihood(candidate: &Candidate) -> f64 {
    candidate.mahalanobis + libm::log((candidate.s * TAU).determinant())
}

/// nu_r^2 / S_rr, the lower bound of D from the range alone, with H_r = [-dx/r, -dy/r, 0].
fn range_bound(bar: &Belief, z: &Vector2<f64>, m: &Vector2<f64>, q: &Matrix2<f64>) -> f64 {
    let dx = m.x - bar.mu.x;
    let dy = m.y - bar.mu.y;
    let r2 = dx * dx + dy * dy;
    let p = &bar.sigma;
    let s_rr =
        (dx * dx * p[(0, 0)] + 2.0 * dx * dy * p[(0, 1)] + dy * dy * p[(1, 1)]) / r2 + q[(0, 0)];
    let nu_r = z.x - r2.sqrt();
    nu_r * nu_r / s_rr
}
