use super::{Belief, symmetrise};
use crate::angle::wrap;
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Vector2, Vector3};

/// The sequential update with one reading (EL2320 Alg. 3):
///
/// K = Sigma_bar H' S^-1,  mu = mu_bar + K nu (heading wrapped),
/// Sigma = (I - K H) Sigma_bar, symmetrised.
///
/// `None` when `S` is singular.
pub fn update(
    bar: &Belief,
    h: &Matrix2x3<f64>,
    s: &Matrix2<f64>,
    nu: &Vector2<f64>,
) -> Option<Belief> {
    let sigma_ht = bar.sigma * h.transpose();
    let k = sigma_ht * s.try_inverse()?;
    let mut mu = bar.mu + k * nu;
    mu.z = wrap(mu.z);
    // (I - K H) Sigma_bar = Sigma_bar - K (Sigma_bar H')', Sigma_bar being symmetric.
    Some(Belief {
        mu,
        sigma: symmetrise(&(bar.sigma - k * sigma_ht.transpose())),
    })
}

/// The batch update with all inlier readings at once (EL2320 Alg. 4, second half), for
/// the stacked H_bar (2n x 3), nu_bar (2n) and Q_bar = blkdiag(Q, ..., Q):
///
/// K = Sigma_bar H_bar' (H_bar Sigma_bar H_bar' + Q_bar)^-1,  mu = mu_bar + K nu_bar,
/// Sigma = (I - K H_bar) Sigma_bar, symmetrised,
///
/// computed in information form with 3 x 3 matrices only (the lab's question 9): with
/// A = sum_i H_i' Q^-1 H_i and b = sum_i H_i' Q^-1 nu_i, the push-through identity gives
///
/// Sigma = Sigma_bar (I + A Sigma_bar)^-1,  mu = mu_bar + Sigma b,
///
/// which holds for a singular Sigma_bar too (M = I + A Sigma_bar has the eigenvalues of
/// I + Sigma_bar^1/2 A Sigma_bar^1/2, all >= 1). `readings` gives each reading's
/// `(H_i, nu_i)`. `None` when `Q` is singular.
pub fn batch_update<'a>(
    bar: &Belief,
    readings: impl IntoIterator<Item = (&'a Matrix2x3<f64>, &'a Vector2<f64>)>,
    q: &Matrix2<f64>,
) -> Option<Belief> {
    let q_inv = q.try_inverse()?;
    let mut a = Matrix3::zeros();
    let mut b = Vector3::zeros();
    for (h, nu) in readings {
        let ht_q_inv = h.transpose() * q_inv;
        a += ht_q_inv * h;
        b += ht_q_inv * nu;
    }
    // Sigma = Sigma_bar M^-1 with M = I + A Sigma_bar, i.e. Sigma' = M'^-1 Sigma_bar: an LU
    // solve with pivoting (the closed-form 3 x 3 inverse loses digits when A is large).
    let m = Matrix3::identity() + a * bar.sigma;
    let sigma = m.transpose().lu().solve(&bar.sigma)?.transpose();
    let mut mu = bar.mu + sigma * b;
    mu.z = wrap(mu.z);
    Some(Belief {
        mu,
        sigma: symmetrise(&sigma),
    })
}
