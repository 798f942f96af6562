// Odometry and how its error grows, computed in the browser by the wasm build of the
// reference model (labs::odometry): a path driven by a differential-drive robot, the
// covariance its odometry propagates, many robots whose wheels really slip, and the
// systematic errors of a robot built otherwise than its odometry assumes, with the
// UMBmark square that measures them.
//
// Three views, each computed only when what it depends on changed: the belief (the
// propagation and the robots), the systematic errors, and the UMBmark test. A view whose
// settings do not run keeps its last plots, dimmed, beside the library's message.
import { LogSlider, byId, fieldMessage, setText, showError } from '../controls.js';
import { decimal, fmt } from '../format.js';
import { renderMath } from '../math.js';
import {
  colours, dashes, ellipseAxes, ellipseSpacing, line, markers, outlineSeries, outlineXY, outlines, overTime, pairs, plane,
  plotsIn, styled,
} from '../plots.js';
import { loadEstlab } from '../wasm.js';

renderMath();
const estlab = await loadEstlab();
const defaults = JSON.parse(estlab.odometryDefaults());
const plots = plotsIn(byId('odometry-plots'), 'odometry');
const degrees = Math.PI / 180;

/**
 * Numbers of the summary lines: a few significant digits, and 0 for what is zero but for
 * rounding (a closed square ends 1e-15 m from its start).
 */
const f = (v) => fmt(Math.abs(v) < 1e-12 ? 0 : v, 3);
/** A log slider's value as it is run: two significant digits (0.05, 0.0001, 0.0032). */
const twoDigits = (v) => Number(v.toPrecision(2));

/** The size each shape starts with (the command line's defaults). */
const sizes = { line: 4, circle: 2, square: 4, 'figure-eight': 1.5 };
const sizeNames = { line: 'length', circle: 'radius', square: 'side', 'figure-eight': 'radius' };

const ui = {
  shape: byId('shape'),
  size: byId('size'),
  sizeName: byId('size-name'),
  sizeLabel: byId('size-label'),
  direction: byId('direction'),
  directionLabel: byId('direction-label'),
  drawing: byId('drawing'),
  pointsValue: byId('points-value'),
  drawHint: byId('draw-hint'),
  points: byId('points'),
  speed: new LogSlider(byId('speed'), byId('speed-value'), (v) => `${fmt(twoDigits(v))} m per step`),
  wheelBase: byId('wheel-base'),
  kR: new LogSlider(byId('k-r'), byId('k-r-value'), (v) => `${fmt(twoDigits(v))} m: after 1 m ±${f(Math.sqrt(twoDigits(v)) * 100)} cm`),
  kL: new LogSlider(byId('k-l'), byId('k-l-value'), (v) => `${fmt(twoDigits(v))} m: after 1 m ±${f(Math.sqrt(twoDigits(v)) * 100)} cm`),
  sigmaTheta: byId('sigma-theta'),
  sigmaXy: byId('sigma-xy'),
  robots: byId('robots'),
  seed: byId('seed'),
  ellipseEvery: byId('ellipse-every'),
  clouds: byId('clouds'),
  mapView: byId('map-view'),
  eD: byId('e-d'),
  eB: byId('e-b'),
  side: byId('umbmark-side'),
  runs: byId('umbmark-runs'),
  error: byId('error'),
  command: byId('command'),
  timing: byId('timing'),
};

/** The points of the path drawn by the reader, [x, y] in metres, to the centimetre. */
let drawn = [];
/** Why the points typed do not read, or null. */
let pointsProblem = null;

/** The points as the text field shows them: `x,y; x,y; ...`. */
const pointsText = (points) => points.map(([x, y]) => `${x},${y}`).join('; ');

/** Points typed as `x,y; x,y; ...`; throws a message naming the field and the point. */
function parsePoints(text) {
  const pairs = text.split(';').map((pair) => pair.trim()).filter((pair) => pair !== '');
  return pairs.map((pair, k) => {
    const numbers = pair.split(',').map((v) => (v.trim() === '' ? NaN : Number(v)));
    if (numbers.length !== 2 || !numbers.every(Number.isFinite)) {
      throw new Error(`shape.points: point ${k} must be two numbers x,y, got "${pair}"`);
    }
    return numbers;
  });
}

/** The drawn points changed by a click or a button: the text field shows them. */
function pointsChanged() {
  ui.points.value = pointsText(drawn);
  pointsProblem = null;
  update();
}

