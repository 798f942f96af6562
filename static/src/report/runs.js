// The runs of a report: asked of the server (which runs the student's code on the whole
// data sets once a submission, in the background) until they are made, then drawn, each
// in its section, with the exercise's report views (the `report` of its folder's
// `web/workbench.js`) from the wasm grader of the whole data sets.
import workbenches from 'estlab:workbenches';
import { getJson } from '../results/http.js';
import { element } from '../results/render.js';
import { loadEstlab } from '../wasm.js';

/** @typedef {import('../types/ReportRuns').ReportRuns} ReportRunsAnswer */
/** @typedef {import('../types/RunPhase').RunPhase} RunPhase */
/** @typedef {import('../types/RunOutput').RunOutput} RunOutput */
/** @typedef {import('estlab-wasm/estlab_wasm.js').Grader} Grader */

/**
 * An exercise's views of the runs of a report: `collect` as its workbench collects a run
 * (throws when the run cannot be drawn), and a `View` that draws one run whole, in a box of
 * its own, with no controls.
 *
 * @template [Shown=unknown]
 * @typedef {{
 *   collect: (grader: Grader, phase: RunPhase, output: RunOutput) => Shown,
 *   View: new (box: HTMLElement, name: string) => { show: (shown: Shown) => void },
 * }} ReportRuns
 */

/** How often the page asks again while the runs are made, ms. */
const ASK_EVERY = 1500;

/** @param {number} ms */
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/**
 * The runs at `url` once made (or why they are not), saying meanwhile in `status` that
 * the server is running the code.
 *
 * @param {string} url
 * @param {HTMLElement} status
 * @returns {Promise<ReportRunsAnswer>}
 */
export async function madeRuns(url, status) {
  for (;;) {
    /** @type {ReportRunsAnswer} */
    const runs = await getJson(url);
    if (runs.state !== 'making') return runs;
    status.textContent = `The server is running submission ${runs.submission} on the whole data sets…`;
    await sleep(ASK_EVERY);
  }
}

/**
 * Draws each run of `outputs` into its box (`boxes`, by run name) with the views of the
 * exercise in `folder`, on the data sets of `seed`; a run that cannot be drawn says why
 * in its box.
 *
 * @param {{ lab: string, folder: string, seed: number, outputs: RunOutput[], boxes: Map<string, HTMLElement> }} runs
 */
export async function drawRuns({ lab, folder, seed, outputs, boxes }) {
  const [estlab, module] = await Promise.all([loadEstlab(), workbenches[folder]()]);
  const views = module.report;
  if (!views) throw new Error(`the exercise ${lab} draws no report`);
  const grader = estlab.Grader.whole(lab, seed);
  /** @type {RunPhase[]} */
  const phases = JSON.parse(grader.job()).runs;
  try {
    for (const [name, box] of boxes) {
      const output = outputs.find((o) => o.name === name);
      const phase = phases.find((p) => p.name === name);
      if (!output || !phase) {
        box.replaceChildren(element('p', 'error', `The run ${name} has no output.`));
        continue;
      }
      try {
        const shown = views.collect(grader, phase, output);
        box.replaceChildren();
        new views.View(box, name).show(shown);
      } catch (error) {
        box.replaceChildren(element('p', 'error', `This run cannot be shown: ${error instanceof Error ? error.message : error}`));
      }
    }
  } finally {
    grader.free();
  }
}
