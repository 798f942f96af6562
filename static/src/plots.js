// Plots with ECharts: one chart per <figure class="plot">, each with buttons that save it
// as PNG or SVG for a report, and a line of text that says what it shows (the canvas
// itself says nothing to a screen reader).
import * as echarts from 'echarts/core';
import { LineChart, LinesChart, ScatterChart } from 'echarts/charts';
import {
  DataZoomComponent,
  GridComponent,
  LegendComponent,
  TooltipComponent,
} from 'echarts/components';
import { CanvasRenderer, SVGRenderer } from 'echarts/renderers';
import { download, setText } from './controls.js';
import { fmt } from './format.js';

/** @typedef {import('echarts').SeriesOption} SeriesOption */

echarts.use([
  LineChart,
  LinesChart,
  ScatterChart,
  DataZoomComponent,
  GridComponent,
  LegendComponent,
  TooltipComponent,
  CanvasRenderer,
  SVGRenderer,
]);

export const colours = {
  truth: '#2e7d32',
  estimate: '#c62828',
  odometry: '#1565c0',
  measurement: '#6d6d6d',
  landmark: '#212121',
  outlier: '#ef6c00',
  band: '#c62828',
  second: '#6a1b9a',
  third: '#00838f',
};

/**
 * Line styles, so that no line is told from another by its colour alone: the truth is
 * solid, the estimate dashed, odometry dotted. The legends say so in words too.
 */
export const dashes = {
  truth: 'solid',
  estimate: [6, 3],
  odometry: [1.5, 3],
};

export class Plot {
  /** `figure` holds a <figcaption> and a <div class="chart">; `file` names saved files. */
  constructor(figure, file) {
    this.figure = figure;
    this.name = file;
    this.element = figure.querySelector('.chart');
    // The canvas is for the eyes; the summary below it (see describe) is the text.
    this.element.setAttribute('aria-hidden', 'true');
    this.chart = echarts.init(this.element, null, { renderer: 'canvas' });
    // Reachable from the page (and its tests) through the element it draws in.
    this.element.plot = this;
    new ResizeObserver(() => {
      this.chart.resize();
      this.refitLegend();
    }).observe(this.element);
    const buttons = document.createElement('div');
    buttons.className = 'save';
    // The caption's own text, before the buttons join it: what a screen reader names.
    const caption = figure.querySelector('figcaption').textContent.trim();
    /** @type {[string, () => void][]} */
    const saves = [['PNG', () => this.savePng()], ['SVG', () => this.saveSvg()]];
    for (const [label, save] of saves) {
      const button = document.createElement('button');
      button.type = 'button';
      button.textContent = label;
      button.title = `Save the plot "${caption}" as ${label}`;
      button.setAttribute('aria-label', button.title);
      button.addEventListener('click', save);
      buttons.append(button);
    }
    figure.querySelector('figcaption').append(buttons);
    this.summary = document.createElement('p');
    this.summary.className = 'plot-summary';
    figure.append(this.summary);
    // A plot out of view keeps its newest option and draws it when it comes into view:
    // moving a control then costs only the plots the reader can see.
    this.visible = true;
    this.pending = [];
    new IntersectionObserver(([entry]) => {
      this.visible = entry.isIntersecting;
      if (this.visible) this.flush();
    }).observe(this.element);
  }

  /**
   * Shows `option`. Series are matched by id and keep their models (and components, such
   * as the axes, are merged), which costs far less than building the chart anew.
   */
  set(option) {
    const shown = option.legend && option.legend.show !== false ? withLegend(this, option) : option;
    // What the legend needs to be laid out again: the margins it was added to, its entries,
    // and the series' names (by id) they list.
    this.legend = shown === option ? null
      : { base: option.grid, entries: shown.legend.data, names: new Map(shown.series.map((s) => [s.id, s.name])) };
    if (shown.grid) this.grid = shown.grid;
    this.pending = [[shown, { replaceMerge: ['series'] }]];
    if (this.visible) this.flush();
  }

