// Odometry and how its error grows, computed in the browser by the wasm build of the
// reference model (labs::odometry): a path driven by a differential-drive robot, the
// covariance its odometry propagates, many robots whose wheels really slip, and the
// systematic errors of a robot built otherwise than its odometry assumes, with the
// UMBmark square that measures them.
//
// Three views, each computed only when what it depends on changed: the belief (the
// propagation and the robots), the systematic errors, and the UMBmark test. A view whose
// settings do not run keeps its last plots, dimmed, beside the library's message.
//
// The parts live in ../odometry/: what the controls say (settings.js) and each view
// (belief.js with the path plot of path.js, systematic.js, umbmark.js); this page runs
// them as the controls change.
import { LogSlider, byId, fieldMessage, setText, showError } from '../controls.js';
import { fmt } from '../format.js';
import { renderMath } from '../math.js';
import { BeliefView } from '../odometry/belief.js';
import {
  commandFlags, commandText, degrees, distinct, parsePoints, pointsText, settings, twoDigits,
} from '../odometry/settings.js';
import { SystematicView } from '../odometry/systematic.js';
import { UmbmarkView } from '../odometry/umbmark.js';
import { f } from '../odometry/view.js';
import { plotsIn } from '../plots.js';
import { loadEstlab } from '../wasm.js';

renderMath();
const estlab = await loadEstlab();
const defaults = JSON.parse(estlab.odometryDefaults());
const plots = plotsIn(byId('odometry-plots'), 'odometry');

/** The size each shape starts with (the command line's defaults). */
const sizes = { line: 4, circle: 2, square: 4, 'figure-eight': 1.5 };
const sizeNames = { line: 'length', circle: 'radius', square: 'side', 'figure-eight': 'radius' };

const ui = {
  shape: byId('shape', HTMLSelectElement),
  size: byId('size', HTMLInputElement),
  sizeName: byId('size-name'),
  sizeLabel: byId('size-label'),
  direction: byId('direction', HTMLSelectElement),
  directionLabel: byId('direction-label'),
  drawing: byId('drawing'),
  pointsValue: byId('points-value'),
  drawHint: byId('draw-hint'),
  points: byId('points', HTMLInputElement),
  speed: new LogSlider(byId('speed'), byId('speed-value'), (v) => `${fmt(twoDigits(v))} m per step`),
  wheelBase: byId('wheel-base', HTMLInputElement),
  kR: new LogSlider(byId('k-r'), byId('k-r-value'), (v) => `${fmt(twoDigits(v))} m: after 1 m ±${f(Math.sqrt(twoDigits(v)) * 100)} cm`),
  kL: new LogSlider(byId('k-l'), byId('k-l-value'), (v) => `${fmt(twoDigits(v))} m: after 1 m ±${f(Math.sqrt(twoDigits(v)) * 100)} cm`),
  sigmaTheta: byId('sigma-theta', HTMLInputElement),
  sigmaXy: byId('sigma-xy', HTMLInputElement),
  robots: byId('robots', HTMLInputElement),
  seed: byId('seed', HTMLInputElement),
  ellipseEvery: byId('ellipse-every', HTMLSelectElement),
  clouds: byId('clouds', HTMLInputElement),
  mapView: byId('map-view', HTMLSelectElement),
  eD: byId('e-d', HTMLInputElement),
  eB: byId('e-b', HTMLInputElement),
  side: byId('umbmark-side', HTMLInputElement),
  runs: byId('umbmark-runs', HTMLInputElement),
  error: byId('error'),
  command: byId('command'),
  timing: byId('timing'),
};

/** The points of the path drawn by the reader, [x, y] in metres, to the centimetre. */
let drawn = [];
/** Why the points typed do not read, or null. */
let pointsProblem = null;

/** The drawn points changed by a click or a button: the text field shows them. */
function pointsChanged() {
  ui.points.value = pointsText(drawn);
  pointsProblem = null;
  update();
}

/**
 * The values beside the controls, and the controls the shape uses; returns how many
 * distinct points the drawn path has.
 */
