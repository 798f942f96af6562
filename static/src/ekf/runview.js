// A whole EKF run drawn with the lab's views: the map (see map.js) with the poses and
// associations of one time step, and the errors with their ±3σ bounds and the covariance
// over time. Used by the experiment page and by the student's data-set runs.
import { byId } from '../controls.js';
import { fmt } from '../format.js';
import { band, colours, overTime, plotsIn, timeLine } from '../plots.js';
import { MapView } from './map.js';

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
  return {
    t: run.t(),
    estimate: [0, 1, 2].map((i) => run.estimate(i)),
    truth: [0, 1, 2].map((i) => run.truth(i)),
    odometry: [0, 1, 2].map((i) => run.odometry(i)),
    error: [0, 1, 2].map((i) => run.error(i)),
    std: [0, 1, 2].map((i) => run.std(i)),
    variance: [0, 1, 2].map((i) => run.variance(i)),
    ellipses: run.ellipses(Math.max(1, Math.round(dataset.steps() / 40)), 3, 36),
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

/** The errors with ±3σ and the covariance diagonal of view `v` over time. */
function drawOverTime(plots, v) {
  const names = ['x (m)', 'y (m)', 'θ (rad)'];
  ['errorX', 'errorY', 'errorTheta'].forEach((name, i) => {
    const bound = v.std[i].map((s) => 3 * s);
    plots[name].set(overTime(`error in ${names[i]}`, [
      ...band('±3σ', v.t, bound.map((b) => -b), bound, colours.band),
      timeLine('estimate − truth', v.t, v.error[i], colours.estimate),
    ]));
  });
  plots.covariance.set(overTime('variance', [
    timeLine('Σₓₓ (m²)', v.t, v.variance[0], colours.estimate),
    timeLine('Σᵧᵧ (m²)', v.t, v.variance[1], colours.second),
    timeLine('Σθθ (rad²)', v.t, v.variance[2], colours.third),
  ], { type: 'log', scale: false }));
}

/**
 * The views of one run at a time in `root` (the markup of `ekf_plots.html`): the map, the
 * time slider under it with its buttons and caption, and the plots over time.
 */
export class RunView {
  constructor(root, prefix) {
    this.plots = plotsIn(root, prefix);
    this.map = new MapView(this.plots.map);
    this.view = null;
    this.time = byId('time');
    this.timeLabel = byId('time-label');
    this.time.addEventListener('input', () => this.showNow());
    for (const [id, delta] of [['time-back', -1], ['time-forward', 1]]) {
      byId(id).addEventListener('click', () => {
        this.time.value = String(Math.min(Number(this.time.max), Math.max(0, Number(this.time.value) + delta)));
        this.showNow();
      });
    }
    window.addEventListener('resize', () => {
      if (!this.view) return;
      this.map.axesKey = null;
      this.map.showRun(this.view.estimate, this.view.ellipses, this.view.rejected);
    });
  }

  /** Shows view `v` (from `collect`); `newData` when its data set differs from the last one's. */
  show(v, newData) {
    this.view = v;
    if (newData) {
      this.map.showData(v.landmarks, v.truth, v.odometry);
      this.time.max = String(v.t.length - 1);
      this.time.value = this.time.max;
    }
    this.map.showRun(v.estimate, v.ellipses, v.rejected);
    this.showNow();
    drawOverTime(this.plots, v);
  }

  showNow() {
    if (this.view) this.timeLabel.textContent = drawNow(this.map, this.view, Number(this.time.value));
  }
}