  /**
   * At a new width the legend may wrap onto more rows or fewer: the plot area (and the
   * overlays', which share its axes) moves to stay clear of it.
   */
  refitLegend() {
    if (!this.legend || !this.grid) return;
    const grid = legendGrid(this, this.legend.base, this.legend.entries);
    if (grid.top === this.grid.top) return;
    this.grid = grid;
    this.update({ grid });
    for (const overlay of this.overlays ?? []) overlay.setOption({ grid });
  }

  /** Says in words what the plot shows (a summary line; not shown, read by screen readers). */
  describe(text) {
    setText(this.summary, text);
  }

  /**
   * A vertical line at `x` (in the units of the x axis) across the plot, or none for
   * null. It is an element laid over the chart, not part of it: moving it redraws
   * nothing, and it follows the chart's zoom. Not in the saved images.
   */
  setMarker(x, title = '') {
    if (!this.marker) {
      this.ensureStack();
      this.marker = document.createElement('div');
      this.marker.className = 'marker';
      this.marker.setAttribute('aria-hidden', 'true');
      this.stack.append(this.marker);
      this.chart.on('rendered', () => this.placeMarker());
    }
    this.markerX = x;
    this.marker.title = title;
    this.placeMarker();
  }

  placeMarker() {
    const x = this.markerX;
    let px = null;
    if (x !== null && x !== undefined && this.grid) {
      try {
        px = this.chart.convertToPixel({ xAxisIndex: 0 }, x);
      } catch {
        px = null;
      }
    }
    const { left = 0, right = 0, top = 0, bottom = 0 } = this.grid ?? {};
    const shown = Number.isFinite(px) && px >= left - 0.5 && px <= this.chart.getWidth() - right + 0.5;
    this.marker.hidden = !shown;
    if (!shown) return;
    // Moved by a transform, on a layer of its own: the compositor moves it, and nothing
    // beneath it is painted again.
    this.marker.style.transform = `translateX(${px - 1}px)`;
    this.marker.style.top = `${top}px`;
    this.marker.style.bottom = `${bottom}px`;
    this.marker.dataset.x = String(x);
  }

  /** The chart in a positioned box, so that overlays and the marker can lie on it. */
  ensureStack() {
    if (this.stack) return;
    this.stack = document.createElement('div');
    this.stack.className = 'stack';
    this.element.replaceWith(this.stack);
    this.stack.append(this.element);
  }

  /**
   * Replaces the data of the series in `series` ([{ id, data }], ids of series the plot
   * has), keeping the rest of the option: far cheaper to draw than `set` when only the
   * numbers change. A plot out of view changes the option it waits to draw instead.
   */
  setData(series) {
    const byId = new Map(series.map((s) => [s.id, s]));
    // The last whole option waiting.
    const waiting = this.pending.findLast(([, how]) => how.replaceMerge);
    if (waiting) {
      waiting[0] = { ...waiting[0], series: waiting[0].series.map((s) => (byId.has(s.id) ? { ...s, ...byId.get(s.id) } : s)) };
    } else {
      // An earlier change of the same series' data, not drawn yet, is superseded.
      this.pending = this.pending.filter(([option, , data]) => !(data && option.series.every((s) => byId.has(s.id))));
      this.pending.push([{ series }, { notMerge: false }, true]);
    }
    if (this.visible) this.flush();
  }

  /**
   * Renames the series `id`, in the legend too (its entries are listed: see withLegend),
   * and keeps the plot area below the legend.
   */
  rename(id, name) {
    const old = this.legend.names.get(id);
    this.legend.names.set(id, name);
    const entries = this.legend.entries.map((entry) => (entry.name === old ? { ...entry, name } : entry));
    this.legend.entries = entries;
    this.update({ series: [{ id, name }], legend: { data: entries } });
    this.refitLegend();
  }

  /** Merges `option` into the current one (series matched by id). */
  update(option) {
    this.pending.push([option, { notMerge: false }]);
    if (this.visible) this.flush();
  }

