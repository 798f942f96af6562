// The EKF workbench's runs on the data sets (the workbench, static/src/pages/code.js,
// loads this view of the exercise's runs): each drawn with the experiment page's views
// (static/src/ekf/runview.js), beside what part of the data set grading
// runs through and a link to the whole of it on the experiment page.
import { byId } from 'estlab/controls.js';
import { RunView, collect } from 'estlab/ekf/runview.js';
import { fmt } from 'estlab/format.js';
import { link } from 'estlab/results/render.js';

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

/**
 * The EKF workbench's runs: each one's views from the harness's output, and where they are drawn.
 *
 * @type {import('estlab/workbench/running.js').ExerciseRuns<ReturnType<typeof collectRun>>}
 */
export const runs = { collect: collectRun, View: DatasetRunView };
