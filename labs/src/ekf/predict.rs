use super::{Belief, symmetrise};
use crate::angle::wrap;
use nalgebra::{Matrix3, Vector3};

/// The prediction step (EL2320 Alg. 1, eq. 5):
///
/// mu_bar = mu + u (heading wrapped),  Sigma_bar = G Sigma G' + R (symmetrised)
/// with G = [1 0 -u_y; 0 1 u_x; 0 0 1], the Jacobian of the motion model.
pub fn predict(belief: &Belief, u: &Vector3<f64>, r: &Matrix3<f64>) -> Belief {
    let mut mu_bar = belief.mu + u;
    mu_bar.z = wrap(mu_bar.z);
    let g = motion_jacobian(u);
    Belief {
        mu: mu_bar,
        sigma: symmetrise(&(g * belief.sigma * g.transpose() + r)),
    }
}

/// G = d(mu + u)/d mu for the odometry motion model, where u depends on the heading:
/// d/d theta [v dt cos(theta), v dt sin(theta), omega dt] = [-u_y, u_x, 0].
pub fn motion_jacobian(u: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, -u.y, 0.0, 1.0, u.x, 0.0, 0.0, 1.0)
}
