// EKF localization of a differential-drive robot: your implementation.
//
// Write every function below in plain JavaScript. The test harness calls each one on
// cases made for you and compares what it returns with the reference filter; the filter
// loop that strings them together (odometry, prediction, association, update) is given
// and runs them on the three data sets with the settings your `init` returns.
//
// Conventions (the same as the lab's, with 0-based indices):
// - vectors are arrays of numbers: mu = [x, y, theta];
// - matrices are arrays of rows: sigma[i][j], H is [[..3..], [..3..]] for 2 x 3;
// - the map M is 2 x N: M[0][j] is the x and M[1][j] the y of landmark j = 0 .. N-1;
// - R is the PROCESS noise (3 x 3) and Q the MEASUREMENT noise (2 x 2), as in the lab
//   and in Probabilistic Robotics (the lectures use the opposite letters);
// - every angle, intermediate ones included, is in radians and wrapped to [-pi, pi);
// - every function is pure: it returns new arrays and keeps nothing between calls.
//
// Your file runs on its own: no import, require, network or files. Helpers of your own
// (a matrix product, a transpose, a 2 x 2 inverse, an angle wrap) are welcome anywhere in
// the file; Math is all yours.

// Odometry from the wheel encoders (lab eq. 4).
//   e_R, e_L   encoder ticks of the right and left wheel since the last time step
//   E_T        ticks per wheel revolution
//   B          wheel base (m)
//   R_R, R_L   radius of the right and left wheel (m)
//   delta_t    time since the last time step (s); may be 0
//   mu         the current estimate [x, y, theta]
// Returns u, a 3-vector [dx, dy, dtheta]: the motion during delta_t, expressed from the
// current heading. When delta_t is 0 the robot has not moved: u = [0, 0, 0].
function calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu) {
  throw new Error('calculate_odometry: not implemented');
}

// Prediction (lab eq. 5, Algorithm 1).
//   mu     3-vector, the belief's mean      sigma  3 x 3, its covariance
//   u      3-vector from calculate_odometry R      3 x 3 process noise
// Returns { mu_bar, sigma_bar }: mu_bar = mu + u with theta wrapped, and
// sigma_bar = G sigma G^T + R, where G is the Jacobian of the motion with respect to
// the state. Symmetrise sigma_bar: (A + A^T) / 2.
function predict(mu, sigma, u, R) {
  throw new Error('predict: not implemented');
}

// Observation model (lab eq. 6): the reading landmark j would give from pose x.
//   x  3-vector pose [x, y, theta]    M  2 x N map    j  landmark index, 0-based
// Returns z_hat = [range, bearing], the bearing wrapped to [-pi, pi).
function observation_model(x, M, j) {
  throw new Error('observation_model: not implemented');
}

// Jacobian of the observation model (lab eq. 6) with respect to the pose.
//   x  3-vector pose    M  2 x N map    j  landmark index, 0-based
//   z_hat  observation_model(x, M, j), which you may reuse for the range
// Returns H, 2 x 3: row 0 the derivatives of the range by x, y, theta; row 1 those of
// the bearing.
function jacobian_observation_model(x, M, j, z_hat) {
  throw new Error('jacobian_observation_model: not implemented');
}

// Maximum-likelihood association of one reading, with the outlier test (Algorithm 2,
// lab eqs. 7 and 8).
//   mu_bar, sigma_bar  the predicted belief (3-vector, 3 x 3)
//   z_i                one reading [range, bearing]
//   M                  2 x N map
//   Lambda_M           the outlier threshold chi2inv(delta_M, 2); Infinity keeps all
//   Q                  2 x 2 measurement noise
// For every landmark j: nu[j] = z_i - z_hat_j (bearing wrapped), H[j] its Jacobian,
// S[j] = H[j] sigma_bar H[j]^T + Q, and the likelihood
// psi_j = det(2 pi S[j])^(-1/2) exp(-D_j / 2) with D_j = nu[j]^T S[j]^-1 nu[j].
// Returns { c, outlier, nu, S, H }:
//   c        the index (0-based) of the landmark with the largest likelihood
//   outlier  true when that landmark's D is at least Lambda_M (D >= Lambda_M)
//   nu       N x 2, S  N x 2 x 2, H  N x 2 x 3: every landmark's, in map order
function associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q) {
  throw new Error('associate: not implemented');
}

// Batch association (Algorithm 4, first half): every reading of a time step associated
// against the same prediction.
//   z  2 x n: z[0][i] the range and z[1][i] the bearing of reading i
//   the rest as for associate
// Returns { c, outlier, nu_bar, H_bar }:
//   c, outlier  n-arrays, reading by reading, as associate decides them
//   nu_bar      2n-vector [range_1, bearing_1, range_2, bearing_2, ...]: each reading's
//               innovation with its associated landmark
//   H_bar       2n x 3: the Jacobians of those landmarks, stacked in the same order
// Include every reading, outliers too: the filter loop drops them before batch_update.
function batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q) {
  throw new Error('batch_associate: not implemented');
}

// Sequential update with one reading (Algorithm 3).
//   mu_bar, sigma_bar  the belief before this reading (3-vector, 3 x 3)
//   H (2 x 3), S (2 x 2), nu (2-vector)  the associated landmark's, from associate
// Returns { mu, sigma }: K = sigma_bar H^T S^-1, mu = mu_bar + K nu (theta wrapped),
// sigma = (I - K H) sigma_bar, symmetrised.
function update(mu_bar, sigma_bar, H, S, nu) {
  throw new Error('update: not implemented');
}

// Batch update with the stacked inlying readings of a time step (Algorithm 4, second half).
//   mu_bar, sigma_bar  the predicted belief
//   H_bar  2m x 3, the inliers' Jacobians stacked
//   Q_bar  2m x 2m, block diagonal with Q on its diagonal: one block per reading
//   nu_bar 2m-vector, the inliers' innovations stacked
// Returns { mu, sigma }: the Kalman update with the stacked quantities (theta wrapped,
// sigma symmetrised).
function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) {
  throw new Error('batch_update: not implemented');
}

// Your settings for each data set: the filter loop calls init with the data set's name,
// 'o3', 'outliers' or 'no-odometry', before its first time step.
// Returns { mu, sigma, R, Q, Lambda_M }:
//   mu, sigma  the initial belief (3-vector, 3 x 3); every run starts at the origin,
//              heading 0, and that is known well
//   R          3 x 3 process noise, Q 2 x 2 measurement noise: your tuning
//   Lambda_M   the outlier threshold, chi2inv(delta_M, 2) = -2 ln(1 - delta_M) for two
//              degrees of freedom; Infinity (delta_M = 1) rejects nothing
function init(dataset) {
  throw new Error('init: not implemented');
}
