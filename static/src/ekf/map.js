// The map of an EKF run: landmarks and paths on axes of equal scale, drawn as three
// charts laid one on the other, as they change at different rates. The data (landmarks,
// the true and the odometry-only path) changes with the data set; the run (estimate,
// 3-sigma ellipses, rejected readings) with every setting; the time step (the poses now
// and each reading's association) with the time slider. The paths differ in line style as
// well as colour: the truth solid, the estimate dashed, odometry dotted.
import { fmt } from '../format.js';
import { colours, dashes, extent, line, outlines, pairs, styled } from '../plots.js';

const star = 'path://M0,-10L2.9,-4 9.5,-3.1 4.7,1.5 5.9,8.1 0,5 -5.9,8.1 -4.7,1.5 -9.5,-3.1 -2.9,-4Z';
const grid = { left: 56, right: 20, top: 40, bottom: 44, outerBoundsMode: 'none' };
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

export class MapView {
  constructor(plot) {
    this.plot = plot;
    this.runLayer = plot.addOverlay();
    this.nowLayer = plot.addOverlay();
    /** 'auto' (enlarged until the typical ellipse is some pixels across) or a factor. */
    this.ellipseScale = 'auto';
    /** The factor the ellipses are drawn with now. */
    this.ellipseFactor = 1;
    /** Called with true when the reader zooms or pans, false when the zoom is reset. */
    this.onZoom = () => {};
    plot.chart.on('datazoom', () => this.onZoom(true));
  }

  /**
   * Axes that show every point with a metre as long on x as on y. The extent is rounded
   * out to a twentieth of the data's, so that a run that moves the estimate a little
   * keeps the axes (and the charts beneath need no redraw).
   */
  axesFor(xs, ys) {
    const chart = this.plot.chart;
    const width = chart.getWidth() - grid.left - grid.right;
    const height = chart.getHeight() - grid.top - grid.bottom;
    const rounded = ([low, high], step) => [Math.floor(low / step) * step, Math.ceil(high / step) * step];
    const [x0, x1] = rounded(extent(xs), this.step[0]);
    const [y0, y1] = rounded(extent(ys), this.step[1]);
    const perPixel = Math.max((x1 - x0) / width, (y1 - y0) / height) * 1.04 || 1;
    this.perPixel = perPixel;
    const [cx, cy] = [(x0 + x1) / 2, (y0 + y1) / 2];
    const labels = { showMinLabel: false, showMaxLabel: false };
    return {
      xAxis: { type: 'value', name: 'x (m)', nameLocation: 'middle', nameGap: 26, min: cx - (perPixel * width) / 2, max: cx + (perPixel * width) / 2, axisLabel: labels },
      yAxis: { type: 'value', name: 'y (m)', nameLocation: 'middle', nameGap: 36, min: cy - (perPixel * height) / 2, max: cy + (perPixel * height) / 2, axisLabel: labels },
    };
  }

  /** Puts every layer on `axes`, unless they already are; `unzoom` shows them whole again. */
  setAxes(axes, unzoom = false) {
    const key = JSON.stringify([axes.xAxis.min, axes.xAxis.max, axes.yAxis.min, axes.yAxis.max]);
    if (key === this.axesKey && !unzoom) return;
    this.axesKey = key;
    this.axes = axes;
    const dataZoom = unzoom ? zoom.map((z) => ({ ...z, start: 0, end: 100 })) : zoom;
    this.plot.update(unzoom ? { ...axes, dataZoom } : axes);
    const hidden = { grid, xAxis: { ...axes.xAxis, show: false }, yAxis: { ...axes.yAxis, show: false }, dataZoom };
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
    this.plot.set({
      animation: false,
      grid,
      legend: { top: 4, type: 'scroll' },
      tooltip: { trigger: 'item', formatter: (p) => `${p.seriesName}${Array.isArray(p.value) ? `: (${fmt(p.value[0])}, ${fmt(p.value[1])})` : ''}` },
      dataZoom: zoom,
      xAxis: { type: 'value' },
      yAxis: { type: 'value' },
      series: [
        styled(line('odometry only', odometry[0], odometry[1], colours.odometry, { name: 'odometry only (dotted)' }), dashes.odometry),
        styled(line('true', truth[0], truth[1], colours.truth, { name: 'true (solid)' }), dashes.truth),
        { id: 'landmarks', name: 'landmarks', type: 'scatter', data: pairs(landmarks[0], landmarks[1]), symbol: star, symbolSize: 14, itemStyle: { color: colours.landmark } },
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
    this.run = { estimate: pairs(estimate[0], estimate[1]), ellipses: measured(outlines(ellipses)), rejected };
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
      this.plot.update({ series: [{ id: 'ellipses', name: ellipsesName(factor) }] });
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
    this.nowLayer.setOption({
      series: [
        { id: 'associations', name: 'associations now', type: 'lines', coordinateSystem: 'cartesian2d', data: lines, silent: true },
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