/** The points without those that repeat the one before (as the library counts them). */
function distinct(points) {
  return points.filter((p, i) => i === 0 || p[0] !== points[i - 1][0] || p[1] !== points[i - 1][1]);
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
  byId('undo-point').disabled = drawn.length === 0;
  byId('clear-points').disabled = drawn.length === 0;
  return points;
}

/** The shape the controls say, as `labs::odometry::Shape` reads it. */
function shape() {
  const kind = ui.shape.value;
  const size = decimal(Number(ui.size.value));
  switch (kind) {
    case 'line': return { kind, length: size };
    case 'circle': return { kind, radius: size, direction: ui.direction.value };
    case 'square': return { kind, side: size, direction: ui.direction.value };
    case 'figure-eight': return { kind, radius: size };
    default: return { kind: 'polyline', points: drawn.map((p) => [...p]) };
  }
}

/**
 * Everything the controls say, as the library's types read it. Every number is the one
 * the command line gets (decimal: 12 significant digits), so that the command the page
 * shows runs exactly what the page ran.
 */
function settings() {
  const sigmaXy = decimal((Number(ui.sigmaXy.value) / 100) ** 2);
  const sigmaTheta = decimal((Number(ui.sigmaTheta.value) * degrees) ** 2);
  const params = {
    shape: shape(),
    speed: twoDigits(ui.speed.value),
    wheel_base: decimal(Number(ui.wheelBase.value)),
    k_r: twoDigits(ui.kR.value),
    k_l: twoDigits(ui.kL.value),
    sigma0: [[sigmaXy, 0, 0], [0, sigmaXy, 0], [0, 0, sigmaTheta]],
  };
  return {
    params,
    robots: Number(ui.robots.value),
    seed: Number(ui.seed.value),
    errors: { e_d: decimal(Number(ui.eD.value)), e_b: decimal(Number(ui.eB.value)) },
    umbmark: { side: decimal(Number(ui.side.value)), runs: Number(ui.runs.value), seed: Number(ui.seed.value) },
  };
}

/** The flags of `estlab odometry` that make the same runs. */
function commandFlags(s) {
  const p = s.params;
  const flags = [];
  if (p.shape.kind === 'polyline') {
    flags.push('--points', p.shape.points.map(([x, y]) => `${x},${y}`).join(';'));
  } else {
    flags.push('--shape', p.shape.kind, '--size', String(p.shape.length ?? p.shape.radius ?? p.shape.side));
    if (p.shape.direction) flags.push('--direction', p.shape.direction === 'clockwise' ? 'cw' : 'ccw');
  }
  flags.push('--speed', String(p.speed), '--wheel-base', String(p.wheel_base), '--k-r', String(p.k_r), '--k-l', String(p.k_l));
  flags.push('--sigma0', [p.sigma0[0][0], p.sigma0[1][1], p.sigma0[2][2]].map(String).join(','));
  flags.push('--monte-carlo', String(s.robots), '--seed', String(s.seed));
  flags.push('--e-d', String(s.errors.e_d), '--e-b', String(s.errors.e_b));
  flags.push('--umbmark', String(s.umbmark.side), '--runs', String(s.umbmark.runs));
  return flags;
}

/** The command as a person types it: the points quoted for the shell. */
function commandText(flags) {
  return ['estlab odometry', ...flags.map((flag) => (flag.includes(';') ? `'${flag}'` : flag))].join(' ');
}

// --- geometry for the plots ---

/** The angle wrapped to [-pi, pi). */
const wrap = (angle) => angle - 2 * Math.PI * Math.floor((angle + Math.PI) / (2 * Math.PI));

/**
 * The sample standard deviations of poses (positions `xy`: x, y, x, y, ...; headings
 * `theta`) about their mean, the heading taken as its wrapped difference from
 * `nominalTheta` (as the library does).
 */
function spread(xy, theta, nominalTheta) {
  const n = theta.length;
  const sd = (value) => {
    let mean = 0;
    for (let i = 0; i < n; i++) mean += value(i);
    mean /= n;
    let sum = 0;
    for (let i = 0; i < n; i++) sum += (value(i) - mean) ** 2;
    return Math.sqrt(sum / (n - 1));
  };
  return [sd((i) => xy[2 * i]), sd((i) => xy[2 * i + 1]), sd((i) => wrap(theta[i] - nominalTheta))];
}

