// The sensor-fusion workbench's runs over the grader's trials (the workbench,
// static/src/pages/code.js, loads this view of the exercise's runs): the student's
// filtered path and 3σ ellipses drawn over the reference filter's, with the truth, the
// readings and the field of view (all from the wasm build of the plan); how far the
// student's belief is from the reference's at every step; a summary in words and a
// table of the step where the run departs (or its last: `estlab/workbench/beliefs.js`);
// and a link to the fusion page.
import { byId, setText } from 'estlab/controls.js';
import { fmt } from 'estlab/format.js';
import { circle, positions } from 'estlab/fusion/map.js';
import { wrap } from 'estlab/angles.js';
import { readingUse } from 'estlab/fusion/run.js';
import {
  colours, dashes, ellipseSpacing, line, markers, outlineSeries, outlineXY, outlines, overTime, plane, plotsIn, styled,
} from 'estlab/plots.js';
import { link } from 'estlab/results/render.js';
import {
  describeDifferences, differenceSeries, differences, f, fillBeliefTable, poseAt,
} from 'estlab/workbench/beliefs.js';

/** @typedef {import('estlab-wasm/estlab_wasm.js').Grader} Grader */
/** @typedef {import('estlab-wasm/estlab_wasm.js').FusionRun} FusionRun */
/** @typedef {import('estlab/types/RunPhase').RunPhase & import('estlab/types/TrialRun').TrialRun} TrialPhase */
/** @typedef {import('estlab/types/RunOutput').RunOutput} RunOutput */
/** @typedef {import('estlab/types/FusionSummary').FusionSummary} FusionSummary */

const degrees = Math.PI / 180;

/**
 * A filter's belief along a trial: the pose and its standard deviations at every step,
 * the 3σ ellipses every `every` steps, and its summary against the truth.
 *
 * @param {FusionRun} run
 * @param {number} every
 */
function beliefOf(run, every) {
  /** @type {FusionSummary} */
  const summary = JSON.parse(run.summary());
  const pose = [0, 1, 2].map((i) => run.estimate(i));
  return {
    pose,
    std: [0, 1, 2].map((i) => run.std(i)),
    ellipses: outlines(run.ellipses(every, 3, 48)),
    summary,
    steps: pose[0].length,
  };
}

/**
 * The trial of `phase`, the reference filter's run over it and the student's as far as
 * their run `output` got, taken out of wasm at once; throws when the output does not read
 * or holds no step (the run's test says why).
 *
 * @param {Grader} grader
 * @param {TrialPhase} phase
 * @param {RunOutput} output
 */
function collectRun(grader, phase, output) {
  // The browser runs the graded trials, which carry their settings (only the server's
  // held-out trials ask the student's tuning()).
  const settings = phase.settings;
  if (settings === null) throw new Error(`the trial ${phase.name} has no settings to show`);
  const reported = JSON.stringify(output);
  let trial;
  let reference;
  let student;
  try {
    trial = grader.fusionTrial(phase.name);
    reference = grader.referenceTrial(phase.name);
    student = grader.studentTrial(reported);
    const every = ellipseSpacing(trial.steps());
    const theirs = {
      ...beliefOf(reference, every),
      use: reference.readingUse(),
      measured: [0, 1].map((i) => reference.measurement(i)),
      distance: reference.mahalanobis(),
    };
    const yours = beliefOf(student, every);
    return {
      phase,
      settings,
      every,
      t: trial.t(),
      truth: [0, 1].map((i) => trial.truth(i)),
      reference: theirs,
      student: yours,
      difference: differences(yours, theirs),
      /** The step (from 1) where the student's belief first leaves the reference's, or null. */
      departure: grader.studentDeparture(reported) ?? null,
    };
  } finally {
    trial?.free();
    reference?.free();
    student?.free();
  }
}

/** @typedef {ReturnType<typeof collectRun>} Shown */

/** What became of the reading at step `k` (from 0) in the reference's run, in words. */
function readingWords(reference, k) {
  const d2 = `d² = ${f(reference.distance[k])}`;
  return {
    [readingUse.none]: 'a step without a reading',
    [readingUse.outsideView]: 'whose reading lay outside the field of view',
    [readingUse.gated]: `whose reading the reference's gate rejected (${d2})`,
    [readingUse.used]: `whose reading the reference used (${d2})`,
  }[reference.use[k]];
}

/** The summary line: whether the run follows the reference's belief, where it departs or stopped, and how good it is. */
function summaryText(v) {
  const { t, reference: r, student: s, departure } = v;
  const steps = r.steps;
  const stopped = s.steps < steps
    ? ` Your run stopped after step ${s.steps} of ${steps} (its test says why).`
    : '';
  if (departure !== null) {
    const k = departure - 1;
    const [rx, ry, rtheta] = poseAt(r, k);
    const [sx, sy, stheta] = poseAt(s, k);
    return `Your filter departs from the reference filter's belief at step ${departure} of ${steps} (t = ${f(t[k], 4)} s), ` +
      `${readingWords(r, k)}: there your position is ${f(Math.hypot(sx - rx, sy - ry))} m from the reference's and your heading ` +
      `${f(wrap(stheta - rtheta) / degrees)}° off.${stopped}`;
  }
  if (stopped) return `Your filter follows the reference filter's belief as far as it got.${stopped}`;
  return `Your filter follows the reference filter's belief at all ${steps} steps: its mean distance from the truth is ` +
    `${f(s.summary.filter.mean)} m (the reference's ${f(r.summary.filter.mean)} m), and the true position lies inside its 3σ ` +
    `ellipse at ${f(100 * s.summary.inside_three_sigma)} % of the steps.`;
}

