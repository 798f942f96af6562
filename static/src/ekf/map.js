// The map of an EKF run: landmarks and paths on axes of equal scale, drawn as three
// charts laid one on the other, as they change at different rates. The data (landmarks,
// the true and the odometry-only path) changes with the data set; the run (estimate,
// 3-sigma ellipses, rejected readings) with every setting; the time step (the poses now
// and each reading's association) with the time slider. The paths differ in line style as
// well as colour: the truth solid, the estimate dashed, odometry dotted.
//
// On a box taller than wide (a phone held upright), a map much wider than tall (o3's
// long room) would be a thin strip across it: it is drawn turned a quarter
// counter-clockwise instead, x running up and y to the left (a rotation, not a mirror:
// the paths turn the way they do), and `turned` says so. The layers' data are in the
// screen's order then ([y, x]); `place` puts a point of the plane there.
import { fmt } from '../format.js';
import { colours, dashes, extent, line, outlines, pairs, styled } from '../plots.js';

const star = 'path://M0,-10L2.9,-4 9.5,-3.1 4.7,1.5 5.9,8.1 0,5 -5.9,8.1 -4.7,1.5 -9.5,-3.1 -2.9,-4Z';
/** The margins of the map; the top grows with the legend's rows (see plots.js's legends). */
const margins = { left: 56, right: 20, top: 40, bottom: 44, outerBoundsMode: 'none' };
const zoom = [
  { type: 'inside', xAxisIndex: 0, filterMode: 'none' },
  { type: 'inside', yAxisIndex: 0, filterMode: 'none' },
];

/** The legend's name of the ellipses drawn `factor` times their size. */
const ellipsesName = (factor) => (factor === 1 ? '3σ ellipses' : `3σ ellipses, drawn ×${factor}`);

/** The factors the ellipses may be drawn enlarged by. */
export const ellipseFactors = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000];

/** The series of a run: the estimated path, its 3-sigma ellipses, the rejected readings. */
function runSeries(estimate, ellipses, rejected, factor = 1) {
  return [
    { ...styled(line('estimate', [], [], colours.estimate, { name: 'estimate (dashed)' }), dashes.estimate), data: estimate },
    { id: 'ellipses', name: ellipsesName(factor), type: 'lines', coordinateSystem: 'cartesian2d', polyline: true, silent: true, data: ellipses, lineStyle: { color: colours.estimate, width: 1, opacity: 0.6 } },
    // Drawn as one shape when there are many, as there are when Q is too small (a
    // built-in symbol: a custom path in this mode brings Chromium down).
    { id: 'rejected', name: 'rejected readings', type: 'scatter', data: rejected, symbol: 'diamond', symbolSize: 7, itemStyle: { color: colours.outlier }, large: true, largeThreshold: 100 },
  ];
}

/**
 * The outlines with their centres (the mean of their vertices, the closing one not
 * counted: the centre of an ellipse traced evenly) and sizes (the largest distance of a
 * vertex from the centre).
 */
function measured(polygons) {
  return polygons.map(({ coords }) => {
    const [first, last] = [coords[0], coords[coords.length - 1]];
    const m = coords.length > 1 && first[0] === last[0] && first[1] === last[1] ? coords.length - 1 : coords.length;
    let [cx, cy] = [0, 0];
    for (let i = 0; i < m; i++) [cx, cy] = [cx + coords[i][0], cy + coords[i][1]];
    [cx, cy] = [cx / m, cy / m];
    let radius = 0;
    for (const [x, y] of coords) radius = Math.max(radius, Math.hypot(x - cx, y - cy));
    return { coords, centre: [cx, cy], radius };
  });
}

/** The outlines drawn `factor` times their size about their centres. */
function enlarged(outlines, factor) {
  return outlines.map(({ coords, centre: [cx, cy] }) => ({
    coords: factor === 1 ? coords : coords.map(([x, y]) => [cx + factor * (x - cx), cy + factor * (y - cy)]),
  }));
}

function median(values) {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted.length ? sorted[Math.floor(sorted.length / 2)] : 0;
}

/** How much better a turned map must fit to be turned: not for a map about square. */
const TURN_GAIN = 1.5;

