// What the odometry page's three views (belief.js, systematic.js, umbmark.js) share: a
// view that keeps its last plots, dimmed, while its settings do not run; plots that take
// a new option cheaply; the plots over the steps; a table row; and the words for numbers
// and shapes.
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { overTime } from '../plots.js';

/**
 * Numbers of the summary lines: a few significant digits, and 0 for what is zero but for
 * rounding (a closed square ends 1e-15 m from its start).
 */
export const f = (v) => fmt(Math.abs(v) < 1e-12 ? 0 : v, 3);

const staleWords = 'These plots and numbers are still those of the last settings that ran, dimmed: the settings now do not run (the message above says why).';

/**
 * A view of the page (#NAME-view, with its note #NAME-stale), computed only when what it
 * depends on changed: `compute(s)` its result for the settings `s` with the wasm build
 * (`estlab`), `draw(result, s)` on the page's plots (`plots`, each view its own), and
 * `describe(result, s)` where a view says more once it is computed.
 */
export class View {
  constructor(name, estlab, plots) {
    this.section = byId(`${name}-view`);
    this.note = byId(`${name}-stale`);
    this.estlab = estlab;
    this.plots = plots;
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

/**
 * Shows `option` on `plot`. When the plot is on screen and already shows an option of the
 * same make (the same series, by id and name), only the axes' ranges and the series'
 * data are merged in, which costs ECharts far less than a whole option.
 */
export function show(plot, option) {
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
export function overSteps(yName, series) {
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

/** A table row: a heading and cells of [shown text, exact value]. */
export function row(heading, cells, id) {
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

/** The shape `s` (as `settings` has it) in words. */
export function describeShape(s) {
  switch (s.kind) {
    case 'line': return `straight line of ${fmt(s.length)} m`;
    case 'circle': return `${s.direction} circle of radius ${fmt(s.radius)} m`;
    case 'square': return `${s.direction} square of side ${fmt(s.side)} m`;
    case 'figure-eight': return `figure eight of radius ${fmt(s.radius)} m`;
    default: return `path through your ${s.points.length} points`;
  }
}
