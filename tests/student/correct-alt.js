// EKF localization (EL2320 lab): another correct solution of the student contract,
// written differently from correct.js where the lab leaves a choice: angles wrapped with
// atan2, the likelihood psi itself (not its logarithm) maximised, the covariance updated
// in Joseph form, 2 x 2 and general inverses written out separately.

const PI = Math.PI;

// Wraps an angle to [-pi, pi) through atan2, whose (-pi, pi] needs its upper end moved.
function wrapAngle(a) {
  const w = Math.atan2(Math.sin(a), Math.cos(a));
  return w >= PI ? -PI : w;
}

function mul(A, B) {
  return A.map((row) => B[0].map((_, j) => row.reduce((s, a, k) => s + a * B[k][j], 0)));
}

function tr(A) {
  return A[0].map((_, j) => A.map((row) => row[j]));
}

function add(A, B) {
  return A.map((row, i) => row.map((a, j) => a + B[i][j]));
}

function eye(n) {
  return Array.from({ length: n }, (_, i) => Array.from({ length: n }, (_, j) => (i === j ? 1 : 0)));
}

function inv2(S) {
  const det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
  return [
    [S[1][1] / det, -S[0][1] / det],
    [-S[1][0] / det, S[0][0] / det],
  ];
}

// Solves A X = B for X (A n x n, B n x m) by Gaussian elimination with partial pivoting.
function solve(A, B) {
  const n = A.length;
  const a = A.map((row, i) => row.concat(B[i]));
  const m = a[0].length;
  for (let k = 0; k < n; k++) {
    let p = k;
    for (let r = k + 1; r < n; r++) if (Math.abs(a[r][k]) > Math.abs(a[p][k])) p = r;
    [a[k], a[p]] = [a[p], a[k]];
    for (let r = k + 1; r < n; r++) {
      const f = a[r][k] / a[k][k];
      for (let c = k; c < m; c++) a[r][c] -= f * a[k][c];
    }
  }
  const X = Array.from({ length: n }, () => new Array(m - n).fill(0));
  for (let c = 0; c < m - n; c++) {
    for (let i = n - 1; i >= 0; i--) {
      let s = a[i][n + c];
      for (let k = i + 1; k < n; k++) s -= a[i][k] * X[k][c];
      X[i][c] = s / a[i][i];
    }
  }
  return X;
}

function symmetric(A) {
  return A.map((row, i) => row.map((a, j) => (a + A[j][i]) / 2));
}

function calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu) {
  if (delta_t === 0) return [0, 0, 0];
  // Distances the wheels rolled over the step (omega_R R_R dt and omega_L R_L dt).
  const d_R = (2 * PI * R_R * e_R) / E_T;
  const d_L = (2 * PI * R_L * e_L) / E_T;
  const distance = (d_R + d_L) / 2;
  return [distance * Math.cos(mu[2]), distance * Math.sin(mu[2]), wrapAngle((d_R - d_L) / B)];
}

function predict(mu, sigma, u, R) {
  const G = [
    [1, 0, -u[1]],
    [0, 1, u[0]],
    [0, 0, 1],
  ];
  return {
    mu_bar: [mu[0] + u[0], mu[1] + u[1], wrapAngle(mu[2] + u[2])],
    sigma_bar: symmetric(add(mul(G, mul(sigma, tr(G))), R)),
  };
}

function observation_model(x, M, j) {
  const dx = M[0][j] - x[0];
  const dy = M[1][j] - x[1];
  return [Math.hypot(dx, dy), wrapAngle(Math.atan2(dy, dx) - x[2])];
}

function jacobian_observation_model(x, M, j, z_hat) {
  const dx = M[0][j] - x[0];
  const dy = M[1][j] - x[1];
  const q = z_hat[0] * z_hat[0];
  return [
    [-dx / z_hat[0], -dy / z_hat[0], 0],
    [dy / q, -dx / q, -1],
  ];
}

