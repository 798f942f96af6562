// Fusing odometry with an indoor positioning sensor: a correct solution of the student
// contract.
//
// A pose is [x, y, theta], a platform's reading [x, y, I] (platform 1 at the front).
// Matrices are arrays of rows. R is the process noise, Q the measurement noise. Each
// function works out what it needs from its own arguments and keeps nothing between
// calls.

const TWO_PI = 2 * Math.PI;

// An angle moved by whole turns into [-pi, pi).
function wrapAngle(a) {
  if (a >= -Math.PI && a < Math.PI) return a;
  const wrapped = a - TWO_PI * Math.floor((a + Math.PI) / TWO_PI);
  // Rounding can land exactly on +pi, which belongs to the other end of the interval.
  return wrapped >= Math.PI ? wrapped - TWO_PI : wrapped;
}

// A times B, for arrays of rows.
function mul(A, B) {
  const C = [];
  for (let i = 0; i < A.length; i++) {
    const row = [];
    for (let j = 0; j < B[0].length; j++) {
      let sum = 0;
      for (let k = 0; k < B.length; k++) sum += A[i][k] * B[k][j];
      row.push(sum);
    }
    C.push(row);
  }
  return C;
}

function transpose(A) {
  const T = [];
  for (let j = 0; j < A[0].length; j++) {
    const row = [];
    for (let i = 0; i < A.length; i++) row.push(A[i][j]);
    T.push(row);
  }
  return T;
}

function add(A, B) {
  return A.map((row, i) => row.map((a, j) => a + B[i][j]));
}

function symmetrise(A) {
  return A.map((row, i) => row.map((a, j) => (a + A[j][i]) / 2));
}

function diag(values) {
  return values.map((v, i) => values.map((_, j) => (i === j ? v : 0)));
}

// The inverse of a 3 x 3 matrix by its cofactors.
function inverse3(A) {
  const [[a, b, c], [d, e, f], [g, h, i]] = A;
  const C = [
    [e * i - f * h, c * h - b * i, b * f - c * e],
    [f * g - d * i, a * i - c * g, c * d - a * f],
    [d * h - e * g, b * g - a * h, a * e - b * d],
  ];
  const det = a * C[0][0] + b * C[1][0] + c * C[2][0];
  return C.map((row) => row.map((v) => v / det));
}

// The innovation z - mu, its heading wrapped.
function innovation(mu, z) {
  return [z[0] - mu[0], z[1] - mu[1], wrapAngle(z[2] - mu[2])];
}

function combine_platforms(p1, p2) {
  const w1 = p1[2] / (p1[2] + p2[2]);
  const w2 = p2[2] / (p1[2] + p2[2]);
  return [
    w1 * p1[0] + w2 * p2[0],
    w1 * p1[1] + w2 * p2[1],
    Math.atan2(p1[1] - p2[1], p1[0] - p2[0]),
  ];
}

function heading_sigma(p1, p2, c_xy) {
  const s1 = c_xy / p1[2];
  const s2 = c_xy / p2[2];
  const dx = p1[0] - p2[0];
  const dy = p1[1] - p2[1];
  const l2 = dx * dx + dy * dy;
  // d theta / d(x1, y1) = (-dy, dx) / L^2; platform 2's are the opposite.
  const terms = [
    [-dy / l2, dx / l2, s1],
    [dy / l2, -dx / l2, s2],
  ];
  let variance = 0;
  for (const [dX, dY, s] of terms) variance += (dX * s) ** 2 + (dY * s) ** 2;
  return Math.sqrt(variance);
}

function measurement_noise(p1, p2, c_xy) {
  const s1 = c_xy / p1[2];
  const s2 = c_xy / p2[2];
  const sxy = Math.max(s1, s2);
  // sigma_theta as heading_sigma has it, in closed form: its four terms sum to
  // (s1^2 + s2^2) / L^2. (Worked out here rather than called, so that each
  // function of this file can be broken alone.)
  const st = Math.sqrt(s1 * s1 + s2 * s2) / Math.hypot(p1[0] - p2[0], p1[1] - p2[1]);
  return diag([sxy * sxy, sxy * sxy, st * st]);
}

function in_field_of_view(z, radius) {
  return Math.sqrt(z[0] * z[0] + z[1] * z[1]) <= radius;
}

function predict(mu, sigma, odom_prev, odom, k_xy, k_theta) {
  // The odometry's increment in the frame of its previous pose.
  const c0 = Math.cos(odom_prev[2]);
  const s0 = Math.sin(odom_prev[2]);
  const gx = odom[0] - odom_prev[0];
  const gy = odom[1] - odom_prev[1];
  const dx = c0 * gx + s0 * gy;
  const dy = -s0 * gx + c0 * gy;
  const dtheta = wrapAngle(odom[2] - odom_prev[2]);
  // Applied along the belief's own heading.
  const c = Math.cos(mu[2]);
  const s = Math.sin(mu[2]);
  const mu_bar = [
    mu[0] + c * dx - s * dy,
    mu[1] + s * dx + c * dy,
    wrapAngle(mu[2] + dtheta),
  ];
  const G = [
    [1, 0, -s * dx - c * dy],
    [0, 1, c * dx - s * dy],
    [0, 0, 1],
  ];
  const moved = Math.hypot(dx, dy);
  const R = diag([
    (k_xy * moved) ** 2,
    (k_xy * moved) ** 2,
    (k_theta * (moved + Math.abs(dtheta))) ** 2,
  ]);
  const sigma_bar = symmetrise(add(mul(mul(G, sigma), transpose(G)), R));
  return { mu_bar, sigma_bar };
}

function mahalanobis(mu_bar, sigma_bar, z, Q) {
  const nu = innovation(mu_bar, z);
  const S_inv = inverse3(add(sigma_bar, Q));
  let d2 = 0;
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j < 3; j++) d2 += nu[i] * S_inv[i][j] * nu[j];
  }
  return d2;
}

function update(mu_bar, sigma_bar, z, Q) {
  const nu = innovation(mu_bar, z);
  const K = mul(sigma_bar, inverse3(add(sigma_bar, Q)));
  const step = mul(K, nu.map((v) => [v]));
  const mu = [
    mu_bar[0] + step[0][0],
    mu_bar[1] + step[1][0],
    wrapAngle(mu_bar[2] + step[2][0]),
  ];
  const I_K = K.map((row, i) => row.map((k, j) => (i === j ? 1 : 0) - k));
  return { mu, sigma: symmetrise(mul(I_K, sigma_bar)) };
}

// The settings of the class challenge: the reference filter's defaults.
function tuning() {
  return {
    k_xy: 0.05, k_theta: 0.05, c_xy: 90, field_of_view: 2,
    lambda: 16.266236196238,
  };
}