  /**
   * A transparent chart laid over this one, with the same zoom (and legend), for what
   * changes more often than the rest: redrawing it leaves the charts beneath alone. The
   * caller keeps its axes the same as this chart's. Later overlays lie on earlier ones.
   */
  addOverlay() {
    if (!this.overlays) {
      this.ensureStack();
      this.chart.group = `overlays of ${this.name}`;
      this.overlays = [];
    }
    const div = document.createElement('div');
    div.className = 'overlay';
    this.stack.append(div);
    const overlay = echarts.init(div, null, { renderer: 'canvas' });
    new ResizeObserver(() => overlay.resize()).observe(div);
    overlay.group = this.chart.group;
    echarts.connect(this.chart.group);
    this.overlays.push(overlay);
    return overlay;
  }

  /** Draws what is pending now, in view or not: a page that is to be printed. */
  drawNow() {
    this.visible = true;
    this.flush();
  }

  /** Draws what is pending. */
  flush() {
    for (const [option, how] of this.pending) this.chart.setOption(option, how);
    this.pending = [];
  }

  /** What the chart shows, its overlays' series in place of any with the same id. */
  series() {
    this.flush();
    const above = (this.overlays ?? []).flatMap((overlay) => overlay.getOption().series ?? []);
    const covered = new Set(above.map((s) => s.id));
    // getOption gives every component as an array: the series too.
    const own = /** @type {SeriesOption[]} */ (this.chart.getOption().series);
    return [...own.filter((s) => !covered.has(s.id)), ...above];
  }

  savePng() {
    this.flush();
    // With overlays, every layer composed into one image on white.
    const background = this.overlays
      ? { backgroundColor: 'transparent', connectedBackgroundColor: '#fff' }
      : { backgroundColor: '#fff' };
    const url = this.chart.getConnectedDataURL({ type: 'png', pixelRatio: 2, ...background });
    const bytes = Uint8Array.from(atob(url.slice(url.indexOf(',') + 1)), (c) => c.charCodeAt(0));
    download(`${this.name}.png`, new Blob([bytes], { type: 'image/png' }));
  }

  saveSvg() {
    download(`${this.name}.svg`, this.svg(), 'image/svg+xml');
  }

  /** The chart rendered again as SVG, at its size on the page. */
  svg() {
    this.flush();
    const vector = echarts.init(null, null, {
      renderer: 'svg',
      ssr: true,
      width: this.chart.getWidth(),
      height: this.chart.getHeight(),
    });
    vector.setOption({ ...this.chart.getOption(), series: this.series(), backgroundColor: '#fff' });
    const svg = vector.renderToSVGString();
    vector.dispose();
    return svg;
  }
}

/** A plot for every <figure class="plot"> in `root`, by data-name; saved as `prefix-name`. */
export function plotsIn(root, prefix) {
  const plots = {};
  for (const figure of root.querySelectorAll('figure.plot')) {
    plots[figure.dataset.name] = new Plot(figure, `${prefix}-${figure.dataset.name}`);
  }
  return plots;
}

/** [[x0, y0], [x1, y1], ...] from two arrays. */
export function pairs(xs, ys) {
  const out = new Array(xs.length);
  for (let i = 0; i < xs.length; i++) out[i] = [xs[i], ys[i]];
  return out;
}

/**
 * The closed outlines (ellipses drawn by the wasm build) in a flat
 * [x, y, x, y, ..., NaN, NaN, ...] array, as the data of a `lines` series.
 */
export function outlines(flat) {
  const shapes = [];
  let current = [];
  for (let i = 0; i < flat.length; i += 2) {
    if (Number.isNaN(flat[i])) {
      if (current.length) shapes.push({ coords: current });
      current = [];
    } else {
      current.push([flat[i], flat[i + 1]]);
    }
  }
  return shapes;
}

/** A line through (xs, ys). */
export function line(name, xs, ys, colour, extra = {}) {
  return {
    id: name,
    name,
    type: 'line',
    data: pairs(xs, ys),
    showSymbol: false,
    lineStyle: { width: 1.5, color: colour },
    itemStyle: { color: colour },
    emphasis: { disabled: true },
    silent: true,
    ...extra,
  };
}