// c maximises psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2) itself.
function associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q) {
  const out = { c: 0, outlier: false, nu: [], S: [], H: [] };
  let bestPsi = -1;
  let bestD = 0;
  for (let j = 0; j < M[0].length; j++) {
    const z_hat = observation_model(mu_bar, M, j);
    const H = jacobian_observation_model(mu_bar, M, j, z_hat);
    const S = add(mul(H, mul(sigma_bar, tr(H))), Q);
    const nu = [z_i[0] - z_hat[0], wrapAngle(z_i[1] - z_hat[1])];
    const Si = inv2(S);
    const D = nu[0] * (Si[0][0] * nu[0] + Si[0][1] * nu[1]) + nu[1] * (Si[1][0] * nu[0] + Si[1][1] * nu[1]);
    const det = (2 * PI) ** 2 * (S[0][0] * S[1][1] - S[0][1] * S[1][0]);
    const psi = Math.exp(-D / 2) / Math.sqrt(det);
    if (psi > bestPsi) {
      bestPsi = psi;
      bestD = D;
      out.c = j;
    }
    out.nu.push(nu);
    out.S.push(S);
    out.H.push(H);
  }
  out.outlier = !(bestD < Lambda_M);
  return out;
}

function batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q) {
  const out = { c: [], outlier: [], nu_bar: [], H_bar: [] };
  z[0].forEach((range, i) => {
    const a = associate(mu_bar, sigma_bar, [range, z[1][i]], M, Lambda_M, Q);
    out.c.push(a.c);
    out.outlier.push(a.outlier);
    out.nu_bar.push(...a.nu[a.c]);
    out.H_bar.push(...a.H[a.c]);
  });
  return out;
}

// The Kalman update in Joseph form, (I - K H) Sigma_bar (I - K H)^T + K Q K^T, with the
// measurement noise Q = S - H Sigma_bar H^T; K = Sigma_bar H^T S^-1 by solving S K^T =
// H Sigma_bar.
function josephUpdate(mu_bar, sigma_bar, H, S, Qm, nu) {
  const K = tr(solve(S, mul(H, sigma_bar)));
  const Knu = mul(K, nu.map((v) => [v])).map((row) => row[0]);
  const IKH = add(eye(3), mul(K, H).map((row) => row.map((v) => -v)));
  const sigma = add(mul(IKH, mul(sigma_bar, tr(IKH))), mul(K, mul(Qm, tr(K))));
  return {
    mu: [mu_bar[0] + Knu[0], mu_bar[1] + Knu[1], wrapAngle(mu_bar[2] + Knu[2])],
    sigma: symmetric(sigma),
  };
}

function update(mu_bar, sigma_bar, H, S, nu) {
  const HSHt = mul(H, mul(sigma_bar, tr(H)));
  const Qm = S.map((row, i) => row.map((s, j) => s - HSHt[i][j]));
  return josephUpdate(mu_bar, sigma_bar, H, S, Qm, nu);
}

function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) {
  const S = add(mul(H_bar, mul(sigma_bar, tr(H_bar))), Q_bar);
  return josephUpdate(mu_bar, sigma_bar, H_bar, S, Q_bar, nu_bar);
}

function init(dataset) {
  const deg = PI / 180;
  const noOdometry = dataset === 'no-odometry';
  const R = noOdometry ? eye(3) : [
    [1e-4, 0, 0],
    [0, 1e-4, 0],
    [0, 0, deg * deg],
  ];
  const q = { o3: [1e-4, deg * deg], outliers: [0.04, 0.04], 'no-odometry': [0.01, 0.01] }[dataset];
  const deltaM = noOdometry ? 1 : 0.999;
  return {
    mu: [0, 0, 0],
    sigma: eye(3).map((row) => row.map((v) => v * 1e-10)),
    R,
    Q: [
      [q[0], 0],
      [0, q[1]],
    ],
    Lambda_M: deltaM === 1 ? Infinity : -2 * Math.log(1 - deltaM),
  };
}
