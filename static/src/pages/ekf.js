// EKF localization, computed in the browser by the wasm build of the reference filters:
// a data set (simulated, or the reader's own EL2320 files), the filter's settings, and
// the plots of the lab.
import { byId, download, showError } from '../controls.js';
import { fmt } from '../format.js';
import { renderMath } from '../math.js';
import { MapView } from '../ekf/map.js';
import { band, colours, overTime, plotsIn, timeLine } from '../plots.js';
import { loadEstlab } from '../wasm.js';

renderMath();
const estlab = await loadEstlab();
const plots = plotsIn(byId('ekf-plots'), 'ekf');
const map = new MapView(plots.map);
const degrees = Math.PI / 180;

const ui = {
  kind: byId('dataset-kind'),
  seed: byId('dataset-seed'),
  files: byId('dataset-files'),
  mapFile: byId('map-file'),
  sensorFile: byId('sensor-file'),
  rX: byId('r-x'),
  rY: byId('r-y'),
  rTheta: byId('r-theta'),
  qRange: byId('q-range'),
  qBearing: byId('q-bearing'),
  deltaM: byId('delta-m'),
  lambda: byId('lambda-m'),
  known: byId('known-associations'),
  time: byId('time'),
  timeLabel: byId('time-label'),
  error: byId('error'),
};

let dataset = null;
let view = null;

/**
 * The variance an input of standard deviations (in `unit`s) stands for. An input filled
 * from the lab's settings shows a rounded value but keeps the exact variance until the
 * reader edits it, so that the lab's settings run exactly.
 */
function variance(input, unit = 1) {
  if (input.dataset.variance && input.value === input.dataset.shown) return Number(input.dataset.variance);
  return (Number(input.value) * unit) ** 2;
}

function showVariance(input, value, unit = 1) {
  input.value = fmt(Math.sqrt(value) / unit, 4);
  input.dataset.shown = input.value;
  input.dataset.variance = String(value);
}

/** The filter settings the controls say: standard deviations become variances. */
function settings() {
  return {
    mode: document.querySelector('input[name=mode]:checked').value,
    known_associations: ui.known.checked,
    r: [variance(ui.rX), variance(ui.rY), variance(ui.rTheta, degrees)],
    q: [variance(ui.qRange), variance(ui.qBearing, degrees)],
    delta_m: Number(ui.deltaM.value),
  };
}

/** Sets the controls to the lab's settings for the current data. */
function labSettings() {
  const lab = JSON.parse(dataset.labSettings());
  showVariance(ui.rX, lab.r[0]);
  showVariance(ui.rY, lab.r[1]);
  showVariance(ui.rTheta, lab.r[2], degrees);
  showVariance(ui.qRange, lab.q[0]);
  showVariance(ui.qBearing, lab.q[1], degrees);
  ui.deltaM.value = lab.delta_m;
  ui.known.checked = lab.known_associations;
  document.querySelector(`input[name=mode][value=${lab.mode}]`).checked = true;
}

async function loadDataset() {
  const kind = ui.kind.value;
  ui.files.hidden = kind !== 'files';
  for (const id of ['download-map', 'download-sensor']) byId(id).disabled = kind === 'files';
  let next;
  try {
    if (kind === 'files') {
      const [map, sensor] = [ui.mapFile.files[0], ui.sensorFile.files[0]];
      if (!map || !sensor) {
        showError(ui.error, 'Choose a map file and a sensor file.');
        return;
      }
      next = estlab.Dataset.parse(await map.text(), map.name, await sensor.text(), sensor.name);
    } else {
      next = estlab.Dataset.simulate(kind, Number(ui.seed.value));
    }
  } catch (error) {
    showError(ui.error, error.message);
    return;
  }
  dataset?.free();
  dataset = next;
  labSettings();
  ui.time.max = String(dataset.steps() - 1);
  ui.time.value = ui.time.max;
  update(true);
}

