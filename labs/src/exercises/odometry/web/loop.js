// The odometry exercise's loop in the test harness (static/src/harness.js): one path
// driven with the student's functions, recording the pose and its covariance after every
// step (`PathRecord` in Rust). Loaded with the harness, before any student code runs, in
// the browser's worker and the server's sandbox alike.
estlabHarness.defineLoop('path', (tools) => {
  'use strict';
  const { put, push, copy, vector, matrix } = tools;

  /// The loop along a path: from the start pose, known exactly
  /// (Sigma_p = 0), every step carries the pose's covariance through the step's Jacobians
  /// and adds the wheels' noise, then takes the step; the pose and its covariance after
  /// every step are recorded.
  /** @type {Loop<import('estlab/types/PathRun').PathRun, import('estlab/types/PathRecord').PathRecord>} */
  function pathLoop(run, kept, invoke, at) {
    put(kept, 'poses', []);
    put(kept, 'covariances', []);
    const b = run.b;
    /** @type {number[]} */
    let p = copy(run.start);
    let sigma = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (let k = 0; k < run.steps.length; k++) {
      const ds_r = run.steps[k][0];
      const ds_l = run.steps[k][1];
      at.step = 'at step ' + (k + 1) + ', ';
      const Fp = matrix(3, 3)(invoke('pose_jacobian', [copy(p), ds_r, ds_l, b]), 'F_p');
      const Fdelta = matrix(3, 2)(invoke('increment_jacobian', [copy(p), ds_r, ds_l, b]),
        'F_delta');
      const sigmaDelta = matrix(2, 2)(invoke('wheel_noise', [ds_r, ds_l, run.k_r, run.k_l]),
        'Sigma_delta');
      sigma = matrix(3, 3)(invoke('propagate', [copy(sigma), Fp, Fdelta, sigmaDelta]),
        'Sigma_p_next');
      p = vector(3)(invoke('odometry_step', [copy(p), ds_r, ds_l, b]), 'p_next');
      push(kept.poses, copy(p));
      push(kept.covariances, copy(sigma));
    }
  }

  return pathLoop;
});