/**
 * The series of a scatter of many points (`xy`: x, y, x, y, ... in a typed array, which
 * ECharts reads without a copy), drawn in one pass.
 */
function cloudSeries(id, name, xy, colour, size, opacity, z) {
  return { id, name, type: 'scatter', data: xy, dimensions: ['x', 'y'], symbolSize: size, large: true, largeThreshold: 200, silent: true, itemStyle: { color: colour, opacity }, z };
}

/**
 * Shows `option` on `plot`. When the plot is on screen and already shows an option of the
 * same make (the same series, by id and name), only the axes' ranges and the series'
 * data are merged in, which costs ECharts far less than a whole option.
 */
function show(plot, option) {
  const make = option.series.map((s) => `${s.id}\u0000${s.name}`).join('\u0001');
  if (plot.visible && plot.make === make) {
    const range = (axis) => (typeof axis?.min === 'number' ? { min: axis.min, max: axis.max } : undefined);
    const [xAxis, yAxis] = [range(option.xAxis), range(option.yAxis)];
    plot.update({
      ...(xAxis && { xAxis }),
      ...(yAxis && { yAxis }),
      series: option.series.map(({ id, data }) => ({ id, data })),
    });
  } else {
    plot.make = make;
    plot.set(option);
  }
}

/** A plot over the steps of the path. */
function overSteps(yName, series) {
  return {
    ...overTime(yName, series, {}, { name: 'step k' }),
    tooltip: {
      trigger: 'axis',
      formatter: (items) => items.length
        ? [`step ${fmt(items[0].value[0])}`, ...items.map((item) => `${item.marker}${item.seriesName}: ${fmt(item.value[1])}`)].join('<br>')
        : '',
    },
  };
}

// --- the views ---

const staleWords = 'These plots and numbers are still those of the last settings that ran, dimmed: the settings now do not run (the message above says why).';

class View {
  constructor(name) {
    this.section = byId(`${name}-view`);
    this.note = byId(`${name}-stale`);
    /** What the view was last computed from (JSON text), null when it is to be computed. */
    this.key = null;
    /** Whether it shows a result. */
    this.shown = false;
    this.result = null;
  }

  /** Marks the view's plots as those of settings that no longer run, or as current. */
  stale(isStale) {
    const dimmed = isStale && this.shown;
    this.section.classList.toggle('stale', dimmed);
    this.note.hidden = !dimmed;
    setText(this.note, dimmed ? staleWords : '');
  }
}

const views = { belief: new View('belief'), systematic: new View('systematic'), umbmark: new View('umbmark') };

/** The steps between ellipses (and clouds) along a path of `steps` steps. */
function ellipseEvery(steps) {
  const chosen = ui.ellipseEvery.value;
  return chosen === 'auto' ? ellipseSpacing(steps) : Number(chosen);
}

/** Propagation and robots for `s`, taken out of wasm at once. */
function computeBelief(s) {
  const json = JSON.stringify(s.params);
  const run = estlab.propagateOdometry(json);
  try {
    const steps = run.steps();
    const every = ellipseEvery(steps);
    const cloudEvery = ui.clouds.checked ? every : 0;
    const mc = estlab.odometryMonteCarlo(json, JSON.stringify({ robots: s.robots, seed: s.seed, cloud_every: cloudEvery }));
    try {
      const cloudSteps = [...mc.cloudSteps()];
      return {
        steps,
        every,
        pose: [0, 1, 2].map((i) => run.pose(i)),
        std: [0, 1, 2].map((i) => run.std(i)),
        ellipses: outlines(run.ellipses(every, 3, 48)),
        finalEllipse: outlines(run.ellipse(steps, 3, 96)),
        finalPose: run.finalPose(),
        covariance: mc.covariance(),
        robots: mc.robots(),
        finalXY: mc.finalPositions(),
        cloudSteps,
        clouds: cloudSteps.map((_, c) => ({ xy: mc.cloudPositions(c), theta: mc.cloud(c, 2) })),
        sampleMean: mc.sampleMean(),
        sampleCovariance: mc.sampleCovariance(),
        inside: mc.insideThreeSigma(),
        gaussian: mc.gaussianInsideThreeSigma(),
      };
    } finally {
      mc.free();
    }
  } finally {
    run.free();
  }
}

