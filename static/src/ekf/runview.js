// A whole EKF run drawn with the lab's views: the map (see map.js) with the poses and
// associations of one time step, and the errors with their ±3σ bounds and the covariance
// over time, each with a marker at the time slider's step and a summary line in words.
// Used by the experiment page and by the student's data-set runs.
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { band, colours, dashes, overTime, plotsIn, stats, styled, timeLine } from '../plots.js';
import { MapView } from './map.js';

/** Numbers in the summary lines: a few significant digits. */
const f = (v) => fmt(v, 3);

/** Everything the views need from a run (an `EkfRun`) of `dataset`, taken out of wasm once. */
export function collect(run, dataset) {
  const readingStep = run.readingStep();
  const firstReading = new Uint32Array(dataset.steps() + 1);
  for (const step of readingStep) firstReading[step + 1]++;
  for (let k = 1; k < firstReading.length; k++) firstReading[k] += firstReading[k - 1];
  const outlier = run.readingOutlier();
  const readingXY = run.readingPosition();
  const rejected = [];
  for (let r = 0; r < outlier.length; r++) {
    if (outlier[r]) rejected.push([readingXY[2 * r], readingXY[2 * r + 1]]);
  }
  const ellipseEvery = Math.max(1, Math.round(dataset.steps() / 40));
  return {
    t: run.t(),
    estimate: [0, 1, 2].map((i) => run.estimate(i)),
    truth: [0, 1, 2].map((i) => run.truth(i)),
    odometry: [0, 1, 2].map((i) => run.odometry(i)),
    error: [0, 1, 2].map((i) => run.error(i)),
    std: [0, 1, 2].map((i) => run.std(i)),
    variance: [0, 1, 2].map((i) => run.variance(i)),
    ellipses: run.ellipses(ellipseEvery, 3, 36),
    ellipseEvery,
    association: run.readingAssociation(),
    outlier,
    readingXY,
    rejected,
    firstReading,
    landmarks: [dataset.landmarkX(), dataset.landmarkY()],
    report: run.report(),
  };
}

/** Time step `k` of view `v` on `map`: the poses, and each reading's association. Returns its caption. */
function drawNow(map, v, k) {
  const [lx, ly] = v.landmarks;
  const at = [v.estimate[0][k], v.estimate[1][k]];
  const lines = [];
  let rejected = 0;
  for (let r = v.firstReading[k]; r < v.firstReading[k + 1]; r++) {
    const c = v.association[r];
    const style = v.outlier[r]
      ? { color: colours.outlier, type: 'dashed', width: 1.5 }
      : { color: colours.estimate, width: 1.5 };
    lines.push({ coords: [at, [lx[c], ly[c]]], lineStyle: style });
    lines.push({ coords: [at, [v.readingXY[2 * r], v.readingXY[2 * r + 1]]], lineStyle: { color: colours.measurement, type: 'dotted', width: 1 } });
    rejected += v.outlier[r];
  }
  map.showNow(at, [v.truth[0][k], v.truth[1][k]], lines);
  const n = v.firstReading[k + 1] - v.firstReading[k];
  return `t = ${fmt(v.t[k])} s (step ${k + 1} of ${v.t.length}): ${n} reading${n === 1 ? '' : 's'}, ${rejected} rejected`;
}

const errorPlots = [
  ['errorX', 'x', 'm'],
  ['errorY', 'y', 'm'],
  ['errorTheta', 'θ', 'rad'],
];
const varianceSeries = [
  ['Σₓₓ (m²)', 'solid', colours.estimate],
  ['Σᵧᵧ (m²), dashed', dashes.estimate, colours.second],
  ['Σθθ (rad²), dotted', dashes.odometry, colours.third],
];
const varianceIds = ['Σₓₓ (m²)', 'Σᵧᵧ (m²)', 'Σθθ (rad²)'];

/**
 * The errors with ±3σ and the covariance diagonal of view `v` over time: the whole option
 * for a new data set (`whole`), only the numbers for another run over the same one.
 */
export function drawOverTime(plots, v, whole) {
  errorPlots.forEach(([name, component, unit], i) => {
    const bound = v.std[i].map((s) => 3 * s);
    const series = [
      ...band('±3σ', v.t, bound.map((b) => -b), bound, colours.band),
      timeLine('estimate − truth', v.t, v.error[i], colours.estimate),
    ];
    if (whole) plots[name].set(overTime(`error in ${component} (${unit})`, series));
    else plots[name].setData(series.map(({ id, data }) => ({ id, data })));
  });
  const series = varianceIds.map((id, i) => {
    const [name, dash, colour] = varianceSeries[i];
    return styled(timeLine(id, v.t, v.variance[i], colour, { name }), dash);
  });
  if (whole) plots.covariance.set(overTime('variance', series, { type: 'log', scale: false }));
  else plots.covariance.setData(series.map(({ id, data }) => ({ id, data })));
}

/** The summary lines of the plots over time. */
export function describeOverTime(plots, v) {
  const n = v.t.length;
  const span = `over ${n} steps (t = ${f(v.t[0])} to ${f(v.t[n - 1])} s)`;
  errorPlots.forEach(([name, component, unit], i) => {
    const s = stats(v.error[i], v.t);
    let inside = 0;
    for (let k = 0; k < n; k++) if (Math.abs(v.error[i][k]) <= 3 * v.std[i][k]) inside++;
    plots[name].describe(
      `Error in ${component} ${span}: mean ${f(s.mean)} ${unit}, mean absolute ${f(s.meanAbs)} ${unit}, ` +
      `largest ${f(s.maxAbs)} ${unit} in size at t = ${f(s.maxAbsAt)} s; within ±3σ at ${f((100 * inside) / n)}% of the steps ` +
      `(3σ at the end: ${f(3 * v.std[i][n - 1])} ${unit}).`);
  });
  const words = ['Σₓₓ', 'Σᵧᵧ', 'Σθθ'].map((name, i) => {
    const s = stats(v.variance[i]);
    const unit = i === 2 ? 'rad²' : 'm²';
    return `${name} from ${f(s.first)} to ${f(s.last)} ${unit} (largest ${f(s.max)})`;
  });
  plots.covariance.describe(`The covariance diagonal on a log scale ${span}: ${words.join('; ')}.`);
}

