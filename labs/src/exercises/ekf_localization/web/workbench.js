// The EKF workbench's runs on the data sets (the workbench, static/src/pages/code.js,
// loads this view of the exercise's runs): each drawn with the experiment page's views
// (static/src/ekf/runview.js), beside what part of the data set grading
// runs through and a link to the whole of it on the experiment page.
import { byId } from 'estlab/controls.js';
import { MapView } from 'estlab/ekf/map.js';
import { RunView, collect, describeMap, describeOverTime, drawOverTime } from 'estlab/ekf/runview.js';
import { plotsIn } from 'estlab/plots.js';
import { fmt } from 'estlab/format.js';
import { element, link } from 'estlab/results/render.js';

/**
 * Everything the views need from the student's run `output` of `phase`, taken out of wasm
 * at once; throws when the run cannot be drawn (its test says why).
 */
function collectRun(grader, phase, output) {
  let run;
  let dataset;
  try {
    run = grader.studentRun(JSON.stringify(output));
    dataset = grader.dataset(phase.name);
    return { ...collect(run, dataset), phase, dataSeed: grader.dataSeed(phase.name) };
  } finally {
    run?.free();
    dataset?.free();
  }
}

/**
 * Where the run is shown, what part of the data set grading runs through (a prefix, so
 * that the server grades within a second), and a link to the whole data set on the
 * experiment page with the same update.
 */
function prefixNote({ phase, dataSeed }) {
  const readings = phase.steps.reduce((n, step) => n + step.z[0].length, 0);
  const seconds = phase.steps.reduce((t, step) => t + step.delta_t, 0);
  const whole = link(`/ekf?kind=${phase.dataset}&seed=${dataSeed}&mode=${phase.mode}`,
    'the whole data set on the experiment page');
  return [
    `Grading runs the first ${readings} readings of this data set (${fmt(seconds, 3)} s of ${phase.steps.length} time steps), ` +
      'which keeps a grading on the server within a second; the map shows only that much of the path. See ',
    whole, ' with the reference filter.',
  ];
}

/** The runs section (the markup of `web/plots.html` in `root`, after the summary) showing one run at a time. */
class DatasetRunView {
  constructor(root) {
    this.view = new RunView(root, 'code');
  }

  show(v) {
    this.view.show(v, true);
    byId('summary').textContent = v.report;
    byId('prefix').replaceChildren(...prefixNote(v));
  }
}

/** The figures of a run in a report: the whole run at once, no controls. */
const REPORT_FIGURES = [
  ['map', 'The map: true (green, solid), estimated (red, dashed) and odometry-only (blue, dotted) paths, 3σ ellipses, rejected readings', 'plot tall wide'],
  ['errorX', 'Error in x, with ±3σ', 'plot'],
  ['errorY', 'Error in y, with ±3σ', 'plot'],
  ['errorTheta', 'Error in θ, with ±3σ', 'plot'],
  ['covariance', 'The covariance diagonal', 'plot'],
];

/**
 * A run of the student's report in `box`: the experiment page's views of the whole run,
 * still (the map as the run ends, the plots over time), and the printout of `estlab run`.
 */
class ReportRunView {
  constructor(box, name) {
    const plots = element('div', 'plots');
    for (const [figureName, caption, className] of REPORT_FIGURES) {
      const figure = element('figure', className);
      figure.dataset.name = figureName;
      figure.append(element('figcaption', null, caption), element('div', 'chart'));
      plots.append(figure);
    }
    this.printout = element('pre', 'printout');
    box.append(plots, this.printout);
    this.plots = plotsIn(box, name.replace('/', '-'));
    this.map = new MapView(this.plots.map);
  }

  show(v) {
    this.map.showData(v.landmarks, v.truth, v.odometry);
    this.map.showRun(v.estimate, v.ellipses, v.rejected);
    drawOverTime(this.plots, v, true);
    describeOverTime(this.plots, v);
    describeMap(this.map, v);
    this.printout.textContent = v.report;
    for (const plot of Object.values(this.plots)) plot.drawNow();
  }
}

/**
 * The EKF report's runs: collected as the workbench collects them, drawn still.
 *
 * @type {import('estlab/report/runs.js').ReportRuns<ReturnType<typeof collectRun>>}
 */
export const report = { collect: collectRun, View: ReportRunView };

/**
 * The EKF workbench's runs: each one's views from the harness's output, and where they are drawn.
 *
 * @type {import('estlab/workbench/running.js').ExerciseRuns<ReturnType<typeof collectRun>>}
 */
export const runs = { collect: collectRun, View: DatasetRunView };