/** The covariance entries shown in the table: [label, row, column, unit]. */
const entries = [
  ['Σ<sub>xx</sub> (m²)', 0, 0],
  ['Σ<sub>xy</sub> (m²)', 0, 1],
  ['Σ<sub>yy</sub> (m²)', 1, 1],
  ['Σ<sub>xθ</sub> (m rad)', 0, 2],
  ['Σ<sub>yθ</sub> (m rad)', 1, 2],
  ['Σ<sub>θθ</sub> (rad²)', 2, 2],
];

/** A table row: a heading and cells of [shown text, exact value]. */
function row(heading, cells, id) {
  const tr = document.createElement('tr');
  if (id) tr.dataset.row = id;
  const th = document.createElement('th');
  th.scope = 'row';
  th.innerHTML = heading;
  tr.append(th);
  for (const [text, value] of cells) {
    const td = document.createElement('td');
    td.textContent = text;
    if (value !== undefined && value !== null) td.dataset.value = String(value);
    tr.append(td);
  }
  return tr;
}

const percent = (share) => `${fmt(100 * share, 4)} %`;

function describeTable(b) {
  const body = byId('covariance-table').tBodies[0];
  setText(byId('robots-heading'), `${b.robots} robots`);
  const rows = [
    row('x (m)', [[f(b.finalPose[0]), b.finalPose[0]], [f(b.sampleMean[0]), b.sampleMean[0]]], 'x'),
    row('y (m)', [[f(b.finalPose[1]), b.finalPose[1]], [f(b.sampleMean[1]), b.sampleMean[1]]], 'y'),
    row('θ (°)', [[f(b.finalPose[2] / degrees), b.finalPose[2]], [f(b.sampleMean[2] / degrees), b.sampleMean[2]]], 'theta'),
    ...entries.map(([label, i, j]) => row(label, [
      [fmt(b.covariance[3 * i + j], 4), b.covariance[3 * i + j]],
      [fmt(b.sampleCovariance[3 * i + j], 4), b.sampleCovariance[3 * i + j]],
    ], `sigma-${i}${j}`)),
    row('inside the 3σ ellipse', [
      [percent(b.gaussian), b.gaussian],
      b.inside === undefined ? ['no ellipse: the position covariance is singular', null] : [percent(b.inside), b.inside],
    ], 'inside'),
  ];
  body.replaceChildren(...rows);
}

/** The extents of x and of y of positions given as x, y, x, y, ...: [[x0, x1], [y0, y1]]. */
function extentXY(xy) {
  let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
  for (let i = 0; i < xy.length; i += 2) {
    const [x, y] = [xy[i], xy[i + 1]];
    if (x < x0) x0 = x;
    if (x > x1) x1 = x;
    if (y < y0) y0 = y;
    if (y > y1) y1 = y;
  }
  return xy.length ? [[x0, x1], [y0, y1]] : [[], []];
}

/**
 * The series of the path plot: always the same ones, empty where there is nothing to
 * draw (a series left out would leave a hole in the chart's option). The first three
 * change with the path, the rest with the noise too.
 */
function pathSeries({ x = [], y = [], points = [], every = 0, ellipses = [], clouds = [], robots = [], count = 0, finalEllipse = [], end = [] }) {
  return {
    base: [
      styled(line('path', x, y, colours.odometry, { name: "the odometry's path (dotted)", z: 2 }), dashes.odometry, 2),
      markers('start', 'start', x.length ? [[x[0], y[0]]] : [], colours.truth, 'triangle', 11),
      markers('points', 'your points', points, '#1d2125', 'circle', 8, 9),
    ],
    noise: [
      outlineSeries('ellipses', every ? `3σ ellipses, every ${every} steps` : '3σ ellipses', ellipses, colours.estimate, 1, 0.7, 3),
      cloudSeries('clouds', 'the robots along the way', clouds, colours.third, 2, 0.35, 4),
      cloudSeries('robots', count ? `the ${count} robots at the end` : 'the robots at the end', robots, colours.second, 3, 0.55, 5),
      outlineSeries('final ellipse', '3σ ellipse at the end', finalEllipse, colours.estimate, 2.5, 1, 6),
      markers('end', "the odometry's end", end, colours.odometry, 'circle', 9),
    ],
  };
}

/**
 * The path plot in two layers: the chart itself (axes, legend, the path, its start, the
 * points drawn) and a transparent one over it with what the noise changes (ellipses,
 * robots, the end). A noise setting moved without moving the axes redraws the upper
 * layer alone, which costs ECharts far less than the whole plot.
 */