/** The summary line of the map. */
export function describeMap(map, v) {
  const n = v.t.length;
  const distance = (path, k) => Math.hypot(path[0][k] - v.truth[0][k], path[1][k] - v.truth[1][k]);
  const gaps = Array.from({ length: n }, (_, k) => distance(v.estimate, k));
  const gap = stats(gaps, v.t);
  const { factor, across } = map.ellipseSize();
  const rejected = v.rejected.length;
  const [x0, y0, x1, y1] = [v.truth[0][0], v.truth[1][0], v.truth[0][n - 1], v.truth[1][n - 1]];
  map.plot.describe(
    `The map: ${v.landmarks[0].length} landmarks (black stars); the true path (green, solid) over ${n} steps from ` +
    `(${f(x0)}, ${f(y0)}) to (${f(x1)}, ${f(y1)}) m; the estimated path (red, dashed) ${f(gap.meanAbs)} m from it on average, ` +
    `at most ${f(gap.maxAbs)} m (at t = ${f(gap.maxAbsAt)} s); the odometry-only path (blue, dotted) ends ${f(distance(v.odometry, n - 1))} m ` +
    `from the true pose; ${rejected} reading${rejected === 1 ? '' : 's'} rejected (orange diamonds); 3σ ellipses every ` +
    `${v.ellipseEvery === 1 ? '' : `${v.ellipseEvery}th `}step, typically ${f(across)} m across, ` +
    `${factor === 1 ? 'drawn at their true size' : `drawn ${factor} times their size`}.`);
}

/**
 * The views of one run at a time in `root` (the markup of the EKF exercise's `web/plots.html`): the map with
 * its zoom and ellipse tools, the time slider under it with its buttons and caption, and
 * the plots over time.
 */
export class RunView {
  constructor(root, prefix) {
    this.plots = plotsIn(root, prefix);
    this.map = new MapView(this.plots.map);
    this.view = null;
    this.time = byId('time', HTMLInputElement);
    this.timeLabel = byId('time-label');
    this.time.addEventListener('input', () => this.showNow());
    /** @type {[string, number][]} */
    const stepButtons = [['time-back', -1], ['time-forward', 1]];
    for (const [id, delta] of stepButtons) {
      byId(id).addEventListener('click', () => {
        this.time.value = String(Math.min(Number(this.time.max), Math.max(0, Number(this.time.value) + delta)));
        this.showNow();
      });
    }
    const reset = byId('map-reset', HTMLButtonElement);
    this.map.onZoom = (zoomed) => { reset.disabled = !zoomed; };
    reset.addEventListener('click', () => this.map.resetZoom());
    this.ellipseScale = byId('ellipse-scale', HTMLSelectElement);
    this.ellipseNote = byId('ellipse-note');
    this.ellipseScale.addEventListener('change', () => {
      const value = this.ellipseScale.value;
      this.map.ellipseScale = value === 'auto' ? 'auto' : Number(value);
      if (this.view) {
        this.map.drawRun();
        this.describeEllipses();
      }
    });
    window.addEventListener('resize', () => {
      if (!this.view) return;
      // A phone turned on its side: the map may fit better the other way now.
      if (this.map.fitsTurned() !== this.map.turned) this.showData(this.view);
      this.map.axesKey = null;
      this.map.showRun(this.view.estimate, this.view.ellipses, this.view.rejected);
      this.describeEllipses();
    });
  }

  /** Shows view `v` (from `collect`); `newData` when its data set differs from the last one's. */
  show(v, newData) {
    const whole = newData || !this.view;
    this.view = v;
    if (newData) {
      this.showData(v);
      this.time.max = String(v.t.length - 1);
      this.time.value = this.time.max;
    }
    this.map.showRun(v.estimate, v.ellipses, v.rejected);
    drawOverTime(this.plots, v, whole);
    this.showNow();
    this.describeEllipses();
    describeOverTime(this.plots, v);
  }

  /** The map of `v`'s data set, and whether it is turned. */
  showData(v) {
    this.map.showData(v.landmarks, v.truth, v.odometry);
    byId('map-turned').hidden = !this.map.turned;
  }

  /** Says how large the ellipses are drawn, beside their control and in the map's summary. */
  describeEllipses() {
    const { factor, across } = this.map.ellipseSize();
    setText(this.ellipseNote, factor === 1
      ? `at their true size (typically ${f(across)} m across)`
      : `drawn ${factor} times their size (typically ${f(across)} m across, ${f(factor * across)} m as drawn)`);
    describeMap(this.map, this.view);
  }

  /** The time step of the slider: on the map, and as a marker on the plots over time. */
  showNow() {
    if (!this.view) return;
    const k = Number(this.time.value);
    this.timeLabel.textContent = drawNow(this.map, this.view, k);
    const t = this.view.t[k];
    for (const [name] of [...errorPlots, ['covariance']]) this.plots[name].setMarker(t, `t = ${fmt(t)} s: the step the map shows`);
  }
}
