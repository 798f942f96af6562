// The fusion page's errors over time: the filter's error in x, y and θ against the
// ground truth, inside the ±3σ its own covariance claims.
import { fmt } from '../format.js';
import { band, colours, overTime, stats, timeLine } from '../plots.js';

/** @typedef {import('./run.js').FusionView} FusionView */

const f = (v) => fmt(v, 3);

/** The plots, by name, with the component they show and its unit. */
const components = [
  ['error-x', 'x', 'm'],
  ['error-y', 'y', 'm'],
  ['error-theta', 'θ', 'rad'],
];

/**
 * A plot over the steps of `v`: over time where the trial has times, else over the
 * rows' numbers.
 */
function overSteps(v, yName, series) {
  if (v.timed) return overTime(yName, series);
  const option = overTime(yName, series, {}, { name: 'step k' });
  return {
    ...option,
    tooltip: {
      trigger: 'axis',
      formatter: (items) => {
        const shown = items.filter((item) => !String(item.seriesId).startsWith('band '));
        return shown.length
          ? [`step ${fmt(shown[0].value[0])}`, ...shown.map((item) => `${item.marker}${item.seriesName}: ${fmt(item.value[1])}`)].join('<br>')
          : '';
      },
    },
  };
}

/**
 * Draws the errors of run `v` on the page's plots (`plotsIn`'s, of which it draws
 * `error-x`, `error-y` and `error-theta`), each with a summary line.
 *
 * @param {FusionView} v
 */
export function drawErrors(plots, v) {
  const n = v.t.length;
  const when = (k) => (v.timed ? `t = ${f(v.t[k])} s` : `step ${k}`);
  components.forEach(([name, component, unit], c) => {
    const bound = v.std[c].map((s) => 3 * s);
    plots[name].set(overSteps(v, `error in ${component} (${unit})`, [
      ...band('±3σ', v.t, bound.map((b) => -b), bound, colours.band),
      timeLine('error', v.t, v.error[c], colours.estimate, { name: 'filter − truth' }),
    ]));
    const s = stats(v.error[c]);
    let inside = 0;
    for (let k = 0; k < n; k++) if (Math.abs(v.error[c][k]) <= bound[k]) inside++;
    plots[name].describe(
      `The filter's error in ${component} over ${n} steps: mean ${f(s.mean)} ${unit}, mean absolute ${f(s.meanAbs)} ${unit}, ` +
      `largest ${f(s.maxAbs)} ${unit} in size at ${when(s.maxAbsAt)}; within its ±3σ at ${f((100 * inside) / n)} % of the steps ` +
      `(3σ at the end: ${f(bound[n - 1])} ${unit}).`);
  });
}