class PathView {
  constructor(plot) {
    this.plot = plot;
    this.layer = plot.addOverlay();
    /** What the chart itself shows: its axes' ranges, the legend's names and its series' data. */
    this.shown = null;
  }

  /** Shows the series of `pathSeries` on the axes of `plane` over `xs`, `ys`. */
  show({ base, noise }, xs, ys) {
    // The legend lists the upper layer's series too: entries without data down here. It
    // leaves out the points drawn and the robots along the way while there are none.
    const listed = [...base, ...noise].filter((s) => !['points', 'clouds'].includes(s.id) || s.data.length);
    const option = plane(this.plot, [...base, ...noise.map((s) => ({ ...s, data: [] }))], xs, ys, listed.map((s) => s.name));
    const shown = {
      axes: [option.xAxis.min, option.xAxis.max, option.yAxis.min, option.yAxis.max],
      names: listed.map((s) => s.name),
      data: base.map((s) => s.data.flat()),
    };
    if (!this.shown || !sameNumbers(shown.axes, this.shown.axes) || shown.names.join() !== this.shown.names.join()
      || shown.data.some((data, i) => !sameNumbers(data, this.shown.data[i]))) {
      this.shown = shown;
      this.plot.set(option);
    }
    // Drawn at once, in view or not (the chart beneath waits until it is in view).
    const hidden = (axis) => ({ ...axis, show: false });
    this.layer.setOption({ animation: false, grid: option.grid, legend: { show: false }, xAxis: hidden(option.xAxis), yAxis: hidden(option.yAxis), series: noise }, { replaceMerge: ['series'] });
  }
}

/** Whether two lists hold the same numbers. */
function sameNumbers(a, b) {
  return a.length === b.length && a.every((v, i) => v === b[i]);
}

const pathView = new PathView(plots.path);

/**
 * The standard deviations over the steps `k` (propagated, `std`: x, y, theta) and the
 * robots' spread at some steps (`sampled`: [step, x, y, theta]), both plots' series.
 */
function stdSeries(k = [], std = [[], [], []], sampled = []) {
  const robotsAt = (i, colour, symbol, name) => ({
    id: `robots ${i}`, name, type: 'scatter', data: sampled.map((p) => [p[0], i === 2 ? p[3] / degrees : p[i + 1]]),
    symbol, symbolSize: 8, itemStyle: { color: colour }, z: 5,
  });
  return {
    position: [
      line('σx', k, std[0], colours.estimate, { name: 'σx, propagated' }),
      styled(line('σy', k, std[1], colours.second, { name: 'σy, propagated (dashed)' }), dashes.estimate),
      robotsAt(0, colours.estimate, 'circle', 'σx of the robots'),
      robotsAt(1, colours.second, 'diamond', 'σy of the robots'),
    ],
    heading: [
      line('σθ', k, Array.from(std[2], (v) => v / degrees), colours.third, { name: 'σθ, propagated' }),
      robotsAt(2, colours.third, 'circle', 'σθ of the robots'),
    ],
  };
}

function drawBelief(b, s) {
  const [x, y] = b.pose;
  const [fx, fy] = extentXY(b.finalXY);
  const clouds = new Float64Array(b.clouds.reduce((n, c) => n + c.xy.length, 0));
  let at = 0;
  for (const { xy } of b.clouds) {
    clouds.set(xy, at);
    at += xy.length;
  }
  const [cx, cy] = extentXY(clouds);
  const [ex, ey] = outlineXY(b.ellipses);
  const [lx, ly] = outlineXY(b.finalEllipse);
  const end = ui.mapView.value === 'end';
  const points = s.params.shape.kind === 'polyline' ? drawn : [];
  const room = drawingRoom(points);
  const axesX = end ? [lx, fx, [b.finalPose[0]]] : [x, ex, lx, fx, cx, room[0]];
  const axesY = end ? [ly, fy, [b.finalPose[1]]] : [y, ey, ly, fy, cy, room[1]];
  pathView.show(pathSeries({
    x,
    y,
    points,
    every: b.every,
    ellipses: b.ellipses,
    clouds,
    robots: b.finalXY,
    count: b.robots,
    finalEllipse: b.finalEllipse,
    end: [[b.finalPose[0], b.finalPose[1]]],
  }), axesX, axesY);

  const k = Array.from({ length: b.steps + 1 }, (_, i) => i);
  // The robots' spread at the clouds' steps and at the end, beside the propagated σ.
  const sampled = b.cloudSteps.map((step, c) => [step, ...spread(b.clouds[c].xy, b.clouds[c].theta, b.pose[2][step])]);
  const sd = (i) => Math.sqrt(b.sampleCovariance[4 * i]);
  sampled.push([b.steps, sd(0), sd(1), sd(2)]);
  const series = stdSeries(k, b.std, sampled);
  show(plots['position-std'], overSteps('σ (m)', series.position));
  show(plots['heading-std'], overSteps('σθ (°)', series.heading));
}

