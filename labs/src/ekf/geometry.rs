//! Geometry for drawing a run: where a reading points, and the ellipse a covariance spans.

use nalgebra::{Matrix2, Vector2, Vector3};
use std::f64::consts::TAU;

/// The point a range-bearing reading `z` points at, seen from `pose`:
/// [x + r cos(theta + b), y + r sin(theta + b)].
pub fn reading_position(pose: &Vector3<f64>, z: &Vector2<f64>) -> Vector2<f64> {
    let direction = pose.z + z.y;
    Vector2::new(
        pose.x + z.x * libm::cos(direction),
        pose.y + z.x * libm::sin(direction),
    )
}

/// `segments + 1` points round the ellipse {centre + d : d' Sigma^-1 d = k^2} of a 2 x 2
/// covariance, the last equal to the first: centre + k V Lambda^1/2 [cos t, sin t] with
/// Sigma = V Lambda V', so k = 3 draws the 3-sigma ellipse.
pub fn covariance_ellipse(
    centre: &Vector2<f64>,
    sigma: &Matrix2<f64>,
    k: f64,
    segments: usize,
) -> Vec<Vector2<f64>> {
    let (a, b, d) = (sigma[(0, 0)], sigma[(0, 1)], sigma[(1, 1)]);
    // Eigenvalues of the symmetric [a b; b d] and the angle of the first eigenvector.
    let mean = (a + d) / 2.0;
    let radius = (((a - d) / 2.0).powi(2) + b * b).sqrt();
    let (major, minor) = (
        (mean + radius).max(0.0).sqrt(),
        (mean - radius).max(0.0).sqrt(),
    );
    let angle = 0.5 * libm::atan2(2.0 * b, a - d);
    let (sin, cos) = (libm::sin(angle), libm::cos(angle));
    (0..=segments)
        .map(|i| {
            let t = TAU * (i % segments.max(1)) as f64 / segments.max(1) as f64;
            let (u, v) = (k * major * libm::cos(t), k * minor * libm::sin(t));
            centre + Vector2::new(cos * u - sin * v, sin * u + cos * v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reading_points_at_its_landmark() {
        let pose = Vector3::new(1.0, 2.0, 0.5);
        let landmark = Vector2::new(4.0, -1.0);
        let z = super::super::observation_model(&pose, &landmark);
        assert!((reading_position(&pose, &z) - landmark).norm() < 1e-12);
    }

    #[test]
    fn ellipse_points_lie_at_mahalanobis_distance_k() {
        let sigma = Matrix2::new(0.04, 0.015, 0.015, 0.01);
        let centre = Vector2::new(3.0, -2.0);
        let points = covariance_ellipse(&centre, &sigma, 3.0, 48);
        assert_eq!(points.len(), 49);
        assert_eq!(points[0], points[48]);
        let inverse = sigma.try_inverse().unwrap();
        for p in &points {
            let d = p - centre;
            assert!(((d.transpose() * inverse * d).x - 9.0).abs() < 1e-9);
        }
    }

    #[test]
    fn a_degenerate_covariance_gives_a_segment() {
        let points =
            covariance_ellipse(&Vector2::zeros(), &Matrix2::new(1.0, 0.0, 0.0, 0.0), 2.0, 8);
        assert!(
            points
                .iter()
                .all(|p| p.y.abs() < 1e-12 && p.x.abs() <= 2.0 + 1e-12)
        );
    }
}
