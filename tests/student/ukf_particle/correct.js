// The unscented Kalman filter and the particle filter: a correct solution of the student
// contract.
//
// A pose is [x, y, theta], a control [v, omega], a reading [range, bearing], a post
// [x, y]. Matrices are arrays of rows; a cloud is an array of poses. R is the process
// noise, Q the measurement noise. Each function works out what it needs from its own
// arguments and keeps nothing between calls.

const TWO_PI = 2 * Math.PI;
const N = 3;

// An angle moved by whole turns into [-pi, pi).
function wrapAngle(a) {
  if (a >= -Math.PI && a < Math.PI) return a;
  const wrapped = a - TWO_PI * Math.floor((a + Math.PI) / TWO_PI);
  // Rounding can land exactly on +pi, which belongs to the other end of the interval.
  return wrapped >= Math.PI ? wrapped - TWO_PI : wrapped;
}

function mul(A, B) {
  return A.map((row) => B[0].map((_, j) => row.reduce((sum, a, k) => sum + a * B[k][j], 0)));
}

function transpose(A) {
  return A[0].map((_, j) => A.map((row) => row[j]));
}

function add(A, B) {
  return A.map((row, i) => row.map((a, j) => a + B[i][j]));
}

function scale(A, s) {
  return A.map((row) => row.map((a) => a * s));
}

function symmetrise(A) {
  return A.map((row, i) => row.map((a, j) => (a + A[j][i]) / 2));
}

function inverse2(A) {
  const [[a, b], [c, d]] = A;
  const det = a * d - b * c;
  return [[d / det, -b / det], [-c / det, a / det]];
}

// The lower triangular L with L L^T = A.
function cholesky(A) {
  const n = A.length;
  const L = A.map(() => new Array(n).fill(0));
  for (let j = 0; j < n; j++) {
    let d = A[j][j];
    for (let k = 0; k < j; k++) d -= L[j][k] * L[j][k];
    L[j][j] = Math.sqrt(d);
    for (let i = j + 1; i < n; i++) {
      let s = A[i][j];
      for (let k = 0; k < j; k++) s -= L[i][k] * L[j][k];
      L[i][j] = s / L[j][j];
    }
  }
  return L;
}

// sum w_i a_i b_i^T for column deviations a_i, b_i.
function weightedOuter(as, bs, w) {
  let C = as[0].map(() => bs[0].map(() => 0));
  for (let i = 0; i < as.length; i++) {
    C = add(C, as[i].map((a) => bs[i].map((b) => w[i] * a * b)));
  }
  return C;
}

// The weighted mean of points, component `angle` averaged as an angle.
function weightedMean(points, w, angle) {
  const mean = points[0].map((_, c) => points.reduce((sum, p, i) => sum + w[i] * p[c], 0));
  let s = 0;
  let co = 0;
  for (let i = 0; i < points.length; i++) {
    s += w[i] * Math.sin(points[i][angle]);
    co += w[i] * Math.cos(points[i][angle]);
  }
  mean[angle] = Math.atan2(s, co);
  return mean;
}

// point - mean, component `angle` wrapped.
function deviation(point, mean, angle) {
  return point.map((p, c) => (c === angle ? wrapAngle(p - mean[c]) : p - mean[c]));
}

function motion(pose, u, dt) {
  const [x, y, theta] = pose;
  const [v, omega] = u;
  if (omega === 0) {
    return [x + v * dt * Math.cos(theta), y + v * dt * Math.sin(theta), theta];
  }
  const turned = theta + omega * dt;
  return [
    x + (v / omega) * (-Math.sin(theta) + Math.sin(turned)),
    y + (v / omega) * (Math.cos(theta) - Math.cos(turned)),
    wrapAngle(turned),
  ];
}

function controlSd(u, alphas) {
  const [a1, a2, a3, a4] = alphas;
  const v = Math.abs(u[0]);
  const omega = Math.abs(u[1]);
  return [a1 * v + a2 * omega, a3 * v + a4 * omega];
}

