// EKF localization (EL2320 lab): a correct solution of the student contract.
//
// Conventions: vectors are arrays, matrices arrays of rows, the map M is 2 x N
// (M[0][j] = x, M[1][j] = y), indices are 0-based, every angle this file computes is
// wrapped to [-pi, pi).

// ---- small helpers ----

const TWO_PI = 2 * Math.PI;

// Wraps an angle to [-pi, pi).
function wrap(angle) {
  if (angle >= -Math.PI && angle < Math.PI) return angle;
  const wrapped = angle - TWO_PI * Math.floor((angle + Math.PI) / TWO_PI);
  // Rounding can land exactly on +pi, which belongs to the other end.
  return wrapped >= Math.PI ? wrapped - TWO_PI : wrapped;
}

function zeros(rows, cols) {
  const A = [];
  for (let i = 0; i < rows; i++) A.push(new Array(cols).fill(0));
  return A;
}

function identity(n) {
  const I = zeros(n, n);
  for (let i = 0; i < n; i++) I[i][i] = 1;
  return I;
}

function transpose(A) {
  const T = zeros(A[0].length, A.length);
  for (let i = 0; i < A.length; i++) {
    for (let j = 0; j < A[0].length; j++) T[j][i] = A[i][j];
  }
  return T;
}

function matMul(A, B) {
  const C = zeros(A.length, B[0].length);
  for (let i = 0; i < A.length; i++) {
    for (let j = 0; j < B[0].length; j++) {
      let sum = 0;
      for (let k = 0; k < B.length; k++) sum += A[i][k] * B[k][j];
      C[i][j] = sum;
    }
  }
  return C;
}

function matVec(A, v) {
  return A.map((row) => row.reduce((sum, a, k) => sum + a * v[k], 0));
}

function matAdd(A, B) {
  return A.map((row, i) => row.map((a, j) => a + B[i][j]));
}

function matSub(A, B) {
  return A.map((row, i) => row.map((a, j) => a - B[i][j]));
}

function matScale(A, s) {
  return A.map((row) => row.map((a) => a * s));
}

// (A + A^T) / 2: removes the asymmetry rounding leaves in a covariance.
function symmetrise(A) {
  return matScale(matAdd(A, transpose(A)), 0.5);
}

// Inverse of a square matrix by Gauss-Jordan elimination with partial pivoting.
function inverse(A) {
  const n = A.length;
  const work = A.map((row, i) => row.concat(identity(n)[i]));
  for (let col = 0; col < n; col++) {
    let pivot = col;
    for (let r = col + 1; r < n; r++) {
      if (Math.abs(work[r][col]) > Math.abs(work[pivot][col])) pivot = r;
    }
    if (work[pivot][col] === 0) throw new Error('inverse: the matrix is singular');
    [work[col], work[pivot]] = [work[pivot], work[col]];
    const p = work[col][col];
    for (let k = 0; k < 2 * n; k++) work[col][k] /= p;
    for (let r = 0; r < n; r++) {
      if (r === col) continue;
      const f = work[r][col];
      if (f === 0) continue;
      for (let k = 0; k < 2 * n; k++) work[r][k] -= f * work[col][k];
    }
  }
  return work.map((row) => row.slice(n));
}

function det2(S) {
  return S[0][0] * S[1][1] - S[0][1] * S[1][0];
}

// ---- the contract ----

// Odometry (EL2320 eq. 4):
//   omega_R = 2 pi e_R / (E_T dt),  omega_L = 2 pi e_L / (E_T dt)
//   v = (omega_R R_R + omega_L R_L) / 2,  omega = (omega_R R_R - omega_L R_L) / B
//   u = [v dt cos(theta), v dt sin(theta), omega dt]
// u is zero at the first step, when delta_t is 0.
function calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu) {
  if (delta_t === 0) return [0, 0, 0];
  const omega_R = (TWO_PI * e_R) / (E_T * delta_t); // the wheels' angular speeds
  const omega_L = (TWO_PI * e_L) / (E_T * delta_t);
  const v_R = omega_R * R_R; // and their speeds over the ground
  const v_L = omega_L * R_L;
  const v = (v_R + v_L) / 2;
  const omega = (v_R - v_L) / B;
  const theta = mu[2];
  return [v * delta_t * Math.cos(theta), v * delta_t * Math.sin(theta), wrap(omega * delta_t)];
}