/** The trial plot's summary line: what it draws, and where the two paths end. */
function describeTrial(v) {
  const { phase, settings, every, reference: r, student: s } = v;
  const { used, gated, outside_view: outside } = r.summary;
  const k = s.steps - 1;
  const [rx, ry] = poseAt(r, k);
  const [sx, sy] = poseAt(s, k);
  return `The ${phase.name} trial: the truth (black, dotted), the reference filter's path (green, solid) and yours (red, dashed), ` +
    `with 3σ ellipses every ${every} steps, and the field of view, ${fmt(settings.field_of_view)} m round the detector at (0, 0). ` +
    `The reference used ${used} readings, rejected ${gated} at its gate and ignored ${outside} outside the field of view. ` +
    `After step ${k + 1}, the reference is at (${f(rx)}, ${f(ry)}) m and yours ${f(Math.hypot(sx - rx, sy - ry))} m from it.`;
}

/** What the grader runs over the trial, and a link to the fusion page, where such trials run with the reference filter. */
function trialNote({ phase, settings: s }) {
  return [
    `Grading runs your functions as a filter over this trial: ${phase.steps.length} steps from the odometry's first pose, ` +
      `with k_xy = ${fmt(s.k_xy)}, k_theta = ${fmt(s.k_theta)}, c_xy = ${fmt(s.c_xy)}, a field of view of ` +
      `${fmt(s.field_of_view)} m and the gate at ${fmt(s.lambda)}; your belief must follow the reference filter's after ` +
      'every step. Run such trials with the reference filter, and tune it, on ',
    link('/fusion', 'the sensor-fusion page'), '.',
  ];
}

/** The series of the trial plot: the truth, the readings, the field of view, the reference's path and ellipses, and the student's over them. */
function trialSeries(v, fov) {
  const { every, truth, reference: r, student: s, departure } = v;
  const at = (belief, k) => [poseAt(belief, k).slice(0, 2)];
  const readings = (kind) => positions(r.measured, (k) => r.use[k] === kind);
  return [
    styled(line('truth', truth[0], truth[1], colours.landmark, { name: 'the truth (dotted)', z: 1 }), dashes.odometry, 1.5),
    outlineSeries('field of view', 'the field of view', fov, colours.measurement, 1, 0.8, 1),
    markers('used', 'readings the reference used', readings(readingUse.used), colours.measurement, 'circle', 4, 1),
    markers('gated', 'readings its gate rejected', readings(readingUse.gated), colours.outlier, 'diamond', 8, 1),
    markers('outside', 'readings outside the field of view', readings(readingUse.outsideView), colours.measurement, 'triangle', 6, 1),
    styled(line('reference', r.pose[0], r.pose[1], colours.truth, { name: "the reference filter's path (solid)", z: 2 }), dashes.truth, 2),
    outlineSeries('reference ellipses', `its 3σ ellipses, every ${every} steps`, r.ellipses, colours.truth, 1.5, 0.7, 2),
    styled(line('yours', s.pose[0], s.pose[1], colours.estimate, { name: 'your path (dashed)', z: 3 }), dashes.estimate, 2),
    outlineSeries('your ellipses', 'your 3σ ellipses (dashed)', s.ellipses, colours.estimate, 1, 0.9, 4, 'dashed'),
    markers('start', 'start', at(r, 0), colours.truth, 'triangle', 11),
    ...(departure === null ? [] : [markers('departure', 'where yours departs', at(s, departure - 1), colours.estimate, 'diamond', 12, 9)]),
  ];
}

/** The runs section (the markup of `web/run_view.html` in `root`) showing one trial run at a time. */
class TrialRunView {
  /** @param {HTMLElement} root */
  constructor(root) {
    const plots = plotsIn(root, 'code');
    this.trial = plots.trial;
    this.difference = plots['trial-difference'];
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
    this.trial.describe(describeTrial(v));
    this.difference.set(overTime('difference from the reference', differenceSeries(v), { type: 'log', scale: false }));
    this.difference.describe(describeDifferences(v));
    this.difference.setMarker(v.departure === null ? null : v.t[v.departure - 1], 'where your run departs');
    setText(byId('trial-summary'), summaryText(v));
    fillBeliefTable(byId('trial-table', HTMLTableElement), v);
    byId('prefix').replaceChildren(...trialNote(v));
  }

  draw() {
    const v = this.view;
    const fov = circle(v.settings.field_of_view);
    const [rx, ry] = outlineXY(v.reference.ellipses);
    const [fx, fy] = outlineXY(fov);
    const { truth, reference: r, student: s } = v;
    this.trial.set(plane(this.trial, trialSeries(v, fov), [truth[0], r.pose[0], s.pose[0], rx, fx], [truth[1], r.pose[1], s.pose[1], ry, fy]));
  }
}

/**
 * The sensor-fusion workbench's runs: each one's views from the harness's output, and where they are drawn.
 *
 * @type {import('estlab/workbench/running.js').ExerciseRuns<Shown>}
 */
export const runs = { collect: collectRun, View: TrialRunView };