function process_noise(mu, u, dt, alphas) {
  const theta = mu[2];
  const [v, omega] = u;
  let V;
  if (omega === 0) {
    V = [
      [dt * Math.cos(theta), -v * dt * dt * Math.sin(theta) / 2],
      [dt * Math.sin(theta), v * dt * dt * Math.cos(theta) / 2],
      [0, dt],
    ];
  } else {
    const turned = theta + omega * dt;
    const dsin = -Math.sin(theta) + Math.sin(turned);
    const dcos = Math.cos(theta) - Math.cos(turned);
    V = [
      [dsin / omega, -v * dsin / (omega * omega) + v * dt * Math.cos(turned) / omega],
      [dcos / omega, -v * dcos / (omega * omega) + v * dt * Math.sin(turned) / omega],
      [0, dt],
    ];
  }
  const [sdV, sdOmega] = controlSd(u, alphas);
  const M = [[sdV * sdV, 0], [0, sdOmega * sdOmega]];
  return mul(mul(V, M), transpose(V));
}

function sigma_points(mu, sigma, alpha, beta, kappa) {
  const lambda = alpha * alpha * (N + kappa) - N;
  const L = cholesky(scale(sigma, N + lambda));
  const X = [mu.slice()];
  for (let i = 0; i < N; i++) X.push(mu.map((m, r) => m + L[r][i]));
  for (let i = 0; i < N; i++) X.push(mu.map((m, r) => m - L[r][i]));
  const wm = new Array(2 * N + 1).fill(1 / (2 * (N + lambda)));
  const wc = wm.slice();
  wm[0] = lambda / (N + lambda);
  wc[0] = wm[0] + (1 - alpha * alpha + beta);
  return { X, wm, wc };
}

function ukf_predict(mu, sigma, u, dt, R) {
  const { X, wm, wc } = sigma_points(mu, sigma, 1, 2, 1);
  const moved = X.map((p) => motion(p, u, dt));
  const muBar = weightedMean(moved, wm, 2);
  const d = moved.map((p) => deviation(p, muBar, 2));
  return { mu_bar: muBar, sigma_bar: symmetrise(add(weightedOuter(d, d, wc), R)) };
}

// The camera's reading of a post from a pose: [range, bearing wrapped].
function seen(pose, landmark) {
  const dx = landmark[0] - pose[0];
  const dy = landmark[1] - pose[1];
  return [Math.hypot(dx, dy), wrapAngle(Math.atan2(dy, dx) - pose[2])];
}

function ukf_update(mu_bar, sigma_bar, z, landmark, Q) {
  const { X, wm, wc } = sigma_points(mu_bar, sigma_bar, 1, 2, 1);
  const Z = X.map((p) => seen(p, landmark));
  const zHat = weightedMean(Z, wm, 1);
  const e = Z.map((r) => deviation(r, zHat, 1));
  const d = X.map((p) => deviation(p, mu_bar, 2));
  const S = add(weightedOuter(e, e, wc), Q);
  const T = weightedOuter(d, e, wc);
  const Sinv = inverse2(S);
  const K = mul(T, Sinv);
  const nu = deviation(z, zHat, 1);
  const mu = mu_bar.map((m, r) => m + K[r][0] * nu[0] + K[r][1] * nu[1]);
  mu[2] = wrapAngle(mu[2]);
  const sigma = symmetrise(add(sigma_bar, scale(mul(mul(K, S), transpose(K)), -1)));
  const d2 = nu[0] * (Sinv[0][0] * nu[0] + Sinv[0][1] * nu[1]) +
    nu[1] * (Sinv[1][0] * nu[0] + Sinv[1][1] * nu[1]);
  return { mu, sigma, d2 };
}