function describeBelief(b, s) {
  const n = b.steps;
  const cov = b.covariance;
  const { major, minor, angle } = ellipseAxes(cov[0], cov[1], cov[4]);
  const inside = b.inside === undefined
    ? 'the position covariance is singular, so there is no 3σ ellipse to count them in'
    : `${percent(b.inside)} of them inside the last 3σ ellipse, where a Gaussian puts ${percent(b.gaussian)}`;
  const [x, y] = b.pose;
  plots.path.describe(
    `The ${describeShape(s.params.shape)}: ${n} steps from (${f(x[0])}, ${f(y[0])}) to (${f(x[n])}, ${f(y[n])}) m. ` +
    `3σ ellipses every ${b.every} steps (${b.ellipses.length} of them); the last one ${f(2 * major)} m by ${f(2 * minor)} m across, ` +
    `its long axis at ${f(angle / degrees)}°. ${b.robots} robots (seed ${s.seed}) end with a spread of σx = ${f(Math.sqrt(b.sampleCovariance[0]))} m ` +
    `and σy = ${f(Math.sqrt(b.sampleCovariance[4]))} m, ${inside}.` +
    (b.clouds.length ? ` The robots are also drawn at ${b.clouds.length} steps along the way.` : ''));
  const growth = (name, values, unit, scale = 1) => {
    const half = Math.floor(n / 2);
    return `${name} from ${f(values[0] * scale)} ${unit} at the start to ${f(values[half] * scale)} ${unit} halfway (step ${half}) and ${f(values[n] * scale)} ${unit} at the end`;
  };
  plots['position-std'].describe(
    `The propagated standard deviations over ${n} steps: ${growth('σx', b.std[0], 'm')}; ${growth('σy', b.std[1], 'm')}. ` +
    `The robots' spread at the end: σx = ${f(Math.sqrt(b.sampleCovariance[0]))} m, σy = ${f(Math.sqrt(b.sampleCovariance[4]))} m.`);
  plots['heading-std'].describe(
    `The propagated heading standard deviation over ${n} steps: ${growth('σθ', b.std[2], '°', 1 / degrees)}. ` +
    `The robots' spread at the end: ${f(Math.sqrt(b.sampleCovariance[8]) / degrees)}°.`);
  describeTable(b);
}

function describeShape(s) {
  switch (s.kind) {
    case 'line': return `straight line of ${fmt(s.length)} m`;
    case 'circle': return `${s.direction} circle of radius ${fmt(s.radius)} m`;
    case 'square': return `${s.direction} square of side ${fmt(s.side)} m`;
    case 'figure-eight': return `figure eight of radius ${fmt(s.radius)} m`;
    default: return `path through your ${s.points.length} points`;
  }
}

/** The path view while a drawn path has fewer than two points: the points alone. */
/**
 * The part of the plane the path plot keeps in view while the reader draws: a 6 m square
 * round the origin and a metre round every point, so that there is room to click the
 * next one.
 */
function drawingRoom(points) {
  if (ui.shape.value !== 'polyline') return [[], []];
  return [0, 1].map((i) => [-1, 5, ...points.flatMap((p) => [p[i] - 1, p[i] + 1])]);
}

function drawPointsOnly() {
  const [xs, ys] = drawingRoom(drawn);
  pathView.show(pathSeries({ points: drawn }), [xs], [ys]);
  plots.path.describe(`No path yet: ${drawn.length} point${drawn.length === 1 ? '' : 's'} drawn, at least two are needed.`);
  const series = stdSeries();
  show(plots['position-std'], overSteps('σ (m)', series.position));
  show(plots['heading-std'], overSteps('σθ (°)', series.heading));
  for (const name of ['position-std', 'heading-std']) plots[name].describe('No path yet: draw at least two points.');
  byId('covariance-table').tBodies[0].replaceChildren();
}

