// The belief view of the odometry page: the covariance the odometry propagates along the
// path, beside many robots whose wheels really slip. The path plot with the 3σ ellipses
// and the robots (path.js), the standard deviations over the steps, propagated and
// sampled, and the table of the last step, the propagated covariance beside the robots'.
import { wrap } from '../angles.js';
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { colours, dashes, ellipseAxes, ellipseSpacing, line, outlineXY, outlines, styled } from '../plots.js';
import { PathView, drawingRoom, pathSeries } from './path.js';
import { degrees } from './settings.js';
import { View, describeShape, f, overSteps, row, show } from './view.js';

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
 * The covariance entries shown in the table: [label, row, column].
 *
 * @type {[string, number, number][]}
 */
const entries = [
  ['Σ<sub>xx</sub> (m²)', 0, 0],
  ['Σ<sub>xy</sub> (m²)', 0, 1],
  ['Σ<sub>yy</sub> (m²)', 1, 1],
  ['Σ<sub>xθ</sub> (m rad)', 0, 2],
  ['Σ<sub>yθ</sub> (m rad)', 1, 2],
  ['Σ<sub>θθ</sub> (rad²)', 2, 2],
];

const percent = (share) => `${fmt(100 * share, 4)} %`;

function describeTable(b) {
  const body = byId('covariance-table', HTMLTableElement).tBodies[0];
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

/**
 * The belief view (#belief-view): of the page's plots, it draws `path`, `position-std`
 * and `heading-std`. `ui`: the controls of what it draws: the steps between ellipses
 * (`ellipseEvery`), whether the robots are drawn along the way (`clouds`), and the part
 * of the plane shown (`mapView`).
 */
export class BeliefView extends View {
  constructor(estlab, plots, ui) {
    super('belief', estlab, plots);
    this.ui = ui;
    this.pathView = new PathView(plots.path);
    /** The part of the plane the path plot was last drawn for (`mapView`'s value). */
    this.drawnView = null;
  }

  /** The steps between ellipses (and clouds) along a path of `steps` steps. */
  ellipseEvery(steps) {
    const chosen = this.ui.ellipseEvery.value;
    return chosen === 'auto' ? ellipseSpacing(steps) : Number(chosen);
  }

  /** Propagation and robots for `s`, taken out of wasm at once. */
  compute(s) {
    const { estlab } = this;
    const json = JSON.stringify(s.params);
    const run = estlab.propagateOdometry(json);
    try {
      const steps = run.steps();
      const every = this.ellipseEvery(steps);
      const cloudEvery = this.ui.clouds.checked ? every : 0;
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

  draw(b, s) {
    const { plots } = this;
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
    const end = this.ui.mapView.value === 'end';
    const drawing = s.params.shape.kind === 'polyline';
    const points = drawing ? s.params.shape.points : [];
    const room = drawing ? drawingRoom(points) : [[], []];
    const axesX = end ? [lx, fx, [b.finalPose[0]]] : [x, ex, lx, fx, cx, room[0]];
    const axesY = end ? [ly, fy, [b.finalPose[1]]] : [y, ey, ly, fy, cy, room[1]];
    this.pathView.show(pathSeries({
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

  describe(b, s) {
    const { plots } = this;
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

  /** The view while a drawn path has fewer than two points (`points`): the points alone. */
  drawPointsOnly(points) {
    const { plots } = this;
    const [xs, ys] = drawingRoom(points);
    this.pathView.show(pathSeries({ points }), [xs], [ys]);
    plots.path.describe(`No path yet: ${points.length} point${points.length === 1 ? '' : 's'} drawn, at least two are needed.`);
    const series = stdSeries();
    show(plots['position-std'], overSteps('σ (m)', series.position));
    show(plots['heading-std'], overSteps('σθ (°)', series.heading));
    for (const name of ['position-std', 'heading-std']) plots[name].describe('No path yet: draw at least two points.');
    byId('covariance-table', HTMLTableElement).tBodies[0].replaceChildren();
  }
}