function sample_motion(particles, u, dt, alphas, normals) {
  const [sdV, sdOmega] = controlSd(u, alphas);
  return particles.map((p, i) => {
    const drawn = [u[0] + sdV * normals[i][0], u[1] + sdOmega * normals[i][1]];
    return motion(p, drawn, dt);
  });
}

function particle_weights(particles, weights, z, landmark, Q) {
  const Qinv = inverse2(Q);
  const d = particles.map((p) => {
    const nu = deviation(z, seen(p, landmark), 1);
    return nu[0] * (Qinv[0][0] * nu[0] + Qinv[0][1] * nu[1]) +
      nu[1] * (Qinv[1][0] * nu[0] + Qinv[1][1] * nu[1]);
  });
  // Scaled by the likeliest particle's likelihood, which the sum cancels: no underflow.
  const closest = Math.min(...d);
  const raw = weights.map((w, i) => w * Math.exp(-0.5 * (d[i] - closest)));
  const total = raw.reduce((a, b) => a + b, 0);
  if (!(total > 0 && Number.isFinite(total))) return weights.map(() => 1 / weights.length);
  return raw.map((w) => w / total);
}

function needs_resampling(weights) {
  const size = 1 / weights.reduce((sum, w) => sum + w * w, 0);
  return size < weights.length / 2;
}

function low_variance_resample(weights, r) {
  const n = weights.length;
  const indices = [];
  let i = 0;
  let cumulative = weights[0];
  for (let m = 0; m < n; m++) {
    const tooth = (r + m) / n;
    while (tooth > cumulative && i + 1 < n) {
      i += 1;
      cumulative += weights[i];
    }
    indices.push(i);
  }
  return indices;
}

function particle_estimate(particles, weights) {
  const mu = weightedMean(particles, weights, 2);
  const d = particles.map((p) => deviation(p, mu, 2));
  return { mu, sigma: weightedOuter(d, d, weights) };
}

function measurement_noise(residuals) {
  const n = residuals.length;
  const Q = [[0, 0], [0, 0]];
  for (const [a, b] of residuals) {
    Q[0][0] += a * a;
    Q[0][1] += a * b;
    Q[1][0] += b * a;
    Q[1][1] += b * b;
  }
  return scale(Q, 1 / n);
}

// The non-negative least-squares (a, b) of y ~ a x1 + b x2 over the rows.
function nonNegativeFit(rows, ys) {
  let [sxx, sxy, syy, bx, by] = [0, 0, 0, 0, 0];
  rows.forEach(([x1, x2], k) => {
    sxx += x1 * x1;
    sxy += x1 * x2;
    syy += x2 * x2;
    bx += x1 * ys[k];
    by += x2 * ys[k];
  });
  const det = sxx * syy - sxy * sxy;
  if (det !== 0) {
    const a = (syy * bx - sxy * by) / det;
    const b = (sxx * by - sxy * bx) / det;
    if (a >= 0 && b >= 0) return [a, b];
  }
  // Each term alone, clamped at 0; the smaller squared error (up to the common y^T y).
  const alone = [sxx > 0 ? Math.max(bx / sxx, 0) : 0, syy > 0 ? Math.max(by / syy, 0) : 0];
  const sse = (a, b) => a * a * sxx + 2 * a * b * sxy + b * b * syy - 2 * (a * bx + b * by);
  return sse(alone[0], 0) <= sse(0, alone[1]) ? [alone[0], 0] : [0, alone[1]];
}

function learn_alphas(commanded, implied) {
  const scale = Math.sqrt(Math.PI / 2);
  const rows = commanded.map(([v, omega]) => [Math.abs(v), Math.abs(omega)]);
  const [a1, a2] = nonNegativeFit(rows, commanded.map((u, k) => scale * Math.abs(implied[k][0] - u[0])));
  const [a3, a4] = nonNegativeFit(rows, commanded.map((u, k) => scale * Math.abs(implied[k][1] - u[1])));
  return [a1, a2, a3, a4];
}
