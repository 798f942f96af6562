// The fusion page's tables: the position errors of the filter, of odometry, of the sensor
// alone and of the report's own estimate (beside the figures the report published for its
// trials), and what became of the readings with the filter's consistency.
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { row } from '../odometry/view.js';

/** @typedef {import('../types/FusionSummary').FusionSummary} FusionSummary */
/** @typedef {import('../types/PositionErrors').PositionErrors} PositionErrors */
/** @typedef {import('../types/ReportFigures').ReportFigures} ReportFigures */

const f = (v) => fmt(v, 3);
const percent = (share) => `${fmt(100 * share, 4)} %`;

/** The share of steps a consistent filter has with the truth inside its 3σ ellipse: 1 - e^(-9/2). */
const gaussianInside = 1 - Math.exp(-4.5);

/**
 * Fills the errors table with `summary`'s figures; `published`, on one of the report's
 * trials, is what the report published for it (its own Kalman filter's mean error,
 * odometry's and the sensor's alone), which goes beside them.
 *
 * @param {FusionSummary} summary
 * @param {ReportFigures} [published]
 */
export function showErrors(summary, published) {
  const figures = published
    ? { report: published.kalman, odometry: published.odometry, sensor: published.sensor }
    : undefined;
  byId('published-heading').hidden = !figures;
  /** @type {[string, string, PositionErrors | null][]} */
  const rows = [
    ['filter', 'the filter', summary.filter],
    ['odometry', 'odometry alone', summary.odometry],
    ['sensor', 'the sensor alone', summary.sensor],
  ];
  if (summary.report) rows.push(['report', "the report's own filter", summary.report]);
  const body = byId('errors-table', HTMLTableElement).tBodies[0];
  body.replaceChildren(...rows.map(([id, heading, errors]) => {
    const cells = errors
      ? [[f(errors.mean), errors.mean], [f(errors.rms), errors.rms], [f(errors.max), errors.max], [String(errors.steps), errors.steps]]
      : [['no readings', null], ['', null], ['', null], ['0', 0]];
    if (figures) {
      const value = figures[id];
      cells.push(value === undefined ? ['', null] : [f(value), value]);
    }
    return row(heading, cells, id);
  }));
}

/**
 * Fills the table of the readings and the filter's consistency with `summary`'s figures.
 *
 * @param {FusionSummary} summary
 */
export function showReadings(summary) {
  const body = byId('readings-table', HTMLTableElement).tBodies[0];
  const read = summary.used + summary.outside_view + summary.gated;
  const share = (n) => (read ? ` (${fmt((100 * n) / read, 3)} %)` : '');
  body.replaceChildren(
    row('steps with the truth inside the filter\'s 3σ ellipse', [
      [`${percent(summary.inside_three_sigma)}, where a consistent filter has ${percent(gaussianInside)}`, summary.inside_three_sigma],
    ], 'inside'),
    row('readings used', [[`${summary.used}${share(summary.used)}`, summary.used]], 'used'),
    row('outside the field of view', [[`${summary.outside_view}${share(summary.outside_view)}`, summary.outside_view]], 'outside_view'),
    row('rejected by the gate', [[`${summary.gated}${share(summary.gated)}`, summary.gated]], 'gated'),
  );
}

/** The caption of the errors table, naming the trial. */
export function captionErrors(subject) {
  setText(byId('errors-table', HTMLTableElement).caption, `Position error against the ground truth on ${subject}`);
}
