// The path plot of the odometry page: the path, its 3σ ellipses and the robots in two
// layers, so that a noise setting redraws only what the noise changes, and the room kept
// round the points of a path the reader draws.
import { colours, dashes, line, markers, outlineSeries, plane, styled } from '../plots.js';

/**
 * The series of a scatter of many points (`xy`: x, y, x, y, ... in a typed array, which
 * ECharts reads without a copy), drawn in one pass.
 */
function cloudSeries(id, name, xy, colour, size, opacity, z) {
  return { id, name, type: 'scatter', data: xy, dimensions: ['x', 'y'], symbolSize: size, large: true, largeThreshold: 200, silent: true, itemStyle: { color: colour, opacity }, z };
}

/**
 * The series of the path plot: always the same ones, empty where there is nothing to
 * draw (a series left out would leave a hole in the chart's option). The first three
 * change with the path, the rest with the noise too.
 *
 * @param {object} drawn what there is to draw (each part left out: none of it)
 * @param {ArrayLike<number>} [drawn.x] the path's x at every step
 * @param {ArrayLike<number>} [drawn.y] and its y
 * @param {number[][]} [drawn.points] the points the reader drew, [x, y]
 * @param {number} [drawn.every] the steps between the ellipses
 * @param {{ coords: number[][] }[]} [drawn.ellipses] the 3σ ellipses along the path (see `outlines`)
 * @param {ArrayLike<number>} [drawn.clouds] the robots along the way: x, y, x, y, ...
 * @param {ArrayLike<number>} [drawn.robots] the robots at the end: x, y, x, y, ...
 * @param {number} [drawn.count] how many robots there are
 * @param {{ coords: number[][] }[]} [drawn.finalEllipse] the 3σ ellipse at the end
 * @param {number[][]} [drawn.end] the odometry's end, [[x, y]]
 */
export function pathSeries({ x = [], y = [], points = [], every = 0, ellipses = [], clouds = [], robots = [], count = 0, finalEllipse = [], end = [] }) {
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

/** Whether two lists hold the same numbers. */
function sameNumbers(a, b) {
  return a.length === b.length && a.every((v, i) => v === b[i]);
}

/**
 * The path plot in two layers: the chart itself (axes, legend, the path, its start, the
 * points drawn) and a transparent one over it with what the noise changes (ellipses,
 * robots, the end). A noise setting moved without moving the axes redraws the upper
 * layer alone, which costs ECharts far less than the whole plot.
 */
export class PathView {
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

/**
 * The part of the plane the path plot keeps in view while the reader draws: a 6 m square
 * round the origin and a metre round every point, so that there is room to click the
 * next one.
 */
export function drawingRoom(points) {
  return [0, 1].map((i) => [-1, 5, ...points.flatMap((p) => [p[i] - 1, p[i] + 1])]);
}