export class MapView {
  constructor(plot) {
    this.plot = plot;
    /** Whether the map is drawn turned a quarter (see the top of this file). */
    this.turned = false;
    this.runLayer = plot.addOverlay();
    this.nowLayer = plot.addOverlay();
    /**
     * 'auto' (enlarged until the typical ellipse is some pixels across) or a factor.
     *
     * @type {'auto' | number}
     */
    this.ellipseScale = 'auto';
    /** The factor the ellipses are drawn with now. */
    this.ellipseFactor = 1;
    /**
     * Called with true when the reader zooms or pans, false when the zoom is reset.
     *
     * @type {(zoomed: boolean) => void}
     */
    this.onZoom = () => {};
    plot.chart.on('datazoom', () => this.onZoom(true));
  }

  /**
   * Axes that show every point with a metre as long on x as on y. The extent is rounded
   * out to a twentieth of the data's, so that a run that moves the estimate a little
   * keeps the axes (and the charts beneath need no redraw).
   */
  axesFor(xs, ys) {
    const [width, height] = this.area();
    const rounded = ([low, high], step) => [Math.floor(low / step) * step, Math.ceil(high / step) * step];
    // The screen's horizontal and vertical: y and x on a turned map.
    const [hs, vs, steps] = this.turned ? [ys, xs, [this.step[1], this.step[0]]] : [xs, ys, this.step];
    const [x0, x1] = rounded(extent(hs), steps[0]);
    const [y0, y1] = rounded(extent(vs), steps[1]);
    const perPixel = Math.max((x1 - x0) / width, (y1 - y0) / height) * 1.04 || 1;
    this.perPixel = perPixel;
    const [cx, cy] = [(x0 + x1) / 2, (y0 + y1) / 2];
    const labels = { showMinLabel: false, showMaxLabel: false };
    const [across, up] = this.turned ? ['y (m), to the left', 'x (m)'] : ['x (m)', 'y (m)'];
    return {
      xAxis: { type: 'value', name: across, inverse: this.turned, nameLocation: 'middle', nameGap: 26, min: cx - (perPixel * width) / 2, max: cx + (perPixel * width) / 2, axisLabel: labels },
      yAxis: { type: 'value', name: up, nameLocation: 'middle', nameGap: 36, min: cy - (perPixel * height) / 2, max: cy + (perPixel * height) / 2, axisLabel: labels },
    };
  }

  /**
   * Whether the data set shown fits its box clearly better turned: drawn larger by
   * TURN_GAIN at least (the steps are a twentieth of the extents).
   */
  fitsTurned() {
    const [width, height] = this.area();
    const scale = (across, up) => Math.min(width / across, height / up);
    return scale(this.step[1], this.step[0]) > TURN_GAIN * scale(this.step[0], this.step[1]);
  }

  /**
   * The plot area's width and height in pixels, as laid out now (the chart learns a new
   * size a moment after a window's resize event, which redraws the map).
   */
  area() {
    // Before the first data the plot has no grid yet: the margins without the legend's rows.
    const { element, grid = margins } = this.plot;
    return [element.clientWidth - grid.left - grid.right, element.clientHeight - grid.top - grid.bottom];
  }

  /** A point [x, y] of the plane where the chart draws it: [y, x] on a turned map. */
  place(point) {
    return this.turned ? [point[1], point[0]] : point;
  }

  /** The points of a path ([xs, ys]) as the chart draws them. */
  path([xs, ys]) {
    return this.turned ? pairs(ys, xs) : pairs(xs, ys);
  }

  /** Puts every layer on `axes`, unless they already are; `unzoom` shows them whole again. */
  setAxes(axes, unzoom = false) {
    const key = JSON.stringify([axes.xAxis.min, axes.xAxis.max, axes.yAxis.min, axes.yAxis.max]);
    if (key === this.axesKey && !unzoom) return;
    this.axesKey = key;
    this.axes = axes;
    const dataZoom = unzoom ? zoom.map((z) => ({ ...z, start: 0, end: 100 })) : zoom;
    this.plot.update(unzoom ? { ...axes, dataZoom } : axes);
    const hidden = { grid: this.plot.grid, xAxis: { ...axes.xAxis, show: false }, yAxis: { ...axes.yAxis, show: false }, dataZoom };
    // A legend that is not shown, so that the base chart's legend toggles these series too.
    for (const layer of [this.runLayer, this.nowLayer]) layer.setOption({ animation: false, legend: { show: false }, ...hidden });
    if (unzoom) this.onZoom(false);
  }

  /** Back to the whole map, as the axes show it before any zoom. */
  resetZoom() {
    if (this.axes) this.setAxes(this.axes, true);
  }