/**
 * A line over time: x increases, so a long one is thinned to the pixels it covers (a
 * short one is not: thinning costs more than it saves).
 */
export function timeLine(name, t, ys, colour, extra = {}) {
  return line(name, t, ys, colour, { sampling: t.length > 4000 ? 'lttb' : undefined, ...extra });
}

/** `style` (a line type: solid, dashed, dotted, or a dash array) for a series made by `line`. */
export function styled(series, style, width = 1.5) {
  return { ...series, lineStyle: { ...series.lineStyle, type: style, width } };
}

// ---------------------------------------------------------------------------------------
// Legends: every entry shown, wrapped onto as many rows as the chart's width needs (a
// paged legend hides entries behind "1/4", and cuts long names on a phone), with the plot
// area moved down below the last row. A line's entry is drawn in its line style, so that
// a solid and a dashed line of one colour have different icons.

/** How every legend is laid out: every size written out, as `legendRows` measures with them. */
const LEGEND = { type: 'plain', top: 4, left: 8, right: 8, padding: 5, itemGap: 10, itemWidth: 25, itemHeight: 14, textStyle: { fontSize: 12, fontFamily: 'sans-serif' } };
/** The gap between the legend's last row and the plot area (room for the top axis label). */
const BELOW_LEGEND = 12;

/**
 * Icons of line styles, drawn as filled bars 2 units high (kept in their aspect, they fill
 * the icon's width as a thin line): solid, dashed, dotted.
 */
const lineIcons = {
  solid: 'path://M0,0h24v2h-24z',
  dashed: 'path://M0,0h6v2h-6zm9,0h6v2h-6zm9,0h6v2h-6z',
  dotted: 'path://M0,0h2v2h-2zm5,0h2v2h-2zm5,0h2v2h-2zm5,0h2v2h-2zm5,0h2v2h-2z',
};

/** The line style of a series drawn as a line: solid, dashed or dotted; null for others (points). */
function lineKind(series) {
  const drawsLine = series.type === 'lines' || (series.type === 'line' && !series.showSymbol);
  if (!drawsLine) return null;
  const type = series.lineStyle?.type ?? 'solid';
  if (Array.isArray(type)) return type[0] >= 3 ? 'dashed' : 'dotted';
  return lineIcons[type] ? type : 'solid';
}

/**
 * The legend's entries: `names` (each once, in order; by default every series') with
 * the icon of the first series of each name in `series`.
 */
function legendEntries(series, names = series.map((s) => s.name)) {
  return [...new Set(names.filter((name) => name !== undefined))].map((name) => {
    const first = series.find((s) => s.name === name);
    const kind = first && lineKind(first);
    return kind ? { name, icon: lineIcons[kind] } : { name };
  });
}

let measurer = null;

/** The rows a legend of `entries` takes in a chart `width` pixels wide, wrapped as ECharts wraps them. */
function legendRows(width, entries) {
  measurer ??= document.createElement('canvas').getContext('2d');
  measurer.font = `${LEGEND.textStyle.fontSize}px ${LEGEND.textStyle.fontFamily}`;
  const room = width - LEGEND.left - LEGEND.right - 2 * LEGEND.padding;
  // A chart not laid out yet has no width: one row until it has (see refitLegend).
  if (!(room > 0)) return 1;
  let [rows, x] = [1, 0];
  for (const { name } of entries) {
    // The icon, a gap of 5 px, the text (rounded up: the chart's text measures alike).
    const item = LEGEND.itemWidth + 5 + Math.ceil(measurer.measureText(name).width);
    if (x > 0 && x + item > room) [rows, x] = [rows + 1, 0];
    x += item + LEGEND.itemGap;
  }
  return rows;
}

