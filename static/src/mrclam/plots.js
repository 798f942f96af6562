// The MRCLAM page's plots: the room with the three filters' paths; a close-up round the
// truth at the chosen step, with the particle cloud, the sigma points and each filter's
// 3σ ellipse; each filter's error in x inside its own
// ±3σ; the NEES of the three over time. The longest stretch without a post in sight is
// shaded on the plots over time.
import { fmt } from '../format.js';
import { band, colours, dashes, line, markers, overTime, plane, stats, styled, timeLine } from '../plots.js';

/** @typedef {import('../types/MrclamFilter').MrclamFilter} MrclamFilter */

/**
 * A filter's run as the page holds it: its kind and name, the series out of wasm, its
 * summary and time.
 *
 * @typedef {{
 *   kind: MrclamFilter, name: string, x: Float64Array, y: Float64Array, sx: Float64Array, inside: Uint8Array,
 *   errorX: Float64Array, nees: Float64Array, snapshots: Float64Array,
 *   samples: (i: number) => Float64Array, ellipse: (k: number) => Float64Array,
 *   summary: { consistency: import('../types/MrclamConsistency').MrclamConsistency,
 *              readings: import('../types/MrclamReadings').MrclamReadings },
 *   ms: number, free: () => void,
 * }} FilterView
 */

/**
 * The robot as the page holds it.
 *
 * @typedef {{ t: Float64Array, truth: Float64Array[], posts: Float64Array, blind: Float64Array, subject: string }} RobotView
 */

const f = (v) => fmt(v, 3);
/** A filled X, the sigma points' symbol. */
const CROSS = 'path://M0,2L2,0L5,3L8,0L10,2L7,5L10,8L8,10L5,7L2,10L0,8L3,5Z';

/** How each filter is drawn: colour, line style, and the words the legends use. */
export const looks = {
  ekf: { colour: colours.estimate, dash: dashes.estimate, words: 'red, dashed' },
  ukf: { colour: colours.second, dash: dashes.odometry, words: 'purple, dotted' },
  particle: { colour: colours.third, dash: [8, 3, 2, 3], words: 'teal, dash-dotted' },
};

/** Every `every`-th of `xs`, paired with `ys`'s: a path thinned to what a map can show. */
function thinned(xs, ys, every) {
  const out = [];
  for (let k = 0; k < xs.length; k += every) out.push([xs[k], ys[k]]);
  out.push([xs[xs.length - 1], ys[ys.length - 1]]);
  return out;
}

/** x, y pairs of a flat [x, y, x, y, ...] array. */
function points(flat) {
  const out = [];
  for (let i = 0; i + 1 < flat.length; i += 2) out.push([flat[i], flat[i + 1]]);
  return out;
}

/**
 * Draws the room: posts, the true path, the filters' paths, and at snapshot `i` the
 * particle filter's particles, the UKF's sigma points and where each filter and the truth
 * are.
 *
 * @param {import('../plots.js').Plot} plot
 * @param {RobotView} robot
 * @param {FilterView[]} views
 * @param {number} i
 */