/** Everything the plots need from a run, taken out of wasm once. */
function collect(run) {
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

/** The time step `k` on the map: the poses, and each reading's association. */
function drawNow(k) {
  const v = view;
  const [lx, ly] = v.landmarks;
  const at = [v.estimate[0][k], v.estimate[1][k]];
  const lines = [];
  for (let r = v.firstReading[k]; r < v.firstReading[k + 1]; r++) {
    const c = v.association[r];
    const style = v.outlier[r]
      ? { color: colours.outlier, type: 'dashed', width: 1.5 }
      : { color: colours.estimate, width: 1.5 };
    lines.push({ coords: [at, [lx[c], ly[c]]], lineStyle: style });
    lines.push({ coords: [at, [v.readingXY[2 * r], v.readingXY[2 * r + 1]]], lineStyle: { color: colours.measurement, type: 'dotted', width: 1 } });
  }
  map.showNow(at, [v.truth[0][k], v.truth[1][k]], lines);
  const n = v.firstReading[k + 1] - v.firstReading[k];
  let rejected = 0;
  for (let r = v.firstReading[k]; r < v.firstReading[k + 1]; r++) rejected += v.outlier[r];
  ui.timeLabel.textContent = `t = ${fmt(v.t[k])} s (step ${k + 1} of ${v.t.length}): ${n} reading${n === 1 ? '' : 's'}, ${rejected} rejected`;
}

function drawOverTime(v) {
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

/** The command that makes the same run with the estlab command line. */
function commandLine(current) {
  const flags = ['--R', current.r.join(','), '--Q', current.q.join(','), '--delta-m', String(current.delta_m)];
  if (current.mode === 'batch') flags.push('--batch');
  if (current.known_associations) flags.push('--known-associations');
  const kind = ui.kind.value;
  if (kind === 'files') {
    return { flags, text: ['estlab run', ui.sensorFile.files[0].name, ui.mapFile.files[0].name, ...flags].join(' ') };
  }
  const stem = `${kind}_${ui.seed.value}`;
  const simulate = `estlab simulate --kind ${kind} --seed ${ui.seed.value} --out data`;
  return { flags, text: `${simulate} && ${['estlab run', `data/so_${stem}.txt`, `data/map_${stem}.txt`, ...flags].join(' ')}` };
}

/** Runs the filter and redraws; `newData` when the data set changed too. */
function update(newData = false) {
  if (!dataset) return;
  const start = performance.now();
  const current = settings();
  ui.lambda.textContent = `Λ_M = ${fmt(estlab.lambdaM(current.delta_m))}`;
  let run;
  try {
    run = dataset.run(JSON.stringify(current));
  } catch (error) {
    showError(ui.error, error.message);
    return;
  }
  showError(ui.error, null);
  view = collect(run);
  run.free();
  if (newData) map.showData(view.landmarks, view.truth, view.odometry);
  map.showRun(view.estimate, view.ellipses, view.rejected);
  drawNow(Number(ui.time.value));
  drawOverTime(view);
  byId('summary').textContent = view.report;
  const command = commandLine(current);
  byId('command').textContent = command.text;
  byId('command').dataset.flags = JSON.stringify(command.flags);
  byId('timing').textContent = `re-run and redraw: ${fmt(performance.now() - start, 2)} ms`;
  document.body.dataset.ready = 'true';
}

ui.kind.addEventListener('change', loadDataset);
ui.seed.addEventListener('change', loadDataset);
ui.mapFile.addEventListener('change', loadDataset);
ui.sensorFile.addEventListener('change', loadDataset);
for (const input of document.querySelectorAll('#ekf-settings .filter input')) input.addEventListener('input', () => update());
byId('lab-settings').addEventListener('click', () => { labSettings(); update(); });
ui.time.addEventListener('input', () => view && drawNow(Number(ui.time.value)));
for (const [id, delta] of [['time-back', -1], ['time-forward', 1]]) {
  byId(id).addEventListener('click', () => {
    ui.time.value = String(Math.min(Number(ui.time.max), Math.max(0, Number(ui.time.value) + delta)));
    if (view) drawNow(Number(ui.time.value));
  });
}
byId('download-map').addEventListener('click', () => download(`map_${ui.kind.value}_${ui.seed.value}.txt`, dataset.mapFile()));
byId('download-sensor').addEventListener('click', () => download(`so_${ui.kind.value}_${ui.seed.value}.txt`, dataset.sensorFile()));
window.addEventListener('resize', () => {
  if (!view) return;
  map.axesKey = null;
  map.showRun(view.estimate, view.ellipses, view.rejected);
});
await loadDataset();