function computeSystematic(s) {
  const run = estlab.odometrySystematic(JSON.stringify(s.params), JSON.stringify(s.errors));
  try {
    return {
      odometry: [0, 1].map((i) => run.odometry(i)),
      truth: [0, 1, 2].map((i) => run.truth(i)),
      finalError: run.finalError(),
    };
  } finally {
    run.free();
  }
}

/** The series of the systematic plot: the two paths (x, y arrays), their start and ends. */
function systematicSeries([ox, oy] = [[], []], [tx, ty] = [[], []]) {
  const n = ox.length - 1;
  return [
    styled(line('odometry', ox, oy, colours.odometry, { name: "the odometry's path (dotted)" }), dashes.odometry, 2),
    styled(line('truth', tx, ty, colours.truth, { name: "the robot's path (solid)" }), dashes.truth, 1.5),
    markers('start', 'start', n >= 0 ? [[ox[0], oy[0]]] : [], colours.truth, 'triangle', 11),
    markers('ends', 'the ends', n >= 0 ? [[ox[n], oy[n]], [tx[n], ty[n]]] : [], '#1d2125', 'circle', 7),
  ];
}

function drawSystematic(r, s) {
  const [ox, oy] = r.odometry;
  const [tx, ty] = r.truth;
  const n = ox.length - 1;
  show(plots.systematic, plane(plots.systematic, systematicSeries(r.odometry, r.truth), [ox, tx], [oy, ty]));
  const [dx, dy, dth] = r.finalError;
  const words = `After ${n} steps the robot is ${f(Math.hypot(dx, dy))} m from where its odometry believes it is ` +
    `(Δx = ${f(dx)} m, Δy = ${f(dy)} m) and its heading is off by ${f(dth / degrees)}°, ` +
    `with E_d = ${s.errors.e_d} and E_b = ${s.errors.e_b}.`;
  plots.systematic.describe(`The ${describeShape(s.params.shape)}, as the odometry computes it and as the real robot drives it. ${words}`);
  setText(byId('systematic-summary'), words);
  byId('systematic-summary').dataset.error = JSON.stringify([...r.finalError]);
}

function computeUmbmark(s) {
  const test = estlab.odometryUmbmark(JSON.stringify(s.params), JSON.stringify(s.errors), JSON.stringify(s.umbmark));
  try {
    return {
      runs: test.runs(),
      directions: [0, 1].map((d) => ({
        odometry: [0, 1].map((i) => test.odometry(d, i)),
        truths: [0, 1].map((i) => test.truths(d, i)),
        errors: [0, 1, 2].map((i) => test.errors(d, i)),
        centre: test.centre(d),
        r: test.r(d),
      })),
      eMax: test.eMaxSyst(),
    };
  } finally {
    test.free();
  }
}

const directionNames = ['clockwise', 'counter-clockwise'];
const directionColours = [colours.estimate, colours.second];

