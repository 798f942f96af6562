// The odometry workbench's runs along the grader's paths (the workbench,
// static/src/pages/code.js, loads this view of the exercise's runs): the
// poses and 3σ ellipses the student's functions propagated, drawn over the reference's
// (both from the wasm build of the plan), a summary line in words and a table of the last
// step, and a link to the odometry page.
import { byId, setText } from 'estlab/controls.js';
import { fmt } from 'estlab/format.js';
import {
  colours, dashes, ellipseAxes, ellipseSpacing, line, markers, outlineSeries, outlineXY, outlines, plane, plotsIn, styled,
} from 'estlab/plots.js';
import { fillHeadedRows, link } from 'estlab/results/render.js';

const degrees = Math.PI / 180;
/** A pose's number (metres, radians, degrees) with `digits` significant digits, and 0 for what is zero but for rounding. */
const f = (v, digits = 3) => fmt(Math.abs(v) < 1e-12 ? 0 : v, digits);

/** The covariance entries the table shows: [label, row, column]. */
const entries = [
  ['Σxx (m²)', 0, 0],
  ['Σxy (m²)', 0, 1],
  ['Σyy (m²)', 1, 1],
  ['Σxθ (m rad)', 0, 2],
  ['Σyθ (m rad)', 1, 2],
  ['Σθθ (rad²)', 2, 2],
];

/**
 * What the views need of a path's poses and covariances (an `OdometryPropagation`): the
 * pose and the covariance at every step, and the 3σ ellipses every `every` steps and at
 * the last.
 */
function pathOf(propagation, every) {
  const steps = propagation.steps();
  return {
    steps,
    pose: [0, 1, 2].map((i) => propagation.pose(i)),
    covariance: entries.map(([, i, j]) => propagation.covariance(i, j)),
    ellipses: [...outlines(propagation.ellipses(every, 3, 48)), ...outlines(propagation.ellipse(steps, 3, 48))],
  };
}

/**
 * The reference's path of `phase` and the student's as far as their run `output` got,
 * taken out of wasm at once; throws when the output does not read (the run's test says
 * why).
 */
function collectRun(grader, phase, output) {
  const reference = grader.referencePath(phase.name);
  let student;
  try {
    student = grader.studentPath(JSON.stringify(output));
    const every = ellipseSpacing(reference.steps());
    return { phase, every, reference: pathOf(reference, every), student: pathOf(student, every) };
  } finally {
    reference.free();
    student?.free();
  }
}

/** The pose at step `k` of a path: [x, y, theta]. */
const poseAt = (path, k) => path.pose.map((component) => component[k]);

/** The size of the 3σ ellipse at step `k` of a path, in words. */
function ellipseWords(path, k) {
  const [xx, xy, yy] = path.covariance;
  const { major, minor } = ellipseAxes(xx[k], xy[k], yy[k]);
  return `${f(2 * major)} m by ${f(2 * minor)} m across`;
}

/** The wrapped difference of two headings, in [-pi, pi). */
const headingDifference = (a, b) => a - b - 2 * Math.PI * Math.floor((a - b + Math.PI) / (2 * Math.PI));

/** The plot's summary line: where both paths go, where the student's ends, and the ellipses. */
function describe(v) {
  const { phase, every, reference: r, student: s } = v;
  const k = s.steps;
  const [x0, y0] = poseAt(r, 0);
  const [rx, ry, rtheta] = poseAt(r, k);
  const [sx, sy, stheta] = poseAt(s, k);
  const reach = k < r.steps
    ? `Your run stopped after ${k} of its ${r.steps} steps (its test says why). There, the reference is at (${f(rx)}, ${f(ry)}) m`
    : `The reference ends at (${f(rx)}, ${f(ry)}) m, heading ${f(rtheta / degrees)}°`;
  return `The ${phase.name} path from (${f(x0)}, ${f(y0)}) m: the reference's poses (green, solid) and yours (red, dashed). ` +
    `${reach}; yours is ${f(Math.hypot(sx - rx, sy - ry))} m from it, its heading ${f(headingDifference(stheta, rtheta) / degrees)}° off. ` +
    `3σ ellipses every ${every} steps; after step ${k} the reference's is ${ellipseWords(r, k)}, yours ${ellipseWords(s, k)}.`;
}