/** `grid` with its top just below a legend of `entries` at `plot`'s width. */
function legendGrid(plot, grid, entries) {
  // The width as laid out now (the chart learns a new one a moment after a resize).
  const rows = legendRows(plot.element.clientWidth, entries);
  const height = 2 * LEGEND.padding + rows * LEGEND.itemHeight + (rows - 1) * LEGEND.itemGap;
  return { ...grid, top: LEGEND.top + height + BELOW_LEGEND };
}

/**
 * `option` with its legend laid out as every legend is (see LEGEND), listing
 * `option.legend.data` (names) or else every series, and its grid's top below it.
 */
function withLegend(plot, option) {
  const names = option.legend.data?.map((entry) => entry.name ?? entry);
  const entries = legendEntries(option.series ?? [], names);
  return { ...option, legend: { ...LEGEND, data: entries }, grid: legendGrid(plot, option.grid, entries) };
}

/** The bounds `lower` and `upper` of a band, as two faint lines under one legend entry. */
export function band(name, t, lower, upper, colour) {
  const bound = { lineStyle: { width: 1, color: colour, opacity: 0.5 } };
  return [
    timeLine(name, t, lower, colour, { ...bound, id: `band ${name} low` }),
    timeLine(name, t, upper, colour, { ...bound, id: `band ${name} high` }),
  ];
}

/** Axes, legend, tooltip and zoom shared by the plots over time. */
export function overTime(yName, series, yAxis = {}, xAxis = {}) {
  return {
    animation: false,
    // The margins are fixed: measuring the labels to fit them costs a redraw dearly. The
    // y axis's title runs up its side, clear of the legend above the plot and of the
    // labels (short: fmt's few digits).
    grid: { left: 76, right: 20, top: 40, bottom: 44, outerBoundsMode: 'none' },
    legend: {},
    tooltip: {
      trigger: 'axis',
      formatter: (items) => {
        const shown = items.filter((item) => !String(item.seriesId).startsWith('band '));
        if (!shown.length) return '';
        const t = fmt(shown[0].value[0]);
        return [`t = ${t} s`, ...shown.map((item) => `${item.marker}${item.seriesName}: ${fmt(item.value[1])}`)].join('<br>');
      },
    },
    xAxis: { type: 'value', name: 't (s)', nameLocation: 'middle', nameGap: 28, min: 'dataMin', max: 'dataMax', ...xAxis },
    yAxis: {
      type: 'value',
      name: yName,
      nameLocation: 'middle',
      nameGap: 60,
      scale: true,
      axisLabel: { formatter: (v) => fmt(v, 3) },
      ...yAxis,
    },
    dataZoom: [{ type: 'inside', filterMode: 'none' }],
    series,
  };
}

/**
 * What a summary line says of `ys` (over `t`): the first and last value, the smallest and
 * largest, the mean, the mean absolute value and the largest absolute value with its time.
 */
export function stats(ys, t = null) {
  const n = ys.length;
  let [min, max, sum, sumAbs, maxAbs, at] = [Infinity, -Infinity, 0, 0, -1, 0];
  for (let i = 0; i < n; i++) {
    const v = ys[i];
    if (v < min) min = v;
    if (v > max) max = v;
    sum += v;
    sumAbs += Math.abs(v);
    if (Math.abs(v) > maxAbs) [maxAbs, at] = [Math.abs(v), i];
  }
  return {
    n,
    first: ys[0],
    last: ys[n - 1],
    min,
    max,
    mean: sum / n,
    meanAbs: sumAbs / n,
    maxAbs,
    maxAbsAt: t ? t[at] : at,
  };
}

// ---------------------------------------------------------------------------------------
// Plots in the plane: x and y in metres on axes of equal scale, with paths, closed
// outlines (ellipses) and marked points. The odometry page's and the odometry workbench's.

/** The margins of a plot in the plane. */
export const planeGrid = { left: 58, right: 16, top: 40, bottom: 44, outerBoundsMode: 'none' };

/**
 * The smallest and largest finite value of `arrays`.
 *
 * @returns {[number, number]}
 */