function drawUmbmark(u, s) {
  const [cw, ccw] = u.directions;
  show(plots['umbmark-paths'], plane(plots['umbmark-paths'], [
    styled(line('square cw', cw.odometry[0], cw.odometry[1], colours.odometry, { name: "the odometry's squares (dotted)" }), dashes.odometry, 2),
    styled(line('square ccw', ccw.odometry[0], ccw.odometry[1], colours.odometry, { name: "the odometry's squares (dotted)" }), dashes.odometry, 2),
    line('runs cw', cw.truths[0], cw.truths[1], colours.estimate, { name: 'clockwise runs', lineStyle: { width: 1, color: colours.estimate, opacity: 0.8 } }),
    styled(line('runs ccw', ccw.truths[0], ccw.truths[1], colours.second, { name: 'counter-clockwise runs (dashed)', lineStyle: { width: 1, color: colours.second, opacity: 0.8 } }), dashes.estimate, 1),
    markers('start', 'start', [[0, 0]], colours.truth, 'triangle', 11),
  ], [cw.odometry[0], ccw.odometry[0], cw.truths[0], ccw.truths[0]], [cw.odometry[1], ccw.odometry[1], cw.truths[1], ccw.truths[1]]));

  const circle = [];
  for (let i = 0; i <= 96; i++) circle.push([u.eMax * Math.cos((2 * Math.PI * i) / 96), u.eMax * Math.sin((2 * Math.PI * i) / 96)]);
  const errorSeries = u.directions.flatMap((d, i) => [
    markers(`errors ${i}`, `return errors, ${directionNames[i]}`, pairs(d.errors[0], d.errors[1]), directionColours[i], i === 0 ? 'circle' : 'triangle', 8, 5),
    markers(`centre ${i}`, `centre of gravity, ${directionNames[i]}`, [[...d.centre]], directionColours[i], 'diamond', 16, 7),
  ]);
  show(plots['umbmark-errors'], plane(plots['umbmark-errors'], [
    outlineSeries('e-max', 'E_max,syst round the start (dashed)', [{ coords: circle }], '#5f6b76', 1, 0.8, 2, 'dashed'),
    ...errorSeries,
    markers('origin', 'where every run should end', [[0, 0]], colours.truth, 'triangle', 11, 8),
  ], [cw.errors[0], ccw.errors[0], circle.map((p) => p[0])], [cw.errors[1], ccw.errors[1], circle.map((p) => p[1])]));

  const words = (d, i) => `${directionNames[i]}: centre of gravity (${f(d.centre[0])}, ${f(d.centre[1])}) m, r = ${f(d.r)} m`;
  plots['umbmark-paths'].describe(
    `The ${fmt(s.umbmark.side)} m square driven ${u.runs} times each way with E_d = ${s.errors.e_d}, E_b = ${s.errors.e_b} ` +
    `and the wheel noise above; the odometry believes every run ends at the start. ${words(cw, 0)}; ${words(ccw, 1)}.`);
  const range = (values) => `${f(Math.min(...values))} to ${f(Math.max(...values))}`;
  plots['umbmark-errors'].describe(
    `Return errors (true minus odometry) of ${u.runs} runs each way. Clockwise: x from ${range(cw.errors[0])} m, y from ${range(cw.errors[1])} m. ` +
    `Counter-clockwise: x from ${range(ccw.errors[0])} m, y from ${range(ccw.errors[1])} m. ${words(cw, 0)}; ${words(ccw, 1)}; ` +
    `E_max,syst = ${f(u.eMax)} m.`);
  const body = byId('umbmark-table').tBodies[0];
  body.replaceChildren(...u.directions.map((d, i) => row(directionNames[i], [
    [f(d.centre[0]), d.centre[0]], [f(d.centre[1]), d.centre[1]], [f(d.r), d.r],
  ], directionNames[i])));
  const eMax = byId('e-max');
  setText(eMax, `${f(u.eMax)} m`);
  eMax.dataset.value = String(u.eMax);
}

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
  const s = settings();
  const messages = [];
  const drawing = s.params.shape.kind === 'polyline';
  const noPath = drawing && !pointsProblem && points < 2;

  /**
   * Computes `view` anew when its `key` (what it depends on) changed, else redraws it
   * when asked to; a failure leaves its last plots, dimmed, and says why.
   */
  const run = (view, key, compute, draw, describe, redraw = false) => {
    if (key === view.key) {
      if (redraw || force) draw(view.result, s);
      return;
    }
    let result;
    try {
      result = compute(s);
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
    draw(result, s);
    describe?.(result, s);
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
      drawPointsOnly();
      show(plots.systematic, plane(plots.systematic, systematicSeries(), [[-1, 5]], [[-1, 5]]));
      plots.systematic.describe('No path yet: draw at least two points.');
      setText(byId('systematic-summary'), 'Draw a path of at least two points on the plot above.');
      delete byId('systematic-summary').dataset.error;
    }
  } else {
    // The ellipses' spacing and the clouds change what is computed (cloud_every); which
    // part of the plane is shown changes only the drawing.
    const changedView = belief.drawnView !== ui.mapView.value;
    belief.drawnView = ui.mapView.value;
    run(belief, JSON.stringify([s.params, s.robots, s.seed, ui.ellipseEvery.value, ui.clouds.checked]), computeBelief, drawBelief, describeBelief, changedView);
    run(systematic, JSON.stringify([s.params.shape, s.params.speed, s.params.wheel_base, s.errors]), computeSystematic, drawSystematic);
  }
  run(umbmark, JSON.stringify([s.params.speed, s.params.wheel_base, s.params.k_r, s.params.k_l, s.errors, s.umbmark]), computeUmbmark, drawUmbmark);

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
const controls = [...document.querySelectorAll('#odometry-controls :is(input, select):not(#points)')];
const initial = controls.map((control) => (control.type === 'checkbox' ? control.checked : control.value));
const initialSizes = { ...sizes };

/** Every setting back to what the page opened with (a path drawn stays, for later). */
function setDefaults() {
  controls.forEach((control, i) => {
    if (control.type === 'checkbox') control.checked = initial[i];
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
