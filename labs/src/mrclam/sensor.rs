//! The camera's model: a post's range and bearing from a pose, its Jacobian, and the gate
//! that turns away readings too far from what the filter expects.

use super::grid::Reading;
use crate::angle;
use nalgebra::{Matrix2, Matrix2x3, Vector2, Vector3};

/// The chi-square quantile of two degrees of freedom at 99.9 %, -2 ln(0.001): a reading
/// whose squared Mahalanobis distance exceeds it is rejected.
pub const GATE: f64 = 13.815_510_557_964_274;

/// h(x): the range and bearing of `landmark` seen from `pose`, the bearing wrapped.
pub fn expected(pose: &Vector3<f64>, landmark: &Vector2<f64>) -> Vector2<f64> {
    let (dx, dy) = (landmark.x - pose.x, landmark.y - pose.y);
    Vector2::new(
        libm::hypot(dx, dy),
        angle::wrap(libm::atan2(dy, dx) - pose.z),
    )
}

/// H, the Jacobian of `expected` with respect to the pose:
/// [[-dx/r, -dy/r, 0], [dy/r^2, -dx/r^2, -1]].
pub fn jacobian(pose: &Vector3<f64>, landmark: &Vector2<f64>) -> Matrix2x3<f64> {
    let (dx, dy) = (landmark.x - pose.x, landmark.y - pose.y);
    let q = dx * dx + dy * dy;
    let r = q.sqrt();
    Matrix2x3::new(-dx / r, -dy / r, 0.0, dy / q, -dx / q, -1.0)
}

/// The reading as a vector (range, bearing).
pub fn observed(reading: &Reading) -> Vector2<f64> {
    Vector2::new(reading.range, reading.bearing)
}

/// The innovation z - z_hat, its bearing wrapped.
pub fn innovation(z: &Vector2<f64>, expected: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(z.x - expected.x, angle::difference(z.y, expected.y))
}

/// nu^T S^-1 nu, the squared Mahalanobis distance of the innovation `nu` whose covariance
/// has the inverse `s_inverse`.
pub fn mahalanobis(nu: &Vector2<f64>, s_inverse: &Matrix2<f64>) -> f64 {
    (nu.transpose() * s_inverse * nu).x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jacobian_is_the_derivative_of_the_reading() {
        let pose = Vector3::new(0.3, -1.2, 2.9);
        let landmark = Vector2::new(-1.0, 0.5);
        let h = 1e-6;
        let analytic = jacobian(&pose, &landmark);
        for j in 0..3 {
            let mut plus = pose;
            let mut minus = pose;
            plus[j] += h;
            minus[j] -= h;
            let d =
                innovation(&expected(&plus, &landmark), &expected(&minus, &landmark)) / (2.0 * h);
            assert!((analytic.column(j) - d).amax() < 1e-8, "column {j}");
        }
    }

    #[test]
    fn the_gate_is_the_quantile() {
        // P(chi2_2 <= g) = 1 - exp(-g / 2).
        assert!((1.0 - (-GATE / 2.0).exp() - 0.999).abs() < 1e-15);
    }
}
