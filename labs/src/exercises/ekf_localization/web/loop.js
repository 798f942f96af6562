// The EKF localization exercise's loop in the test harness (static/src/harness.js): the
// lab's filter loop over one data set with the student's functions, recording the belief
// after every step and every reading's association (`FilterRecord` in Rust). Loaded with
// the harness, before any student code runs, in the browser's worker and the server's
// sandbox alike.
estlabHarness.defineLoop('filter', (tools) => {
  'use strict';
  const { HarnessError, put, push, copy, plain, field, list, vector, matrix, threshold, flag, describe } = tools;

  /// The filter loop over a data set, as the lab's.
  /** @type {Loop<import('estlab/types/FilterRun').FilterRun, import('estlab/types/FilterRecord').FilterRecord>} */
  function filterLoop(run, kept, invoke, at) {
    put(kept, 'init', null);
    put(kept, 'mu', []);
    put(kept, 'sigma', []);
    put(kept, 'c', []);
    put(kept, 'outlier', []);
    const init = "init('" + run.dataset + "')";
    const tuning = put(kept, 'init', invoke('init', [run.dataset], init));
    let mu = field(tuning, 'mu', vector(3));
    let sigma = field(tuning, 'sigma', matrix(3, 3));
    const R = field(tuning, 'R', matrix(3, 3));
    const Q = field(tuning, 'Q', matrix(2, 2));
    const lambda = field(tuning, 'Lambda_M', threshold);
    const robot = run.robot;
    const M = run.M;
    const landmarks = M[0].length;
    const index = (value, what) => {
      if (typeof value !== 'number' || value % 1 !== 0 || value < 0 || value >= landmarks) {
        throw new HarnessError(what + ' is ' + describe(value) +
          ', not a landmark index from 0 to ' + (landmarks - 1));
      }
      return value;
    };
    for (let k = 0; k < run.steps.length; k++) {
      const step = run.steps[k];
      at.step = 'at time step ' + (k + 1) + ', ';
      const u = vector(3)(invoke('calculate_odometry', [step.e_r, step.e_l, robot.E_T,
        robot.B, robot.R_R, robot.R_L, step.delta_t, copy(mu)]), 'u');
      const bar = invoke('predict', [copy(mu), copy(sigma), u, copy(R)]);
      let muBar = field(bar, 'mu_bar', vector(3));
      let sigmaBar = field(bar, 'sigma_bar', matrix(3, 3));
      const z = step.z;
      const n = z[0].length;
      if (run.mode === 'batch') {
        const a = invoke('batch_associate', [copy(muBar), copy(sigmaBar), copy(z), copy(M),
          lambda, copy(Q)]);
        const c = field(a, 'c', list(n));
        const outlier = field(a, 'outlier', list(n));
        const nuBar = field(a, 'nu_bar', vector(2 * n));
        const hBar = field(a, 'H_bar', matrix(2 * n, 3));
        const H = [];
        const nu = [];
        for (let i = 0; i < n; i++) {
          push(kept.c, index(c[i], 'c[' + i + ']'));
          if (!flag(outlier[i], 'outlier[' + i + ']')) {
            push(H, hBar[2 * i]);
            push(H, hBar[2 * i + 1]);
            push(nu, nuBar[2 * i]);
            push(nu, nuBar[2 * i + 1]);
          }
          push(kept.outlier, outlier[i]);
        }
        if (nu.length > 0) {
          const post = invoke('batch_update', [copy(muBar), copy(sigmaBar), H,
            blockDiagonal(Q, nu.length / 2), nu]);
          muBar = field(post, 'mu', vector(3));
          sigmaBar = field(post, 'sigma', matrix(3, 3));
        }
      } else {
        for (let i = 0; i < n; i++) {
          // Of associate's answer for every landmark, the loop takes what it reads: c,
          // outlier, and H, S and nu of landmark c (a whole data set's run would copy
          // a hundred arrays a reading that nothing reads).
          const a = invoke('associate', [copy(muBar), copy(sigmaBar), [z[0][i], z[1][i]],
            copy(M), lambda, copy(Q)], undefined, (answer) => {
            const c = index(field(answer, 'c', plain), 'c');
            const isOutlier = flag(field(answer, 'outlier', plain), 'outlier');
            /** @param {string} name */
            const ofC = (name) => plain(field(answer, name, list(landmarks))[c]);
            return isOutlier
              ? { c, isOutlier }
              : {
                c, isOutlier, H: matrix(2, 3)(ofC('H'), 'H[' + c + ']'),
                S: matrix(2, 2)(ofC('S'), 'S[' + c + ']'), nu: vector(2)(ofC('nu'), 'nu[' + c + ']'),
              };
          });
          const { c, isOutlier } = a;
          push(kept.c, c);
          push(kept.outlier, isOutlier);
          if (!isOutlier) {
            const post = invoke('update', [copy(muBar), copy(sigmaBar), a.H, a.S, a.nu]);
            muBar = field(post, 'mu', vector(3));
            sigmaBar = field(post, 'sigma', matrix(3, 3));
          }
        }
      }
      mu = muBar;
      sigma = sigmaBar;
      push(kept.mu, mu);
      push(kept.sigma, [sigma[0][0], sigma[0][1], sigma[0][2], sigma[1][0], sigma[1][1],
        sigma[1][2], sigma[2][0], sigma[2][1], sigma[2][2]]);
    }
  }


  function blockDiagonal(Q, n) {
    const out = [];
    for (let i = 0; i < 2 * n; i++) {
      const row = put(out, i, []);
      for (let j = 0; j < 2 * n; j++) {
        put(row, j, (i >> 1) === (j >> 1) ? Q[i & 1][j & 1] : 0);
      }
    }
    return out;
  }

  return filterLoop;
});
