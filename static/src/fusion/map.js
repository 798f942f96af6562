// The fusion page's map: the room seen from above, with the true path, the odometry's,
// the filter's with its 3σ ellipses, the report's own estimate where the trial has it,
// the sensor's readings (by the intensity they were read with, where it is known), those
// the gate rejected, and the field of view round the point under the detector.
import { fmt } from '../format.js';
import { colours, dashes, line, markers, outlineSeries, outlineXY, plane, styled } from '../plots.js';
import { readingUse } from './run.js';

/** @typedef {import('./run.js').FusionView} FusionView */

const f = (v) => fmt(v, 3);

/**
 * The classes of readings by the weaker platform's intensity: the brighter, the less
 * noisy (σ = c_xy / I). Told apart by shape as well as by shade.
 */
const intensityClasses = [
  { id: 'readings bright', name: 'readings, intensity 1500 or more (dark circles)', from: 1500, to: Infinity, colour: '#004d40', symbol: 'circle' },
  { id: 'readings middling', name: 'readings, intensity 500 to 1500 (squares)', from: 500, to: 1500, colour: '#26a69a', symbol: 'rect' },
  { id: 'readings faint', name: 'readings, intensity below 500 (light triangles)', from: -Infinity, to: 500, colour: '#80cbc4', symbol: 'triangle' },
];

/**
 * The positions [x, y] of the steps `k` for which `keep(k)` holds, of a path's
 * components (x first, then y).
 *
 * @param {ArrayLike<number>[]} path
 * @param {(k: number) => boolean} keep
 */
export function positions(path, keep) {
  const [xs, ys] = path;
  const out = [];
  for (let k = 0; k < xs.length; k++) if (keep(k)) out.push([xs[k], ys[k]]);
  return out;
}

/** A circle of `radius` round the origin, as an outline. */
export function circle(radius, segments = 96) {
  const coords = [];
  for (let i = 0; i <= segments; i++) {
    const a = (2 * Math.PI * i) / segments;
    coords.push([radius * Math.cos(a), radius * Math.sin(a)]);
  }
  return [{ coords }];
}

/**
 * The series of the readings: by intensity class where it is known, else all alike (the
 * others empty: the map always has the same series, as a series left out would leave a
 * hole in the chart's option).
 */
function readingSeries(v) {
  const read = (k) => v.use[k] !== readingUse.none;
  return [
    markers('readings', 'readings of the sensor (grey dots)', v.platforms ? [] : positions(v.measurement, read), colours.measurement, 'circle', 5, 3),
    ...intensityClasses.map(({ id, name, from, to, colour, symbol }) => markers(id, name,
      v.platforms ? positions(v.measurement, (k) => read(k) && v.intensity[k] >= from && v.intensity[k] < to) : [], colour, symbol, 5, 3)),
  ];
}

/**
 * Draws run `v` on `plot` with the field of view `fieldOfView` (metres); `subject`
 * names the trial in the summary line.
 *
 * @param {import('../plots.js').Plot} plot
 * @param {FusionView} v
 * @param {number} fieldOfView
 * @param {string} subject
 */
export function drawMap(plot, v, fieldOfView, subject) {
  const view = circle(fieldOfView);
  const gated = positions(v.measurement, (k) => v.use[k] === readingUse.gated);
  const [ex, ey] = outlineXY(v.ellipses);
  const series = [
    outlineSeries('field of view', `field of view, ${fmt(fieldOfView)} m (grey, dashed)`, view, '#5f6b76', 1, 0.9, 1, 'dashed'),
    ...readingSeries(v),
    styled(line('truth', v.truth[0], v.truth[1], colours.truth, { name: 'the true path (solid)', z: 4 }), dashes.truth, 2),
    styled(line('odometry', v.odometry[0], v.odometry[1], colours.odometry, { name: 'odometry (dotted)', z: 4 }), dashes.odometry, 2),
    styled(line('report', v.report?.[0] ?? [], v.report?.[1] ?? [], colours.second, { name: "the report's estimate (purple, dash-dotted)", z: 5 }), [8, 3, 2, 3], 1.5),
    styled(line('estimate', v.estimate[0], v.estimate[1], colours.estimate, { name: 'the filter (dashed)', z: 6 }), dashes.estimate, 1.5),
    outlineSeries('ellipses', `3σ ellipses, every ${v.ellipseEvery} steps`, v.ellipses, colours.estimate, 1, 0.7, 6),
    markers('gated', 'rejected by the gate (orange diamonds)', gated, colours.outlier, 'emptyDiamond', 10, 7),
    markers('start', 'start', [[v.truth[0][0], v.truth[1][0]]], colours.truth, 'triangle', 11, 8),
  ];
  // The axes hold the paths, the ellipses and the field of view; a garbage reading far
  // outside it would shrink the room to a corner.
  const paths = [v.truth, v.odometry, v.estimate, ...(v.report ? [v.report] : [])];
  const [cx, cy] = outlineXY(view);
  // The legend lists what there is: not the readings' classes of another kind of trial, nor a report's estimate the trial lacks.
  const listed = series.filter((s) => s.data.length).map((s) => s.name);
  plot.set(plane(plot, series, [...paths.map((p) => p[0]), ex, cx], [...paths.map((p) => p[1]), ey, cy], listed));
  plot.describe(describeMap(v, fieldOfView, subject));
}

/** How many of `use` are `kind`. */
const count = (use, kind) => use.reduce((n, u) => n + (u === kind ? 1 : 0), 0);

/** The map's summary line. */
function describeMap(v, fieldOfView, subject) {
  const n = v.t.length;
  const last = n - 1;
  const s = v.summary;
  const distance = (path, k) => Math.hypot(path[0][k] - v.truth[0][k], path[1][k] - v.truth[1][k]);
  const span = v.timed ? `${n} steps over ${f(v.t[last] - v.t[0])} s` : `${n} steps`;
  const readings = n - count(v.use, readingUse.none);
  let classes = '';
  if (v.platforms) {
    classes = ' (' + intensityClasses.map(({ from, to }) => {
      let inClass = 0;
      for (let k = 0; k < n; k++) if (v.use[k] !== readingUse.none && v.intensity[k] >= from && v.intensity[k] < to) inClass++;
      return `${inClass} ${to === Infinity ? `at intensity ${from} or more` : from === -Infinity ? `below ${to}` : `from ${from} to ${to}`}`;
    }).join(', ') + ')';
  }
  return `The room of ${subject}: ${span}. The true path (green, solid) from (${f(v.truth[0][0])}, ${f(v.truth[1][0])}) ` +
    `to (${f(v.truth[0][last])}, ${f(v.truth[1][last])}) m; the filter (red, dashed) ${f(s.filter.mean)} m from it on average, ` +
    `at most ${f(s.filter.max)} m, with 3σ ellipses every ${v.ellipseEvery} steps (${v.ellipses.length} of them); ` +
    `the odometry (blue, dotted) ends ${f(distance(v.odometry, last))} m from the truth` +
    (v.report ? `; the report's estimate (purple) ${f(s.report.mean)} m from it on average` : '') +
    `. ${readings} readings${classes}: ${s.used} used, ${s.outside_view} outside the field of view ` +
    `(the grey circle of radius ${fmt(fieldOfView)} m round the point under the detector), ${s.gated} rejected by the gate (orange diamonds).`;
}
