// The MRCLAM page's tables, a column each: the filters' (and dead reckoning's) errors,
// consistency, readings and time; the noise learned from the recording beside the noise
// the filters use (and, on a generated data set, the true noise).
import { setText } from '../controls.js';
import { fmt } from '../format.js';

/** @typedef {import('./plots.js').FilterView} FilterView */
/** @typedef {import('../types/MrclamNoise').MrclamNoise} MrclamNoise */

const f = (v) => fmt(v, 3);
const degrees = 180 / Math.PI;

/** Fills the body of `table` with a row for each of `rows`: its header, then its cells. */
function fill(table, rows) {
  const body = table.tBodies[0];
  body.replaceChildren(...rows.map(([header, cells]) => {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    th.scope = 'row';
    th.textContent = header;
    tr.append(th);
    for (const cell of cells) {
      const td = document.createElement('td');
      td.textContent = cell;
      tr.append(td);
    }
    return tr;
  }));
}

/**
 * The filters' table: a column a filter, and dead reckoning's.
 *
 * @param {HTMLTableElement} table
 * @param {FilterView[]} views
 * @param {import('../types/PositionErrors').PositionErrors} drift dead reckoning's errors
 */
export function showFilters(table, views, drift) {
  const each = (cell) => views.map((v) => cell(v.summary.consistency, v.summary.readings, v));
  fill(table, [
    ['RMS error (m)', [...each((c) => f(c.errors.rms)), f(drift.rms)]],
    ['mean error (m)', [...each((c) => f(c.errors.mean)), f(drift.mean)]],
    ['largest error (m)', [...each((c) => f(c.errors.max)), f(drift.max)]],
    ['NEES (3 if consistent)', [...each((c) => fmt(c.nees, 3)), '']],
    ['truth in 3σ (98.9 % if consistent)', [...each((c) => `${fmt(100 * c.inside_three_sigma, 3)} %`), '']],
    ['readings used', [...each((_, r) => String(r.used)), '']],
    ['readings rejected', [...each((_, r) => String(r.rejected)), '']],
    ['time in this browser (ms)', [...each((_, __, v) => fmt(v.ms, 3)), '']],
  ]);
}

/**
 * The noise table: a column for `learned`, one for what the filters use (`rho` times its
 * R2), and one for `truth` where the data set was generated.
 *
 * @param {HTMLTableElement} table
 * @param {MrclamNoise} learned
 * @param {number} rho
 * @param {MrclamNoise | null} truth
 */
export function showNoise(table, learned, rho, truth) {
  /** @type {[MrclamNoise, number][]} */
  const columns = [[learned, 1], [learned, rho], ...(truth ? [/** @type {[MrclamNoise, number]} */ ([truth, 1])] : [])];
  // R2 comes column by column: [range², cross, cross, bearing²].
  fill(table, [
    ...[0, 1, 2, 3].map((i) => [`α${'₁₂₃₄'[i]}`, columns.map(([noise]) => fmt(noise.alphas[i], 3))]),
    ['range σ (m)', columns.map(([noise, scale]) => f(Math.sqrt(scale * noise.measurement[0])))],
    ['bearing σ (°)', columns.map(([noise, scale]) => f(Math.sqrt(scale * noise.measurement[3]) * degrees))],
  ]);
  setText(table.querySelector('#used-heading'), `used by the filters (R₂ × ρ = ${fmt(rho, 3)})`);
  /** @type {HTMLElement} */ (table.querySelector('#true-heading')).hidden = !truth;
}
