// The loop of the exercise on the UKF and the particle filter in the test harness
// (static/src/harness.js): one of the two filters along a generated robot with the
// student's functions, recording the belief at the start and after every step
// (`FilterRecord` in Rust). Every random number the particle filter uses comes from the
// run. Loaded with the harness, before any student code runs, in the browser's worker and
// the server's sandbox alike.
estlabHarness.defineLoop('mrclam', (tools) => {
  'use strict';
  const { HarnessError, put, push, copy, field, list, vector, matrix, number, flag } = tools;

  /// n poses, each three finite numbers.
  const poses = (n) => (value, what) => {
    list(n)(value, what);
    for (let i = 0; i < n; i++) vector(3)(value[i], what + '[' + i + ']');
    return value;
  };

  /// n indices of particles, whole numbers from 0 to n - 1.
  const indices = (n) => (value, what) => {
    list(n)(value, what);
    for (let i = 0; i < n; i++) {
      const index = value[i];
      // (`% 1`, an operator, which the student's code cannot replace as it can Math.floor.)
      if (typeof index !== 'number' || !(index >= 0 && index < n) || index % 1 !== 0) {
        throw new HarnessError(what + '[' + i + '] is ' + tools.describe(index) +
          ', not the index of a particle, 0 to ' + (n - 1));
      }
    }
    return value;
  };

  /// The UKF along the run from its start: at every step the process noise at the mean,
  /// the unscented prediction, and each reading's update when the gate lets it through.
  function ukf(run, kept, invoke, at, { Q, alphas }) {
    /** @type {number[]} */
    let mu = copy(run.start);
    /** @type {number[][]} */
    let sigma = copy(run.start_sigma);
    push(kept.poses, copy(mu));
    push(kept.covariances, copy(sigma));
    for (let k = 0; k < run.steps.length; k++) {
      const step = run.steps[k];
      at.step = 'at step ' + (k + 1) + ', ';
      const R = matrix(3, 3)(invoke('process_noise', [copy(mu), copy(step.u), run.dt,
        copy(alphas)]), 'R');
      const bar = invoke('ukf_predict', [copy(mu), copy(sigma), copy(step.u), run.dt, R]);
      mu = field(bar, 'mu_bar', vector(3));
      sigma = field(bar, 'sigma_bar', matrix(3, 3));
      for (let i = 0; i < step.readings.length; i++) {
        const reading = step.readings[i];
        const post = invoke('ukf_update', [copy(mu), copy(sigma), copy(reading.z),
          copy(reading.landmark), copy(Q)]);
        const d2 = field(post, 'd2', number);
        if (d2 <= run.gate) {
          mu = field(post, 'mu', vector(3));
          sigma = field(post, 'sigma', matrix(3, 3));
        }
      }
      push(kept.poses, copy(mu));
      push(kept.covariances, copy(sigma));
    }
  }

  /// The particle filter along the run from its cloud: at every step where the robot
  /// moves, the particles sampled with the step's draws; each reading weighs them; after
  /// a reading, a cloud worth less than half its count is resampled with the step's
  /// offset; and the cloud's estimate is the belief.
  function particleFilter(run, kept, invoke, at, { Q, alphas }) {
    const start = run.particles;
    if (start === null) throw new HarnessError('the run has no particles');
    const n = start.length;
    /** @type {number[][]} */
    let particles = copy(start);
    /** @type {number[]} */
    let weights = [];
    for (let i = 0; i < n; i++) push(weights, 1 / n);
    const estimate = () => {
      const belief = invoke('particle_estimate', [copy(particles), copy(weights)]);
      push(kept.poses, copy(field(belief, 'mu', vector(3))));
      push(kept.covariances, copy(field(belief, 'sigma', matrix(3, 3))));
    };
    at.step = 'at the start, ';
    estimate();
    for (let k = 0; k < run.steps.length; k++) {
      const step = run.steps[k];
      at.step = 'at step ' + (k + 1) + ', ';
      if (step.normals !== null) {
        particles = poses(n)(invoke('sample_motion', [copy(particles), copy(step.u), run.dt,
          copy(alphas), copy(step.normals)]), 'particles');
      }
      for (let i = 0; i < step.readings.length; i++) {
        const reading = step.readings[i];
        weights = vector(n)(invoke('particle_weights', [copy(particles), copy(weights),
          copy(reading.z), copy(reading.landmark), copy(Q)]), 'weights');
      }
      if (step.readings.length > 0 &&
        flag(invoke('needs_resampling', [copy(weights)]), 'resample')) {
        if (step.r === null) throw new HarnessError('the step has no offset to resample with');
        const kept_ = indices(n)(invoke('low_variance_resample', [copy(weights), step.r]),
          'indices');
        /** @type {number[][]} */
        const drawn = [];
        /** @type {number[]} */
        const even = [];
        for (let i = 0; i < n; i++) {
          push(drawn, copy(particles[kept_[i]]));
          push(even, 1 / n);
        }
        particles = drawn;
        weights = even;
      }
      estimate();
    }
  }

  /// The loop over a run: the camera's noise learned from the residuals and the control
  /// noise's alphas from the commands beside the motion the truth implies, then the run's
  /// filter.
  /** @type {Loop<import('estlab/types/UkfParticleRun').UkfParticleRun, import('estlab/types/UkfParticleRecord').UkfParticleRecord>} */
  function mrclamLoop(run, kept, invoke, at) {
    put(kept, 'poses', []);
    put(kept, 'covariances', []);
    at.step = 'at the start, ';
    const Q = copy(matrix(2, 2)(invoke('measurement_noise', [copy(run.residuals)]), 'Q'));
    put(kept, 'Q', Q);
    const alphas = copy(vector(4)(invoke('learn_alphas', [copy(run.commanded), copy(run.implied)]),
      'alphas'));
    put(kept, 'alphas', alphas);
    const noise = { Q, alphas };
    if (run.filter === 'ukf') ukf(run, kept, invoke, at, noise);
    else particleFilter(run, kept, invoke, at, noise);
  }

  return mrclamLoop;
});
