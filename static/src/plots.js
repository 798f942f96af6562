// Plots with ECharts: one chart per <figure class="plot">, each with buttons that save it
// as PNG or SVG for a report.
import * as echarts from 'echarts/core';
import { LineChart, LinesChart, ScatterChart } from 'echarts/charts';
import {
  DataZoomComponent,
  GridComponent,
  LegendComponent,
  TooltipComponent,
} from 'echarts/components';
import { CanvasRenderer, SVGRenderer } from 'echarts/renderers';
import { download } from './controls.js';
import { fmt } from './format.js';

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

export class Plot {
  /** `figure` holds a <figcaption> and a <div class="chart">; `file` names saved files. */
  constructor(figure, file) {
    this.figure = figure;
    this.name = file;
    this.element = figure.querySelector('.chart');
    this.chart = echarts.init(this.element, null, { renderer: 'canvas' });
    // Reachable from the page (and its tests) through the element it draws in.
    this.element.plot = this;
    new ResizeObserver(() => this.chart.resize()).observe(this.element);
    const buttons = document.createElement('div');
    buttons.className = 'save';
    // The caption's own text, before the buttons join it: what a screen reader names.
    const caption = figure.querySelector('figcaption').textContent.trim();
    for (const [label, save] of [['PNG', () => this.savePng()], ['SVG', () => this.saveSvg()]]) {
      const button = document.createElement('button');
      button.type = 'button';
      button.textContent = label;
      button.title = `Save the plot "${caption}" as ${label}`;
      button.setAttribute('aria-label', button.title);
      button.addEventListener('click', save);
      buttons.append(button);
    }
    figure.querySelector('figcaption').append(buttons);
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
    this.pending = [[option, { replaceMerge: ['series'] }]];
    if (this.visible) this.flush();
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
    if (!this.stack) {
      this.stack = document.createElement('div');
      this.stack.className = 'stack';
      this.element.replaceWith(this.stack);
      this.stack.append(this.element);
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
    return [...this.chart.getOption().series.filter((s) => !covered.has(s.id)), ...above];
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

/** A line over time: x increases, so it can be thinned to the pixels it covers. */
export function timeLine(name, t, ys, colour, extra = {}) {
  return line(name, t, ys, colour, { sampling: 'lttb', ...extra });
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
export function overTime(yName, series, yAxis = {}) {
  return {
    animation: false,
    // The margins are fixed: measuring the labels to fit them costs a redraw dearly.
    grid: { left: 64, right: 20, top: 40, bottom: 44, outerBoundsMode: 'none' },
    legend: { top: 4, type: 'scroll' },
    tooltip: {
      trigger: 'axis',
      formatter: (items) => {
        const shown = items.filter((item) => !String(item.seriesId).startsWith('band '));
        if (!shown.length) return '';
        const t = fmt(shown[0].value[0]);
        return [`t = ${t} s`, ...shown.map((item) => `${item.marker}${item.seriesName}: ${fmt(item.value[1])}`)].join('<br>');
      },
    },
    xAxis: { type: 'value', name: 't (s)', nameLocation: 'middle', nameGap: 28, min: 'dataMin', max: 'dataMax' },
    yAxis: { type: 'value', name: yName, scale: true, ...yAxis },
    dataZoom: [{ type: 'inside', filterMode: 'none' }],
    series,
  };
}