function showValues() {
  setText(byId('wheel-base-value'), `${fmt(Number(ui.wheelBase.value))} m`);
  const theta = Number(ui.sigmaTheta.value);
  setText(byId('sigma-theta-value'), theta === 0 ? '0°: the start heading known exactly' : `${fmt(theta)}° (${f(theta * degrees)} rad)`);
  const xy = Number(ui.sigmaXy.value);
  setText(byId('sigma-xy-value'), xy === 0 ? '0 cm: the start position known exactly' : `${fmt(xy)} cm`);
  const eD = Number(ui.eD.value);
  setText(byId('e-d-value'), `${fmt(eD, 5)}: the right wheel ${f(Math.abs(eD - 1) * 100)} % ${eD >= 1 ? 'larger' : 'smaller'} than the left`);
  const eB = Number(ui.eB.value);
  setText(byId('e-b-value'), `${fmt(eB, 4)}: the real wheel base ${f(Math.abs(eB - 1) * 100)} % ${eB >= 1 ? 'longer' : 'shorter'}`);
  const kind = ui.shape.value;
  ui.sizeLabel.hidden = kind === 'polyline';
  ui.directionLabel.hidden = kind !== 'circle' && kind !== 'square';
  ui.drawing.hidden = kind !== 'polyline';
  ui.drawHint.hidden = kind !== 'polyline';
  if (kind !== 'polyline') setText(ui.sizeName, sizeNames[kind]);
  const points = distinct(drawn).length;
  setText(ui.pointsValue, drawn.length
    ? `${drawn.length} point${drawn.length === 1 ? '' : 's'}${points < 2 ? ': at least two different ones make a path' : ''}`
    : 'No points yet: click on the plot, or type them above.');
  byId('undo-point', HTMLButtonElement).disabled = drawn.length === 0;
  byId('clear-points', HTMLButtonElement).disabled = drawn.length === 0;
  return points;
}

const views = {
  belief: new BeliefView(estlab, plots, { ellipseEvery: ui.ellipseEvery, clouds: ui.clouds, mapView: ui.mapView }),
  systematic: new SystematicView(estlab, plots),
  umbmark: new UmbmarkView(estlab, plots),
};

// --- running ---

/**
 * The field a message of the library (or of parsePoints) concerns, by the setting it
 * names before its colon (`shape.side: must lie in ...`), or null.
 */
function fieldOf(message) {
  const name = message.slice(0, message.indexOf(':'));
  if (name === 'shape.points') return ui.points;
  if (name.startsWith('shape.')) return ui.size;
  return { robots: ui.robots, side: ui.side, runs: ui.runs }[name] ?? null;
}

/** The fields a message can concern: each says beside it what is wrong with it. */
const checkedFields = [ui.points, ui.size, ui.robots, ui.side, ui.runs];

/**
 * Each message beside its field (the box above the plots, an alert, says them all at
 * once: the notes beside the fields are not announced again).
 */
function showFieldMessages(messages) {
  for (const field of checkedFields) {
    const own = messages.filter((message) => fieldOf(message) === field);
    fieldMessage(field, own.length ? own.join('\n') : null, { live: false });
  }
}

/** Runs what changed and redraws it; `force` redraws every view (a new window size). */
function update(force = false) {
  const start = performance.now();
  const points = showValues();
  const s = settings(ui, drawn);
  const messages = [];
  const drawing = s.params.shape.kind === 'polyline';
  const noPath = drawing && !pointsProblem && points < 2;

  /**
   * Computes `view` anew when its `key` (what it depends on) changed, else redraws it
   * when asked to; a failure leaves its last plots, dimmed, and says why.
   */
  const run = (view, key, redraw = false) => {
    if (key === view.key) {
      if (redraw || force) view.draw(view.result, s);
      return;
    }
    let result;
    try {
      result = view.compute(s);
    } catch (error) {
      messages.push(error.message);
      view.key = null;
      view.stale(true);
      return;
    }
    view.key = key;
    view.result = result;
    view.shown = true;
    view.stale(false);
    view.draw(result, s);
    view.describe?.(result, s);
  };
  /** A view that cannot run: the reader's points do not read (`why`), or there is no path yet. */
  const cannotRun = (view, why) => {
    view.key = null;
    if (why) {
      messages.push(why);
      view.stale(true);
    } else {
      view.shown = false;
      view.stale(false);
    }
  };

  const { belief, systematic, umbmark } = views;
  if (drawing && (pointsProblem || noPath)) {
    cannotRun(belief, pointsProblem);
    cannotRun(systematic, pointsProblem);
    if (noPath) {
      belief.drawPointsOnly(drawn);
      systematic.drawNoPath();
    }
  } else {
    // The ellipses' spacing and the clouds change what is computed (cloud_every); which
    // part of the plane is shown changes only the drawing.
    const changedView = belief.drawnView !== ui.mapView.value;
    belief.drawnView = ui.mapView.value;
    run(belief, JSON.stringify([s.params, s.robots, s.seed, ui.ellipseEvery.value, ui.clouds.checked]), changedView);
    run(systematic, JSON.stringify([s.params.shape, s.params.speed, s.params.wheel_base, s.errors]));
  }
  run(umbmark, JSON.stringify([s.params.speed, s.params.wheel_base, s.params.k_r, s.params.k_l, s.errors, s.umbmark]));

  showError(ui.error, messages.length ? [...new Set(messages)].join('\n') : null);
  showFieldMessages([...new Set(messages)]);
  const commandShown = !messages.length && !noPath;
  ui.command.closest('p').hidden = !commandShown;
  if (commandShown) {
    const flags = commandFlags(s);
    setText(ui.command, commandText(flags));
    ui.command.dataset.flags = JSON.stringify(flags);
  } else {
    setText(ui.command, '');
    delete ui.command.dataset.flags;
  }
  setText(ui.timing, `re-run and redraw: ${fmt(performance.now() - start, 2)} ms`);
}