export function drawMap(plot, robot, views, i) {
  const every = Math.max(1, Math.floor(robot.t.length / 3000));
  const k = views[0].snapshots[i];
  const particle = views.find((v) => v.kind === 'particle');
  const ukf = views.find((v) => v.kind === 'ukf');
  const series = [
    markers('posts', 'posts (black squares)', points(robot.posts), colours.landmark, 'rect', 9, 3),
    styled({ ...line('truth', [], [], colours.truth, { name: 'the true path (green, solid)', z: 4 }), data: thinned(robot.truth[0], robot.truth[1], every) }, dashes.truth, 2),
    ...views.map((v) => styled({
      ...line(v.kind, [], [], looks[v.kind].colour, { name: `${v.name} (${looks[v.kind].words})`, z: 5 }),
      data: thinned(v.x, v.y, every),
    }, looks[v.kind].dash, 1.5)),
    markers('particles', `the particles at t = ${fmt(robot.t[k], 4)} s (teal dots)`, particle ? points(particle.samples(i)) : [], looks.particle.colour, 'circle', 3, 6),
    markers('sigma points', `the UKF's sigma points at t = ${fmt(robot.t[k], 4)} s (purple crosses)`, ukf ? points(ukf.samples(i)) : [], looks.ukf.colour, CROSS, 8, 7),
    markers('now', `the truth at t = ${fmt(robot.t[k], 4)} s (green triangle)`, [[robot.truth[0][k], robot.truth[1][k]]], colours.truth, 'triangle', 12, 9),
  ];
  const xs = [robot.truth[0], ...views.map((v) => v.x), robot.posts.filter((_, j) => j % 2 === 0)];
  const ys = [robot.truth[1], ...views.map((v) => v.y), robot.posts.filter((_, j) => j % 2 === 1)];
  const listed = series.filter((s) => s.data.length).map((s) => s.name);
  plot.set(plane(plot, series, xs, ys, listed));
  const when = fmt(robot.t[k], 4);
  const at = views.map((v) => `${v.name} ${f(Math.hypot(v.x[k] - robot.truth[0][k], v.y[k] - robot.truth[1][k]))} m`).join(', ');
  plot.describe(`The room of ${robot.subject}, seen from above: ${robot.posts.length / 2} posts, the true path over ` +
    `${f(robot.t[robot.t.length - 1])} s and the paths of ${views.map((v) => v.name).join(', ')}. ` +
    `At t = ${when} s the filters are this far from the truth: ${at}` +
    (particle ? `; the particle filter's ${particle.samples(i).length / 2} particles are drawn` : '') + '.');
}

/**
 * Draws the close-up round the truth at snapshot `i`: the particles, the sigma points,
 * each filter's mean with its 3σ ellipse, the truth, and the paths through the window.
 *
 * @param {import('../plots.js').Plot} plot
 * @param {RobotView} robot
 * @param {FilterView[]} views
 * @param {number} i
 */
export function drawCloseUp(plot, robot, views, i) {
  const k = views[0].snapshots[i];
  const [cx, cy] = [robot.truth[0][k], robot.truth[1][k]];
  const clouds = views.map((v) => v.samples(i));
  const ellipses = views.map((v) => v.ellipse(k));
  // Wide enough for every ellipse, cloud and mean, and never narrower than 10 cm.
  let half = 0.05;
  for (const flat of [...clouds, ...ellipses]) {
    for (let j = 0; j + 1 < flat.length; j += 2) half = Math.max(half, Math.abs(flat[j] - cx), Math.abs(flat[j + 1] - cy));
  }
  for (const v of views) half = Math.max(half, Math.abs(v.x[k] - cx), Math.abs(v.y[k] - cy));
  half *= 1.1;
  const from = Math.max(0, k - 500);
  const window = (xs) => xs.slice(from, k + 1);
  const series = [
    styled(line('truth', window(robot.truth[0]), window(robot.truth[1]), colours.truth, { name: 'the true path (green, solid)', z: 3 }), dashes.truth, 2),
    ...views.map((v, j) => styled(line(`${v.kind} ellipse`, points(ellipses[j]).map((p) => p[0]), points(ellipses[j]).map((p) => p[1]), looks[v.kind].colour,
      { name: `${v.name}: 3σ ellipse (${looks[v.kind].words})`, z: 5 }), looks[v.kind].dash, 1.5)),
    markers('particles', `particles (teal dots)`, points(clouds[views.findIndex((v) => v.kind === 'particle')] ?? []), looks.particle.colour, 'circle', 3, 4),
    markers('sigma points', `sigma points (purple crosses)`, points(clouds[views.findIndex((v) => v.kind === 'ukf')] ?? []), looks.ukf.colour, CROSS, 9, 6),
    ...views.map((v) => markers(`${v.kind} mean`, `${v.name}: its mean (${v.kind === 'ekf' ? 'red circle' : v.kind === 'ukf' ? 'purple square' : 'teal diamond'})`,
      [[v.x[k], v.y[k]]], looks[v.kind].colour, v.kind === 'ekf' ? 'circle' : v.kind === 'ukf' ? 'rect' : 'diamond', 10, 8)),
    markers('now', 'the truth (green triangle)', [[cx, cy]], colours.truth, 'triangle', 12, 9),
  ];
  const listed = series.filter((s) => s.data.length).map((s) => s.name);
  plot.set(plane(plot, series, [[cx - half, cx + half]], [[cy - half, cy + half]], listed));
  const particle = views.find((v) => v.kind === 'particle');
  plot.describe(`Round the truth at t = ${fmt(robot.t[k], 4)} s, ${f(2 * half)} m across: ` +
    views.map((v) => `${v.name} ${f(Math.hypot(v.x[k] - cx, v.y[k] - cy))} m off, its 3σ ellipse ` +
      `${v.inside[k] ? 'round' : 'not round'} the truth`).join('; ') +
    (particle ? `; ${particle.samples(i).length / 2} particles` : '') + '.');
}

