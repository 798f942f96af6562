// Odometry and how its error grows: a correct solution of the student contract.
//
// The pose is p = [x, y, theta]. In one step the right wheel rolls ds_r and the left
// wheel ds_l metres (negative: backwards); b is the wheel base, the distance between
// the wheels. Matrices are arrays of rows. Each function works out what it needs from
// its own arguments and keeps nothing between calls.

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

// (A + A^T) / 2: exactly symmetric, whatever rounding did to A's two triangles.
function symmetrise(A) {
  return A.map((row, i) => row.map((a, j) => (a + A[j][i]) / 2));
}

// ---- One step of odometry ----
// ds = (ds_r + ds_l) / 2, dtheta = (ds_r - ds_l) / b, and the chord of the arc points
// along the heading halfway through the turn, phi = theta + dtheta / 2:
//   p' = p + [ds cos(phi), ds sin(phi), dtheta], theta' wrapped to [-pi, pi).
function odometry_step(p, ds_r, ds_l, b) {
  const ds = (ds_r + ds_l) / 2;
  const dtheta = (ds_r - ds_l) / b;
  const phi = p[2] + dtheta / 2;
  return [p[0] + ds * Math.cos(phi), p[1] + ds * Math.sin(phi), wrapAngle(p[2] + dtheta)];
}

// ---- F_p = d p' / d p ----
//   | 1  0  -ds sin(phi) |
//   | 0  1   ds cos(phi) |
//   | 0  0   1           |
function pose_jacobian(p, ds_r, ds_l, b) {
  const ds = (ds_r + ds_l) / 2;
  const dtheta = (ds_r - ds_l) / b;
  const phi = p[2] + dtheta / 2;
  return [
    [1, 0, -ds * Math.sin(phi)],
    [0, 1, ds * Math.cos(phi)],
    [0, 0, 1],
  ];
}

// ---- F_delta = d p' / d(ds_r, ds_l) ----
// Each wheel moves ds by 1/2 and dtheta by +-1/b, and so phi by +-1/(2b):
//   | cos(phi)/2 - ds sin(phi)/(2b)   cos(phi)/2 + ds sin(phi)/(2b) |
//   | sin(phi)/2 + ds cos(phi)/(2b)   sin(phi)/2 - ds cos(phi)/(2b) |
//   | 1/b                             -1/b                          |
function increment_jacobian(p, ds_r, ds_l, b) {
  const ds = (ds_r + ds_l) / 2;
  const dtheta = (ds_r - ds_l) / b;
  const phi = p[2] + dtheta / 2;
  const c = Math.cos(phi) / 2;
  const s = Math.sin(phi) / 2;
  const turn = ds / (2 * b);
  return [
    [c - turn * Math.sin(phi), c + turn * Math.sin(phi)],
    [s + turn * Math.cos(phi), s - turn * Math.cos(phi)],
    [1 / b, -1 / b],
  ];
}

// ---- Sigma_delta = diag(k_r |ds_r|, k_l |ds_l|) ----
// Each wheel's variance grows with the distance it rolls, forwards or backwards.
function wheel_noise(ds_r, ds_l, k_r, k_l) {
  return [
    [k_r * Math.abs(ds_r), 0],
    [0, k_l * Math.abs(ds_l)],
  ];
}

// ---- Sigma_p' = F_p Sigma_p F_p^T + F_delta Sigma_delta F_delta^T, symmetrised ----
function propagate(Sigma_p, F_p, F_delta, Sigma_delta) {
  const fromPose = mul(mul(F_p, Sigma_p), transpose(F_p));
  const fromWheels = mul(mul(F_delta, Sigma_delta), transpose(F_delta));
  return symmetrise(add(fromPose, fromWheels));
}
