// A whole run of the fusion filter over a trial, taken out of wasm at once: the series
// the plots draw and the summary the tables show.
import { wrap } from '../angles.js';
import { ellipseSpacing, outlines } from '../plots.js';

/** @typedef {import('../types/FusionSummary').FusionSummary} FusionSummary */

/** What became of a step's reading (`FusionRun.readingUse`). */
export const readingUse = { none: 0, outsideView: 1, gated: 2, used: 3 };

/**
 * A run of the filter, as the page's views draw it.
 *
 * @typedef {object} FusionView
 * @property {Float64Array} t each step's time (the row's number where the trial has none)
 * @property {boolean} timed whether the trial has times of its own
 * @property {Float64Array[]} truth x, y, theta
 * @property {Float64Array[]} odometry the odometry's own pose
 * @property {Float64Array[]} estimate the filter's
 * @property {Float64Array[]} std the square roots of Sigma's diagonal
 * @property {Float64Array[]} error estimate minus truth, theta wrapped
 * @property {Float64Array[]} measurement the sensor's pose of each step (NaN: no reading)
 * @property {Uint8Array} use what became of each step's reading (`readingUse`)
 * @property {Float64Array} intensity the weaker platform's intensity (NaN: none known)
 * @property {boolean} platforms whether the readings have their platforms' intensities
 * @property {Float64Array[] | null} report the report's own estimate, where the trial has it
 * @property {{ coords: number[][] }[]} ellipses the 3σ ellipses of the position
 * @property {number} ellipseEvery the steps between them
 * @property {FusionSummary} summary
 */

/**
 * Runs the filter with `settings` over `trial` (a `FusionTrial`); throws the library's
 * message when the settings do not run.
 *
 * @param {import('estlab-wasm/estlab_wasm.js').FusionTrial} trial
 * @param {import('../types/FusionSettings').FusionSettings} settings
 * @returns {FusionView}
 */
export function runFilter(trial, settings) {
  const run = trial.run(JSON.stringify(settings));
  try {
    const t = trial.t();
    const truth = [0, 1, 2].map((c) => trial.truth(c));
    const estimate = [0, 1, 2].map((c) => run.estimate(c));
    const error = [0, 1, 2].map((c) => estimate[c].map((v, k) => (c === 2 ? wrap(v - truth[c][k]) : v - truth[c][k])));
    const intensity = trial.intensity();
    const ellipseEvery = ellipseSpacing(t.length);
    return {
      t,
      timed: !t.every((time, k) => time === k),
      truth,
      odometry: [0, 1, 2].map((c) => trial.odometry(c)),
      estimate,
      std: [0, 1, 2].map((c) => run.std(c)),
      error,
      measurement: [0, 1, 2].map((c) => run.measurement(c)),
      use: run.readingUse(),
      intensity,
      platforms: intensity.some(Number.isFinite),
      report: trial.hasReport() ? [0, 1, 2].map((c) => trial.report(c)) : null,
      ellipses: outlines(run.ellipses(ellipseEvery, 3, 36)),
      ellipseEvery,
      summary: JSON.parse(run.summary()),
    };
  } finally {
    run.free();
  }
}

/** The mean position error of the filter with `settings` over `trial`. */
export function meanError(trial, settings) {
  const run = trial.run(JSON.stringify(settings));
  try {
    /** @type {FusionSummary} */
    const summary = JSON.parse(run.summary());
    return summary.filter.mean;
  } finally {
    run.free();
  }
}
