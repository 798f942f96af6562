// The map of an EKF run: landmarks and paths on axes of equal scale, drawn as three
// charts laid one on the other, as they change at different rates. The data (landmarks,
// the true and the odometry-only path) changes with the data set; the run (estimate,
// 3-sigma ellipses, rejected readings) with every setting; the time step (the poses now
// and each reading's association) with the time slider.
import { fmt } from '../format.js';
import { colours, line, pairs } from '../plots.js';

const star = 'path://M0,-10L2.9,-4 9.5,-3.1 4.7,1.5 5.9,8.1 0,5 -5.9,8.1 -4.7,1.5 -9.5,-3.1 -2.9,-4Z';
const grid = { left: 56, right: 20, top: 40, bottom: 44, outerBoundsMode: 'none' };
const zoom = [
  { type: 'inside', xAxisIndex: 0, filterMode: 'none' },
  { type: 'inside', yAxisIndex: 0, filterMode: 'none' },
];

/** The series of a run: the estimated path, its 3-sigma ellipses, the rejected readings. */
function runSeries(estimate, ellipses, rejected) {
  return [
    { ...line('estimate', [], [], colours.estimate), data: estimate },
    { id: 'ellipses', name: '3σ ellipses', type: 'lines', coordinateSystem: 'cartesian2d', polyline: true, silent: true, data: ellipses, lineStyle: { color: colours.estimate, width: 1, opacity: 0.6 } },
    // Drawn as one shape when there are many, as there are when Q is too small (a
    // built-in symbol: a custom path in this mode brings Chromium down).
    { id: 'rejected', name: 'rejected readings', type: 'scatter', data: rejected, symbol: 'diamond', symbolSize: 7, itemStyle: { color: colours.outlier }, large: true, largeThreshold: 100 },
  ];
}

/** The closed outlines in a flat [x, y, x, y, ..., NaN, NaN, ...] array. */
function outlines(flat) {
  const polygons = [];
  let current = [];
  for (let i = 0; i < flat.length; i += 2) {
    if (Number.isNaN(flat[i])) {
      if (current.length) polygons.push({ coords: current });
      current = [];
    } else {
      current.push([flat[i], flat[i + 1]]);
    }
  }
  return polygons;
}

function extent(arrays) {
  let [low, high] = [Infinity, -Infinity];
  for (const array of arrays) {
    for (const v of array) {
      if (v < low) low = v;
      if (v > high) high = v;
    }
  }
  return [low, high];
}

export class MapView {
  constructor(plot) {
    this.plot = plot;
    this.runLayer = plot.addOverlay();
    this.nowLayer = plot.addOverlay();
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
    const [cx, cy] = [(x0 + x1) / 2, (y0 + y1) / 2];
    const labels = { showMinLabel: false, showMaxLabel: false };
    return {
      xAxis: { type: 'value', name: 'x (m)', nameLocation: 'middle', nameGap: 26, min: cx - (perPixel * width) / 2, max: cx + (perPixel * width) / 2, axisLabel: labels },
      yAxis: { type: 'value', name: 'y (m)', nameLocation: 'middle', nameGap: 36, min: cy - (perPixel * height) / 2, max: cy + (perPixel * height) / 2, axisLabel: labels },
    };
  }

  /** Puts every layer on `axes`, unless they already are. */
  setAxes(axes) {
    const key = JSON.stringify([axes.xAxis.min, axes.xAxis.max, axes.yAxis.min, axes.yAxis.max]);
    if (key === this.axesKey) return;
    this.axesKey = key;
    this.plot.update(axes);
    const hidden = { grid, xAxis: { ...axes.xAxis, show: false }, yAxis: { ...axes.yAxis, show: false }, dataZoom: zoom };
    // A legend that is not shown, so that the base chart's legend toggles these series too.
    for (const layer of [this.runLayer, this.nowLayer]) layer.setOption({ animation: false, legend: { show: false }, ...hidden });
  }

  /** A new data set: its landmarks, true path and odometry-only path. */
  showData(landmarks, truth, odometry) {
    this.data = { landmarks, truth, odometry };
    this.axesKey = null;
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
        line('odometry only', odometry[0], odometry[1], colours.odometry),
        line('true', truth[0], truth[1], colours.truth),
        { id: 'landmarks', name: 'landmarks', type: 'scatter', data: pairs(landmarks[0], landmarks[1]), symbol: star, symbolSize: 14, itemStyle: { color: colours.landmark } },
        // The legend's entries for the run, drawn on the run's layer.
        ...runSeries([], [], []),
      ],
    });
  }

  /** A new run over the same data: the estimate, its ellipses and the rejected readings. */
  showRun(estimate, ellipses, rejected) {
    const { landmarks, truth, odometry } = this.data;
    this.setAxes(this.axesFor(
      [landmarks[0], truth[0], odometry[0], estimate[0]],
      [landmarks[1], truth[1], odometry[1], estimate[1]],
    ));
    this.runLayer.setOption({ series: runSeries(pairs(estimate[0], estimate[1]), outlines(ellipses), rejected) });
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