/** The shading of the longest stretch without a post in sight. */
function blindArea(robot) {
  return {
    silent: true,
    itemStyle: { color: 'rgba(96, 96, 96, 0.12)' },
    data: [[{ xAxis: robot.blind[0], name: 'no post in sight' }, { xAxis: robot.blind[1] }]],
    label: { show: false },
  };
}

/**
 * Draws each filter's error in x with its ±3σ on `plots['error-<kind>']` (`plotsIn`'s).
 *
 * @param {RobotView} robot
 * @param {FilterView[]} views
 */
export function drawErrors(plots, robot, views) {
  for (const v of views) {
    const bound = Array.from(v.sx, (s) => 3 * s);
    const n = bound.length;
    let inside = 0;
    for (let k = 0; k < n; k++) if (Math.abs(v.errorX[k]) <= bound[k]) inside++;
    plots[`error-${v.kind}`].set(overTime('error in x (m)', [
      ...band('±3σ', robot.t, bound.map((b) => -b), bound, looks[v.kind].colour),
      timeLine('error', robot.t, v.errorX, looks[v.kind].colour, { name: `${v.name} − truth`, markArea: blindArea(robot) }),
    ]));
    const s = stats(v.errorX, robot.t);
    plots[`error-${v.kind}`].describe(`The ${v.name}'s error in x over ${n} steps: mean absolute ${f(s.meanAbs)} m, ` +
      `largest ${f(s.maxAbs)} m at t = ${f(s.maxAbsAt)} s; within its ±3σ at ${f((100 * inside) / n)} % of the steps. ` +
      `No post is in sight from ${fmt(robot.blind[0], 4)} s to ${fmt(robot.blind[1], 4)} s (shaded).`);
  }
}

/**
 * Draws the three filters' NEES over time, beside 3.
 *
 * @param {import('../plots.js').Plot} plot
 * @param {RobotView} robot
 * @param {FilterView[]} views
 */
export function drawNees(plot, robot, views) {
  const three = Array.from(robot.t, () => 3);
  plot.set(overTime('NEES', [
    ...views.map((v) => styled(timeLine(v.kind, robot.t, v.nees, looks[v.kind].colour, { name: `${v.name} (${looks[v.kind].words})` }), looks[v.kind].dash)),
    styled(timeLine('consistent', robot.t, three, colours.truth, { name: '3, a consistent filter (green)', markArea: blindArea(robot) }), dashes.truth, 1),
  ], { type: 'log', scale: false, min: 0.1 }));
  plot.describe(`The NEES of the pose over time: ${views.map((v) => `${v.name} ${f(v.summary.consistency.nees)} on average`).join(', ')}; ` +
    'a consistent filter averages 3.');
}
