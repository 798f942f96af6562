// The sensor-fusion exercise's loop in the test harness (static/src/harness.js): the
// filter over one trial with the student's functions, recording the belief after every
// step (`TrialRecord` in Rust). Loaded with the harness, before any student code runs, in
// the browser's worker and the server's sandbox alike.
estlabHarness.defineLoop('fusion', (tools) => {
  'use strict';
  const { HarnessError, put, push, copy, field, vector, matrix, number, threshold, flag } = tools;

  /// A finite number of 0 or more.
  const constant = (value, what) => number(threshold(value, what), what);
  /// A finite number above 0.
  function positive(value, what) {
    if (!(number(value, what) > 0)) throw new HarnessError(what + ' is ' + value + ', not a number > 0');
    return value;
  }

  /// The settings `tuning()` returns, checked field by field: the process noise constants
  /// finite and not negative, c_xy above 0, the field of view and the gate 0 or more
  /// (Infinity: every reading in view, no gate).
  /** @returns {import('estlab/types/FilterSettings').FilterSettings} */
  function tuned(invoke) {
    const settings = invoke('tuning', [], 'calling tuning()');
    return {
      k_xy: field(settings, 'k_xy', constant),
      k_theta: field(settings, 'k_theta', constant),
      c_xy: field(settings, 'c_xy', positive),
      field_of_view: field(settings, 'field_of_view', threshold),
      lambda: field(settings, 'lambda', threshold),
    };
  }

  /// The settings of a run's job, each number as JSON carried it ("Infinity" back as one).
  /** @param {import('estlab/types/FilterSettings').FilterSettings} settings */
  function given(settings) {
    return {
      k_xy: copy(settings.k_xy),
      k_theta: copy(settings.k_theta),
      c_xy: copy(settings.c_xy),
      field_of_view: copy(settings.field_of_view),
      lambda: copy(settings.lambda),
    };
  }

  /// The fusion loop over a trial: with the run's settings, or those of the student's
  /// `tuning()` where the run has none (the class's held-out trials, asked before any of
  /// its data reaches the student's code), from the odometry's first pose, every step
  /// predicts with the odometry's motion since the step before, and a reading the detector
  /// made corrects the belief when it is in the field of view and within the gate.
  /** @type {Loop<import('estlab/types/TrialRun').TrialRun, import('estlab/types/TrialRecord').TrialRecord>} */
  function fusionLoop(run, kept, invoke, at) {
    put(kept, 'poses', []);
    put(kept, 'covariances', []);
    let settings;
    if (run.settings === null) {
      settings = tuned(invoke);
      put(kept, 'tuning', settings);
    } else {
      settings = given(run.settings);
    }
    /** @type {number[]} */
    let mu = copy(run.start);
    /** @type {number[][]} */
    let sigma = copy(run.start_sigma);
    for (let k = 0; k < run.steps.length; k++) {
      const step = run.steps[k];
      at.step = 'at step ' + (k + 1) + ', ';
      if (k > 0) {
        const bar = invoke('predict', [copy(mu), copy(sigma), copy(run.steps[k - 1].odom),
          copy(step.odom), settings.k_xy, settings.k_theta]);
        mu = field(bar, 'mu_bar', vector(3));
        sigma = field(bar, 'sigma_bar', matrix(3, 3));
      }
      const platforms = step.platforms;
      if (platforms !== null) {
        const p1 = platforms[0];
        const p2 = platforms[1];
        const z = vector(3)(invoke('combine_platforms', [copy(p1), copy(p2)]), 'z');
        const inView = flag(invoke('in_field_of_view', [copy(z), settings.field_of_view]),
          'in_view');
        if (inView) {
          const Q = matrix(3, 3)(invoke('measurement_noise', [copy(p1), copy(p2), settings.c_xy]),
            'Q');
          const d2 = number(invoke('mahalanobis', [copy(mu), copy(sigma), copy(z), copy(Q)]),
            'd2');
          if (d2 <= settings.lambda) {
            const post = invoke('update', [copy(mu), copy(sigma), copy(z), copy(Q)]);
            mu = field(post, 'mu', vector(3));
            sigma = field(post, 'sigma', matrix(3, 3));
          }
        }
      }
      push(kept.poses, copy(mu));
      push(kept.covariances, copy(sigma));
    }
  }

  return fusionLoop;
});
