// The workbench's view of the UKF and particle filter runs (the workbench,
// static/src/pages/code.js, loads this view of the exercise's runs): the student's
// filter's path drawn over the reference filter's, with the truth and the posts the
// robot read (all from the wasm build of the plan); how far the student's belief is from
// the reference's at every step, a summary in words and a table of the step where the run
// departs (`estlab/workbench/beliefs.js`); and a link to the page of the filters on the
// real data set.
import { byId, setText } from 'estlab/controls.js';
import { fmt } from 'estlab/format.js';
import { colours, dashes, line, markers, overTime, pairs, plane, plotsIn, styled } from 'estlab/plots.js';
import { link } from 'estlab/results/render.js';
import {
  describeDifferences, differenceSeries, differences, f, fillBeliefTable, poseAt,
} from 'estlab/workbench/beliefs.js';

/** @typedef {import('estlab-wasm/estlab_wasm.js').Grader} Grader */
/** @typedef {import('estlab/types/RunPhase').RunPhase & import('estlab/types/UkfParticleRun').UkfParticleRun} FilterPhase */
/** @typedef {import('estlab/types/RunOutput').RunOutput} RunOutput */

const degrees = Math.PI / 180;

/**
 * The run of `phase`: its times, truth and posts, the reference filter's belief and the
 * student's as far as their run `output` got, taken out of wasm at once; throws when the
 * output does not read or holds no step (the run's test says why).
 *
 * @param {Grader} grader
 * @param {FilterPhase} phase
 * @param {RunOutput} output
 */
function collectRun(grader, phase, output) {
  const view = grader.filterRun(JSON.stringify(output));
  try {
    const belief = (pose, std) => ({ pose, std, steps: pose[0].length });
    const reference = belief([0, 1, 2].map((i) => view.reference(i)), [0, 1, 2].map((i) => view.referenceStd(i)));
    const student = belief([0, 1, 2].map((i) => view.student(i)), [0, 1, 2].map((i) => view.studentStd(i)));
    const posts = view.posts();
    return {
      phase,
      particle: view.particle,
      t: view.t(),
      truth: [0, 1].map((i) => view.truth(i)),
      posts: pairs(posts.filter((_, i) => i % 2 === 0), posts.filter((_, i) => i % 2 === 1)),
      reference,
      student,
      difference: differences(student, reference),
      departure: view.departure ?? null,
    };
  } finally {
    view.free();
  }
}

/** @typedef {ReturnType<typeof collectRun>} Shown */

/** The filter a run strings the student's functions into, in words. */
const filterName = (v) => (v.particle ? 'particle filter' : 'UKF');

/** The summary line: whether the run follows the reference's belief, where it departs or stopped. */
function summaryText(v) {
  const { t, reference: r, student: s, departure } = v;
  const steps = r.steps;
  const name = filterName(v);
  const stopped = s.steps < steps
    ? ` Your run stopped after step ${s.steps} of ${steps} (its test says why).`
    : '';
  if (departure !== null) {
    const k = departure - 1;
    const [rx, ry, rtheta] = poseAt(r, k);
    const [sx, sy, stheta] = poseAt(s, k);
    const dtheta = Math.atan2(Math.sin(stheta - rtheta), Math.cos(stheta - rtheta));
    return `Your ${name} departs from the reference ${name}'s belief at step ${departure} of ${steps} (t = ${f(t[k], 4)} s): ` +
      `there your position is ${f(Math.hypot(sx - rx, sy - ry))} m from the reference's and your heading ` +
      `${f(dtheta / degrees)}° off.${stopped}`;
  }
  if (stopped) return `Your ${name} follows the reference ${name}'s belief as far as it got.${stopped}`;
  const last = steps - 1;
  const [tx, ty] = [v.truth[0][last], v.truth[1][last]];
  const [sx, sy] = poseAt(s, last);
  return `Your ${name} follows the reference ${name}'s belief at all ${steps} steps; at the end it is ` +
    `${f(Math.hypot(sx - tx, sy - ty))} m from the truth.`;
}

