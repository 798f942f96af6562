use crate::angle::wrap;
use nalgebra::{Matrix2x3, Vector2, Vector3};

/// The observation model (EL2320 eq. 6): range and bearing of the landmark at `m` seen
/// from the pose `x`, bearing wrapped:
///
/// z_hat = [sqrt(dx^2 + dy^2), atan2(dy, dx) - theta],  dx = m_x - x,  dy = m_y - y
pub fn observation_model(x: &Vector3<f64>, m: &Vector2<f64>) -> Vector2<f64> {
    let dx = m.x - x.x;
    let dy = m.y - x.y;
    Vector2::new((dx * dx + dy * dy).sqrt(), wrap(libm::atan2(dy, dx) - x.z))
}

/// The Jacobian of the observation model with respect to the pose, with r the range of
/// `z_hat`:
///
/// H = [-dx/r, -dy/r, 0; dy/r^2, -dx/r^2, -1]
pub fn jacobian_observation_model(
    x: &Vector3<f64>,
    m: &Vector2<f64>,
    z_hat: &Vector2<f64>,
) -> Matrix2x3<f64> {
    let dx = m.x - x.x;
    let dy = m.y - x.y;
    let r = z_hat.x;
    let r2 = r * r;
    Matrix2x3::new(-dx / r, -dy / r, 0.0, dy / r2, -dx / r2, -1.0)
}
