//! The wheels' noise, one step of covariance propagation, and the 3 x 3 covariance
//! helpers the rest of the module shares (checks, a square root for sampling, and the
//! array-of-rows form that crosses into JSON).

use super::motion::{Increment, increment_jacobian, pose_jacobian};
use crate::Error;
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector3};

/// The covariance of one step's wheel distances. Each wheel's error is independent of the
/// other's and its variance grows in proportion to the distance it rolled:
///
/// Sigma_delta = diag(k_r |ds_r|, k_l |ds_l|)
///
/// `k_r` and `k_l` are variances per metre rolled (so metres): after a metre a wheel's
/// distance is off by about sqrt(k) metres. Because the variance is proportional to the
/// distance, splitting a path into more, shorter steps adds up to the same wheel variance.
pub fn wheel_noise(increment: Increment, k_r: f64, k_l: f64) -> Matrix2<f64> {
    Matrix2::new(
        k_r * increment.right.abs(),
        0.0,
        0.0,
        k_l * increment.left.abs(),
    )
}

/// One step of first-order error propagation:
///
/// Sigma_p' = F_p Sigma_p F_p' + F_delta Sigma_delta F_delta'
///
/// with both Jacobians taken at the pose before the step (`pose`) and the nominal wheel
/// increments. The result is symmetrised, `(A + A') / 2`, so rounding leaves no asymmetry.
pub fn propagate_covariance(
    sigma: &Matrix3<f64>,
    pose: &Vector3<f64>,
    increment: Increment,
    wheel_base: f64,
    k_r: f64,
    k_l: f64,
) -> Matrix3<f64> {
    propagate_through(
        sigma,
        &pose_jacobian(pose, increment, wheel_base),
        &increment_jacobian(pose, increment, wheel_base),
        &wheel_noise(increment, k_r, k_l),
    )
}

/// The same step from the Jacobians and the wheel noise themselves:
///
/// Sigma_p' = F_p Sigma_p F_p' + F_delta Sigma_delta F_delta', symmetrised.
pub fn propagate_through(
    sigma: &Matrix3<f64>,
    f_p: &Matrix3<f64>,
    f_delta: &Matrix3x2<f64>,
    sigma_delta: &Matrix2<f64>,
) -> Matrix3<f64> {
    symmetrise(&(f_p * sigma * f_p.transpose() + f_delta * sigma_delta * f_delta.transpose()))
}

/// `(A + A') / 2`.
pub(crate) fn symmetrise(a: &Matrix3<f64>) -> Matrix3<f64> {
    (a + a.transpose()) * 0.5
}

/// A matrix as an array of its rows, the form the results are serialised in.
pub fn to_rows(a: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)]))
}

/// The matrix of an array of rows.
pub fn from_rows(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// Checks that `rows` is a covariance: finite, exactly symmetric, positive semi-definite
/// (every principal minor, the three diagonal entries, the three 2 x 2 ones and the
/// determinant, at least zero up to rounding). Errors name `field`.
pub(crate) fn check_covariance(field: &str, rows: &[[f64; 3]; 3]) -> Result<(), Error> {
    if !rows.iter().flatten().all(|v| v.is_finite()) {
        return Err(Error::invalid(field, "must be finite"));
    }
    for (i, j) in [(1, 0), (2, 0), (2, 1)] {
        if rows[i][j] != rows[j][i] {
            return Err(Error::invalid(
                field,
                format!("must be symmetric, but [{i}][{j}] != [{j}][{i}]"),
            ));
        }
    }
    let a = from_rows(rows);
    let scale = a.abs().max();
    let not_psd = || Err(Error::invalid(field, "must be positive semi-definite"));
    if (0..3).any(|i| a[(i, i)] < 0.0) {
        return not_psd();
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let minor = a[(i, i)] * a[(j, j)] - a[(i, j)] * a[(i, j)];
        if minor < -1e-12 * scale * scale {
            return not_psd();
        }
    }
    if a.determinant() < -1e-12 * scale * scale * scale {
        return not_psd();
    }
    Ok(())
}

/// A lower-triangular `L` with `L L' = A` for a positive semi-definite `A`: Cholesky's
/// factorisation, with a column of zeros where a pivot is zero (or rounding made it
/// slightly negative), so a singular covariance (no initial uncertainty at all, or none
/// in one direction) factors too. A standard normal 3-vector `z` then gives `L z`, a draw
/// from N(0, A).
///
/// L_jj = sqrt(A_jj - sum_{m<j} L_jm^2),  L_ij = (A_ij - sum_{m<j} L_im L_jm) / L_jj.
pub(crate) fn square_root(a: &Matrix3<f64>) -> Matrix3<f64> {
    let mut l = Matrix3::zeros();
    let tiny = 1e-14 * a.abs().max();
    for j in 0..3 {
        let pivot = a[(j, j)] - (0..j).map(|m| l[(j, m)] * l[(j, m)]).sum::<f64>();
        if pivot <= tiny {
            continue;
        }
        let root = libm::sqrt(pivot);
        l[(j, j)] = root;
        for i in j + 1..3 {
            l[(i, j)] = (a[(i, j)] - (0..j).map(|m| l[(i, m)] * l[(j, m)]).sum::<f64>()) / root;
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_root_reproduces_regular_and_singular_covariances() {
        let v = Vector3::new(0.3, -1.0, 2.0);
        for a in [
            Matrix3::new(4.0, 1.0, 0.5, 1.0, 3.0, -0.2, 0.5, -0.2, 2.0),
            v * v.transpose(),
            Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 0.25)),
            Matrix3::zeros(),
        ] {
            let l = square_root(&a);
            assert!((l * l.transpose() - a).abs().max() < 1e-12, "{a}");
            assert_eq!(
                l.upper_triangle() - Matrix3::from_diagonal(&l.diagonal()),
                Matrix3::zeros()
            );
        }
    }

    #[test]
    fn covariances_are_checked_field_named() {
        let ok = [[1.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(check_covariance("sigma0", &ok), Ok(()));
        let v = [1.0, -2.0, 0.7];
        let rank_one = std::array::from_fn(|i| std::array::from_fn(|j| v[i] * v[j]));
        assert_eq!(check_covariance("sigma0", &rank_one), Ok(()));
        let message = |rows| check_covariance("sigma0", &rows).unwrap_err().to_string();
        assert_eq!(
            message([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            "sigma0: must be positive semi-definite"
        );
        assert_eq!(
            message([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            "sigma0: must be symmetric, but [1][0] != [0][1]"
        );
        assert_eq!(
            message([[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            "sigma0: must be finite"
        );
        assert_eq!(
            message([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1e-3]]),
            "sigma0: must be positive semi-definite"
        );
        // Every leading principal minor is zero (so Sylvester's test for definite
        // matrices would pass it), but the lower 2 x 2 one is negative.
        assert_eq!(
            message([[0.0, 0.0, 0.0], [0.0, 1.0, 2.0], [0.0, 2.0, 1.0]]),
            "sigma0: must be positive semi-definite"
        );
    }
}