export function extent(arrays) {
  let [low, high] = [Infinity, -Infinity];
  for (const array of arrays) {
    for (const v of array) {
      if (v < low) low = v;
      if (v > high) high = v;
    }
  }
  return [low, high];
}

/**
 * Axes that show every point of `xs` and `ys` (lists of arrays) with a metre as long on
 * x as on y, in `plot`'s chart. The centre and the half-widths are rounded to a round
 * step, so that a small change of the data keeps the axes still (and a chart beneath an
 * upper layer need not be drawn again).
 */
function equalAxes(plot, grid, xs, ys) {
  const chart = plot.chart;
  const width = Math.max(1, chart.getWidth() - grid.left - grid.right);
  const height = Math.max(1, chart.getHeight() - grid.top - grid.bottom);
  let [x0, x1] = extent(xs);
  let [y0, y1] = extent(ys);
  if (!(x0 <= x1 && y0 <= y1)) [x0, x1, y0, y1] = [-1, 1, -1, 1];
  const step = 10 ** Math.floor(Math.log10(Math.max(x1 - x0, y1 - y0, 1e-9))) / 2;
  const round = (v) => Math.round(v / step) * step;
  const [cx, cy] = [round((x0 + x1) / 2), round((y0 + y1) / 2)];
  const half = (low, high, centre) => Math.ceil(Math.max(high - centre, centre - low) / step) * step;
  const perPixel = Math.max((2 * half(x0, x1, cx)) / width, (2 * half(y0, y1, cy)) / height, 1e-9) * 1.06;
  const labels = { showMinLabel: false, showMaxLabel: false, formatter: (v) => fmt(v, 3) };
  return {
    xAxis: { type: 'value', name: 'x (m)', nameLocation: 'middle', nameGap: 26, min: cx - (perPixel * width) / 2, max: cx + (perPixel * width) / 2, axisLabel: labels },
    yAxis: { type: 'value', name: 'y (m)', nameLocation: 'middle', nameGap: 40, min: cy - (perPixel * height) / 2, max: cy + (perPixel * height) / 2, axisLabel: labels },
  };
}

/**
 * The option of a plot in the plane showing every point of `xs` and `ys` (lists of
 * arrays), its legend listing `listed` (names; by default every series').
 */
export function plane(plot, series, xs, ys, listed = undefined) {
  const option = withLegend(plot, { animation: false, grid: planeGrid, legend: { data: listed }, series });
  return { ...option, ...equalAxes(plot, option.grid, xs, ys) };
}

/** The x and the y values of outlines (for the axes). */
export function outlineXY(shapes) {
  const xs = [];
  const ys = [];
  for (const { coords } of shapes) for (const [x, y] of coords) { xs.push(x); ys.push(y); }
  return [xs, ys];
}

/** A few marked points (start, end, centres). */
export function markers(id, name, data, colour, symbol, size, z = 8) {
  return { id, name, type: 'scatter', data, symbol, symbolSize: size, silent: true, itemStyle: { color: colour, borderColor: '#fff', borderWidth: 1 }, z };
}

/** The `lines` series of closed outlines. */
export function outlineSeries(id, name, shapes, colour, width, opacity, z, type = 'solid') {
  return { id, name, type: 'lines', coordinateSystem: 'cartesian2d', polyline: true, silent: true, data: shapes, lineStyle: { color: colour, width, opacity, type }, z };
}

/** The steps between the ellipses drawn along a path of `steps` steps: about twenty of them. */
export function ellipseSpacing(steps) {
  return Math.max(1, Math.round(steps / 20));
}

/** The half-axes of the k-sigma ellipse of a 2 x 2 covariance [[a, c], [c, d]] and the long one's angle. */
export function ellipseAxes(a, c, d, k = 3) {
  const mean = (a + d) / 2;
  const radius = Math.hypot((a - d) / 2, c);
  return {
    major: k * Math.sqrt(Math.max(0, mean + radius)),
    minor: k * Math.sqrt(Math.max(0, mean - radius)),
    angle: 0.5 * Math.atan2(2 * c, a - d),
  };
}