/** The path plot's summary line: what it draws, and where the paths end. */
function describePath(v) {
  const { phase, reference: r, student: s } = v;
  const k = s.steps - 1;
  const [rx, ry] = poseAt(r, k);
  const [sx, sy] = poseAt(s, k);
  return `The ${phase.name} run: the truth (black, dotted), the reference ${filterName(v)}'s path (green, solid) and yours ` +
    `(red, dashed), and the ${v.posts.length} posts the robot read. After step ${k + 1}, the reference is at ` +
    `(${f(rx)}, ${f(ry)}) m and yours ${f(Math.hypot(sx - rx, sy - ry))} m from it.`;
}

/** What the grader runs, and a link to the page of the three filters on the real data. */
function runNote({ phase, particle }) {
  const steps = phase.steps.length;
  const what = particle
    ? `a particle filter of ${phase.particles?.length ?? 0} particles, every random number given`
    : 'a UKF, the gate at chi2inv(0.999, 2)';
  return [
    `Grading strings your functions into ${what}, over this run: ${steps} steps of ${fmt(phase.dt)} s of a generated robot, ` +
      `the camera's noise learned first from ${phase.residuals.length} residuals and the alphas from ${phase.commanded.length} ` +
      'commands; your belief must follow the reference ' +
      'filter\'s at the start and after every step. Run the three filters on the real robots of MRCLAM, and tune them, on ',
    link('/mrclam', 'the EKF, UKF and particle filter page'), '.',
  ];
}

/** The series of the path plot. */
function pathSeries(v) {
  const { truth, posts, reference: r, student: s, departure } = v;
  const at = (belief, k) => [poseAt(belief, k).slice(0, 2)];
  return [
    styled(line('truth', truth[0], truth[1], colours.landmark, { name: 'the truth (dotted)', z: 1 }), dashes.odometry, 1.5),
    markers('posts', 'the posts read', posts, colours.measurement, 'rect', 9, 1),
    styled(line('reference', r.pose[0], r.pose[1], colours.truth, { name: "the reference filter's path (solid)", z: 2 }), dashes.truth, 2),
    styled(line('yours', s.pose[0], s.pose[1], colours.estimate, { name: 'your path (dashed)', z: 3 }), dashes.estimate, 2),
    markers('start', 'start', at(r, 0), colours.truth, 'triangle', 11),
    ...(departure === null ? [] : [markers('departure', 'where yours departs', at(s, departure - 1), colours.estimate, 'diamond', 12, 9)]),
  ];
}

/** The runs section (the markup of `web/run_view.html` in `root`) showing one run at a time. */
class FilterRunView {
  /** @param {HTMLElement} root */
  constructor(root) {
    const plots = plotsIn(root, 'code');
    this.path = plots['filter-path'];
    this.difference = plots['filter-difference'];
    /** @type {Shown | null} */
    this.view = null;
    // The axes keep a metre as long on x as on y: a new size of the window needs new ones.
    window.addEventListener('resize', () => {
      if (this.view) this.draw();
    });
  }

  /** @param {Shown} v */
  show(v) {
    this.view = v;
    this.draw();
    this.path.describe(describePath(v));
    this.difference.set(overTime('difference from the reference', differenceSeries(v), { type: 'log', scale: false }));
    this.difference.describe(describeDifferences(v));
    this.difference.setMarker(v.departure === null ? null : v.t[v.departure - 1], 'where your run departs');
    setText(byId('filter-summary'), summaryText(v));
    fillBeliefTable(byId('filter-table', HTMLTableElement), v);
    byId('prefix').replaceChildren(...runNote(v));
  }

  draw() {
    const v = this.view;
    const { truth, posts, reference: r, student: s } = v;
    const px = posts.map((p) => p[0]);
    const py = posts.map((p) => p[1]);
    this.path.set(plane(this.path, pathSeries(v), [truth[0], r.pose[0], s.pose[0], px], [truth[1], r.pose[1], s.pose[1], py]));
  }
}

/**
 * The workbench's runs of the UKF and the particle filter: each one's views from the
 * harness's output, and where they are drawn.
 *
 * @type {import('estlab/workbench/running.js').ExerciseRuns<Shown>}
 */
export const runs = { collect: collectRun, View: FilterRunView };