  /** A new data set: its landmarks, true path and odometry-only path. */
  showData(landmarks, truth, odometry) {
    this.data = { landmarks, truth, odometry };
    this.axesKey = null;
    this.unzoom = true;
    this.ellipseFactor = 1;
    const size = (arrays) => { const [low, high] = extent(arrays); return (high - low) / 20 || 1; };
    this.step = [size([landmarks[0], truth[0], odometry[0]]), size([landmarks[1], truth[1], odometry[1]])];
    this.turned = this.fitsTurned();
    this.plot.set({
      animation: false,
      grid: margins,
      legend: {},
      tooltip: {
        trigger: 'item',
        formatter: (p) => {
          if (!Array.isArray(p.value)) return p.seriesName;
          const [x, y] = this.place(p.value);
          return `${p.seriesName}: (${fmt(x)}, ${fmt(y)})`;
        },
      },
      dataZoom: zoom,
      xAxis: { type: 'value' },
      yAxis: { type: 'value' },
      series: [
        { ...styled(line('odometry only', [], [], colours.odometry, { name: 'odometry only (dotted)' }), dashes.odometry), data: this.path(odometry) },
        { ...styled(line('true', [], [], colours.truth, { name: 'true (solid)' }), dashes.truth), data: this.path(truth) },
        { id: 'landmarks', name: 'landmarks', type: 'scatter', data: this.path(landmarks), symbol: star, symbolSize: 14, itemStyle: { color: colours.landmark } },
        // The legend's entries for the run, drawn on the run's layer.
        ...runSeries([], [], []),
      ],
    });
  }

  /**
   * A new run over the same data: the estimate, its ellipses (`ellipses`: flat, as
   * EkfRun.ellipses gives them) and the rejected readings.
   */
  showRun(estimate, ellipses, rejected) {
    const { landmarks, truth, odometry } = this.data;
    this.setAxes(this.axesFor(
      [landmarks[0], truth[0], odometry[0], estimate[0]],
      [landmarks[1], truth[1], odometry[1], estimate[1]],
    ), this.unzoom);
    this.unzoom = false;
    const placed = outlines(ellipses).map(({ coords }) => ({ coords: coords.map((point) => this.place(point)) }));
    this.run = { estimate: this.path(estimate), ellipses: measured(placed), rejected: rejected.map((point) => this.place(point)) };
    this.drawRun();
  }

  /** The run's layer, with the ellipses as large as `ellipseScale` says. */
  drawRun() {
    const { estimate, ellipses, rejected } = this.run;
    // On accurate data the ellipses are far smaller than a pixel at the whole map's
    // scale: 'auto' draws them enlarged, by a round factor, until the typical one is 8
    // pixels across, and the legend says by how much. The factor stays while the typical
    // ellipse drawn with it is 4 to 100 pixels across, so that a setting moved a little
    // does not change it (nor the legend, which costs a redraw of the map beneath).
    const pixels = (2 * median(ellipses.map((e) => e.radius))) / this.perPixel;
    let factor = this.ellipseScale;
    if (factor === 'auto') {
      const kept = this.ellipseFactor * pixels;
      factor = kept >= 4 && kept <= 100 ? this.ellipseFactor : ellipseFactors.find((f) => f * pixels >= 8) ?? ellipseFactors.at(-1);
    }
    if (factor !== this.ellipseFactor) {
      this.ellipseFactor = factor;
      // The base chart's legend names the ellipses too.
      this.plot.rename('ellipses', ellipsesName(factor));
    }
    this.runLayer.setOption({ series: runSeries(estimate, enlarged(ellipses, factor), rejected, factor) });
  }

  /** How the ellipses are drawn now: the factor, and the typical size at true scale. */
  ellipseSize() {
    const across = this.run ? 2 * median(this.run.ellipses.map((e) => e.radius)) : 0;
    return { factor: this.ellipseFactor, across };
  }

  /** The time step on the overlay: `lines` from the estimate `at`, and the true pose. */
  showNow(at, truth, lines) {
    at = this.place(at);
    truth = this.place(truth);
    const placed = lines.map((l) => ({ ...l, coords: l.coords.map((point) => this.place(point)) }));
    this.nowLayer.setOption({
      series: [
        { id: 'associations', name: 'associations now', type: 'lines', coordinateSystem: 'cartesian2d', data: placed, silent: true },
        {
          id: 'now',
          name: 'pose now',
          type: 'scatter',
          symbolSize: 10,
          silent: true,
          data: [
            { value: at, itemStyle: { color: colours.estimate } },
            { value: truth, itemStyle: { color: colours.truth } },
          ],
        },
      ],
    });
  }
}