// Prediction (EL2320 Alg. 1, eq. 5):
//   mu_bar = mu + u (heading wrapped),  Sigma_bar = G Sigma G^T + R (symmetrised),
//   G = [1 0 -u_y; 0 1 u_x; 0 0 1], the Jacobian of the motion model.
function predict(mu, sigma, u, R) {
  const mu_bar = [mu[0] + u[0], mu[1] + u[1], wrap(mu[2] + u[2])];
  const G = [
    [1, 0, -u[1]],
    [0, 1, u[0]],
    [0, 0, 1],
  ];
  const GSGt = matMul(matMul(G, sigma), transpose(G));
  const sigma_bar = symmetrise(matAdd(GSGt, R));
  return { mu_bar, sigma_bar };
}

// Observation model (EL2320 eq. 6): range and bearing of landmark j seen from pose x,
//   z_hat = [sqrt(dx^2 + dy^2), atan2(dy, dx) - theta],  dx = m_x - x,  dy = m_y - y,
// bearing wrapped.
function observation_model(x, M, j) {
  const dx = M[0][j] - x[0];
  const dy = M[1][j] - x[1];
  const range = Math.sqrt(dx * dx + dy * dy);
  const bearing = wrap(Math.atan2(dy, dx) - x[2]);
  return [range, bearing];
}

// Jacobian of the observation model with respect to the pose (x, y, theta), r = z_hat[0]:
//   H = [-dx/r, -dy/r, 0; dy/r^2, -dx/r^2, -1]
function jacobian_observation_model(x, M, j, z_hat) {
  const mx = M[0][j];
  const my = M[1][j];
  const dx = mx - x[0];
  const dy = my - x[1];
  const r = z_hat[0];
  const r2 = r * r;
  const rangeRow = [-dx / r, -dy / r, 0];
  const bearingRow = [dy / r2, -dx / r2, -1];
  return [rangeRow, bearingRow];
}

// Maximum-likelihood association with outlier detection (EL2320 Alg. 2, eqs. 7-8).
// For every landmark j:
//   S_j = H_j Sigma_bar H_j^T + Q,  nu_j = z_i - z_hat_j (bearing wrapped),
//   D_j = nu_j^T S_j^-1 nu_j,  psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2).
// c = argmax_j psi_j (ties go to the first landmark), outlier = D_c >= Lambda_M.
// The argmax is taken on ln(psi_j), which cannot underflow.
function associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q) {
  const nu = [];
  const S = [];
  const H = [];
  const D = [];
  const logPsi = [];
  for (let j = 0; j < M[0].length; j++) {
    const z_hat = observation_model(mu_bar, M, j);
    const H_j = jacobian_observation_model(mu_bar, M, j, z_hat);
    const S_j = matAdd(matMul(matMul(H_j, sigma_bar), transpose(H_j)), Q);
    const nu_j = [z_i[0] - z_hat[0], wrap(z_i[1] - z_hat[1])];
    const det = det2(S_j);
    // nu^T S^-1 nu with the closed-form 2 x 2 inverse.
    const D_j = det === 0
      ? Infinity
      : (nu_j[0] * (S_j[1][1] * nu_j[0] - S_j[0][1] * nu_j[1]) +
         nu_j[1] * (S_j[0][0] * nu_j[1] - S_j[1][0] * nu_j[0])) / det;
    nu.push(nu_j);
    S.push(S_j);
    H.push(H_j);
    D.push(D_j);
    logPsi.push(-0.5 * Math.log(TWO_PI * TWO_PI * det) - 0.5 * D_j);
  }
  let c = 0;
  for (let j = 1; j < logPsi.length; j++) {
    if (logPsi[j] > logPsi[c]) c = j;
  }
  const outlier = D[c] >= Lambda_M;
  return { c, outlier, nu, S, H };
}