// --- the controls ---

// The library's defaults on the controls that have them (the page's own on the rest).
ui.size.value = String(defaults.shape.side);
ui.direction.value = defaults.shape.direction;
ui.speed.value = defaults.speed;
ui.wheelBase.value = String(defaults.wheel_base);
ui.kR.value = defaults.k_r;
ui.kL.value = defaults.k_l;
const controls = [.../** @type {NodeListOf<HTMLInputElement | HTMLSelectElement>} */ (
  document.querySelectorAll('#odometry-controls :is(input, select):not(#points)'))];
/** What each control holds at first: its value, and for a checkbox whether it is checked. */
const initial = controls.map((control) => control.value);
const initialChecked = controls.map((control) => control instanceof HTMLInputElement && control.checked);
const initialSizes = { ...sizes };

/** Every setting back to what the page opened with (a path drawn stays, for later). */
function setDefaults() {
  controls.forEach((control, i) => {
    if (control instanceof HTMLInputElement && control.type === 'checkbox') control.checked = initialChecked[i];
    else control.value = initial[i];
  });
  Object.assign(sizes, initialSizes);
  for (const slider of [ui.speed, ui.kR, ui.kL]) slider.render();
}

ui.shape.addEventListener('change', () => {
  if (ui.shape.value !== 'polyline') ui.size.value = String(sizes[ui.shape.value]);
  update();
});
ui.size.addEventListener('input', () => {
  if (ui.shape.value !== 'polyline') sizes[ui.shape.value] = Number(ui.size.value);
  update();
});
for (const input of document.querySelectorAll('#odometry-controls input:not(#size):not(#points), #odometry-controls select:not(#shape)')) {
  input.addEventListener('input', () => update());
}
byId('banana').addEventListener('click', () => {
  ui.shape.value = 'line';
  sizes.line = 8;
  ui.size.value = '8';
  ui.kR.value = 1e-6;
  ui.kL.value = 1e-6;
  ui.sigmaTheta.value = '15';
  ui.sigmaXy.value = '0';
  update();
});
byId('reset').addEventListener('click', () => {
  setDefaults();
  update();
});
byId('undo-point').addEventListener('click', () => {
  drawn.pop();
  pointsChanged();
});
byId('clear-points').addEventListener('click', () => {
  drawn = [];
  pointsChanged();
});
ui.points.addEventListener('input', () => {
  try {
    drawn = parsePoints(ui.points.value);
    pointsProblem = null;
  } catch (error) {
    pointsProblem = error.message;
  }
  update();
});

// Drawing: a click (or tap) inside the path plot's axes adds a point there, to the
// centimetre, while the shape is the drawn one.
const pathChart = plots.path.chart;
pathChart.getZr().on('click', (event) => {
  if (ui.shape.value !== 'polyline') return;
  const pixel = [event.offsetX, event.offsetY];
  if (!pathChart.containPixel({ gridIndex: 0 }, pixel)) return;
  const [x, y] = pathChart.convertFromPixel({ gridIndex: 0 }, pixel);
  drawn.push([Math.round(x * 100) / 100, Math.round(y * 100) / 100]);
  pointsChanged();
});
// The axes keep a metre as long on x as on y: a new size of the window needs new ones.
let resizing = false;
window.addEventListener('resize', () => {
  if (resizing) return;
  resizing = true;
  requestAnimationFrame(() => {
    resizing = false;
    update(true);
  });
});

update();
document.body.dataset.ready = 'true';