/** The last step the student's run reported, theirs beside the reference's, in the table's rows. */
function fillTable(table, v) {
  const { reference: r, student: s } = v;
  const k = s.steps;
  setText(table.caption, `After step ${k} of ${r.steps}, the last your run reported`);
  const [rp, sp] = [poseAt(r, k), poseAt(s, k)];
  const rows = [
    ['x (m)', f(sp[0], 8), f(rp[0], 8)],
    ['y (m)', f(sp[1], 8), f(rp[1], 8)],
    ['θ (°)', f(sp[2] / degrees, 8), f(rp[2] / degrees, 8)],
    ...entries.map(([label], e) => [label, fmt(s.covariance[e][k], 6), fmt(r.covariance[e][k], 6)]),
  ];
  fillHeadedRows(table, rows);
}

/**
 * What the grader drives along the path, and a link to the odometry page, where such paths
 * run with the reference model.
 */
function pathNote({ phase }) {
  const start = phase.start.map((v) => fmt(v, 4)).join(', ');
  return [
    `Grading drives your functions along this path: ${phase.steps.length} steps from the pose (${start}), known exactly ` +
      `(Σp = 0), with the wheel base b = ${fmt(phase.b)} m and k_r = ${fmt(phase.k_r)} m, k_l = ${fmt(phase.k_l)} m; ` +
      'the pose and its covariance must follow the reference\'s after every step. See how odometry\'s error grows along such paths on ',
    link('/odometry', 'the odometry page'), '.',
  ];
}

/** The series of the path plot: the reference's path and ellipses, and the student's over them. */
function pathSeries({ every, reference: r, student: s }) {
  /** The position at step `k` of a path, as a marker's data. */
  const at = (path, k) => [poseAt(path, k).slice(0, 2)];
  return [
    styled(line('reference', r.pose[0], r.pose[1], colours.truth, { name: "the reference's path (solid)", z: 2 }), dashes.truth, 2),
    outlineSeries('reference ellipses', `the reference's 3σ ellipses, every ${every} steps`, r.ellipses, colours.truth, 1.5, 0.7, 2),
    styled(line('yours', s.pose[0], s.pose[1], colours.estimate, { name: 'your path (dashed)', z: 3 }), dashes.estimate, 2),
    outlineSeries('your ellipses', 'your 3σ ellipses (dashed)', s.ellipses, colours.estimate, 1, 0.9, 4, 'dashed'),
    markers('start', 'start', at(r, 0), colours.truth, 'triangle', 11),
    markers('reference end', "the reference's end", at(r, r.steps), colours.truth, 'circle', 9),
    markers('your end', 'your end', at(s, s.steps), colours.estimate, 'circle', 7, 9),
  ];
}

/** The runs section (the markup of `web/run_view.html` in `root`) showing one path run at a time. */
class PathRunView {
  constructor(root) {
    this.plot = plotsIn(root, 'code').path;
    this.view = null;
    // The axes keep a metre as long on x as on y: a new size of the window needs new ones.
    window.addEventListener('resize', () => {
      if (this.view) this.draw();
    });
  }

  show(v) {
    this.view = v;
    this.draw();
    this.plot.describe(describe(v));
    fillTable(byId('path-table'), v);
    byId('prefix').replaceChildren(...pathNote(v));
  }

  draw() {
    const { reference: r, student: s } = this.view;
    const [rx, ry] = outlineXY(r.ellipses);
    const [sx, sy] = outlineXY(s.ellipses);
    this.plot.set(plane(this.plot, pathSeries(this.view), [r.pose[0], s.pose[0], rx, sx], [r.pose[1], s.pose[1], ry, sy]));
  }
}

/**
 * The odometry workbench's runs: each one's views from the harness's output, and where they are drawn.
 *
 * @type {import('estlab/workbench/running.js').ExerciseRuns<ReturnType<typeof collectRun>>}
 */
export const runs = { collect: collectRun, View: PathRunView };
