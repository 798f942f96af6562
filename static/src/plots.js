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
    for (const [label, save] of [['PNG', () => this.savePng()], ['SVG', () => this.saveSvg()]]) {
      const button = document.createElement('button');
      button.type = 'button';
      button.textContent = label;
      button.title = `Save this plot as ${label}`;
      button.addEventListener('click', save);
      buttons.append(button);
    }
    figure.querySelector('figcaption').append(buttons);
  }

  /** Replaces the whole option. */
  set(option) {
    this.chart.setOption(option, { notMerge: true });
  }

  /** Merges `option` into the current one (series matched by id). */
  update(option) {
    this.chart.setOption(option, { notMerge: false, lazyUpdate: false });
  }

  /** What the chart shows now, for tests and exports. */
  series() {
    return this.chart.getOption().series;
  }

  savePng() {
    const url = this.chart.getDataURL({ type: 'png', pixelRatio: 2, backgroundColor: '#fff' });
    const bytes = Uint8Array.from(atob(url.slice(url.indexOf(',') + 1)), (c) => c.charCodeAt(0));
    download(`${this.name}.png`, new Blob([bytes], { type: 'image/png' }));
  }

  saveSvg() {
    download(`${this.name}.svg`, this.svg(), 'image/svg+xml');
  }

  /** The chart rendered again as SVG, at its size on the page. */
  svg() {
    const vector = echarts.init(null, null, {
      renderer: 'svg',
      ssr: true,
      width: this.chart.getWidth(),
      height: this.chart.getHeight(),
    });
    vector.setOption({ ...this.chart.getOption(), backgroundColor: '#fff' });
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
    name,
    type: 'line',
    data: pairs(xs, ys),
    showSymbol: false,
    lineStyle: { width: 1.5, color: colour },
    itemStyle: { color: colour },
    ...extra,
  };
}

/**
 * The band between `lower` and `upper`, shaded: an invisible line at `lower` with the
 * width stacked on top of it, kept out of the tooltip.
 */
export function band(name, xs, lower, upper, colour) {
  const stack = `band ${name}`;
  const width = upper.map((u, i) => u - lower[i]);
  // stackStrategy 'all': stack the width on the lower line even where that is negative.
  const hidden = { showSymbol: false, lineStyle: { opacity: 0 }, stack, stackStrategy: 'all', silent: true };
  return [
    { ...hidden, id: `${stack} low`, name, type: 'line', data: pairs(xs, lower) },
    { ...hidden, id: `${stack} width`, name, type: 'line', data: pairs(xs, width), areaStyle: { color: colour, opacity: 0.15 } },
  ];
}

/** Axes, legend, tooltip and zoom shared by the plots over time. */
export function overTime(yName, series, yAxis = {}) {
  return {
    animation: false,
    grid: { left: 64, right: 20, top: 40, bottom: 44 },
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