// Batch association (EL2320 Alg. 4, first half): every reading (a column of z)
// associated on its own against the same predicted belief. nu_bar stacks the winners'
// innovations [r_1, b_1, r_2, b_2, ...] and H_bar their Jacobians (2n x 3); outliers
// are included, the filter loop leaves them out.
function batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q) {
  const c = [];
  const outlier = [];
  const nu_bar = [];
  const H_bar = [];
  for (let i = 0; i < z[0].length; i++) {
    const a = associate(mu_bar, sigma_bar, [z[0][i], z[1][i]], M, Lambda_M, Q);
    c.push(a.c);
    outlier.push(a.outlier);
    nu_bar.push(a.nu[a.c][0], a.nu[a.c][1]);
    H_bar.push(a.H[a.c][0], a.H[a.c][1]);
  }
  return { c, outlier, nu_bar, H_bar };
}

// Sequential update with one reading (EL2320 Alg. 3):
//   K = Sigma_bar H^T S^-1,  mu = mu_bar + K nu (heading wrapped),
//   Sigma = (I - K H) Sigma_bar, symmetrised.
function update(mu_bar, sigma_bar, H, S, nu) {
  const K = matMul(matMul(sigma_bar, transpose(H)), inverse(S));
  const Knu = matVec(K, nu);
  const mu = [mu_bar[0] + Knu[0], mu_bar[1] + Knu[1], wrap(mu_bar[2] + Knu[2])];
  const KH = matMul(K, H);
  const A = matMul(matSub(identity(3), KH), sigma_bar);
  const sigma = symmetrise(A);
  return { mu, sigma };
}

// Batch update with all inliers at once (EL2320 Alg. 4, second half), in the stacked
// form with H_bar (2n x 3), Q_bar = blkdiag(Q, ..., Q) (2n x 2n) and nu_bar (2n):
//   S = H_bar Sigma_bar H_bar^T + Q_bar,  K = Sigma_bar H_bar^T S^-1,
//   mu = mu_bar + K nu_bar (heading wrapped),  Sigma = (I - K H_bar) Sigma_bar, symmetrised.
function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) {
  const SHt = matMul(sigma_bar, transpose(H_bar));
  const HSHt = matMul(H_bar, SHt);
  const S = matAdd(HSHt, Q_bar);
  const K = matMul(SHt, inverse(S));
  const Knu = matVec(K, nu_bar);
  const mu = [mu_bar[0] + Knu[0], mu_bar[1] + Knu[1], wrap(mu_bar[2] + Knu[2])];
  const sigma = symmetrise(matMul(matSub(identity(3), matMul(K, H_bar)), sigma_bar));
  return { mu, sigma };
}

// The lab's tuning for each data set:
//   o3:          R = diag(0.01^2, 0.01^2, (1 deg)^2), Q = diag(0.01^2, (1 deg)^2), delta_M = 0.999
//   outliers:    R as for o3, Q = 0.2^2 I
//   no-odometry: R = I, Q = 0.1^2 I, delta_M = 1 (no outlier rejection)
// mu = 0, Sigma = 1e-10 I, and Lambda_M = chi2inv(delta_M, 2) = -2 ln(1 - delta_M),
// which is Infinity for delta_M = 1.
function init(dataset) {
  const deg = Math.PI / 180;
  let R = [
    [0.01 ** 2, 0, 0],
    [0, 0.01 ** 2, 0],
    [0, 0, deg * deg],
  ];
  let Q = [
    [0.01 ** 2, 0],
    [0, deg * deg],
  ];
  let delta_M = 0.999;
  if (dataset === 'outliers') {
    Q = matScale(identity(2), 0.2 ** 2);
  } else if (dataset === 'no-odometry') {
    R = identity(3);
    Q = matScale(identity(2), 0.1 ** 2);
    delta_M = 1;
  }
  const mu = [0, 0, 0];
  const sigma = matScale(identity(3), 1e-10);
  const Lambda_M = delta_M === 1 ? Infinity : -2 * Math.log(1 - delta_M);
  return { mu, sigma, R, Q, Lambda_M };
}
