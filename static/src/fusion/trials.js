// The trials the fusion page runs on: generated from a seed, the Northstar report's
// (from the server, when it has them), or the reader's own CSV file; each with the words
// that name it and the flags of `estlab fusion` that make the same trial.

/** @typedef {import('estlab-wasm/estlab_wasm.js').FusionTrial} FusionTrial */
/** @typedef {import('../types/TrialParams').TrialParams} TrialParams */
/** @typedef {import('../types/NamedTrial').NamedTrial} NamedTrial */

/**
 * A trial ready to run, and what the page says of it.
 *
 * @typedef {object} LoadedTrial
 * @property {FusionTrial} trial
 * @property {'generated' | 'report' | 'file'} kind
 * @property {string} name what it is, in a sentence: "the generated trial of seed 1 (12 waypoints)"
 * @property {string} short what it is, in a table: "seed 1", "trial 1", "run.csv"
 * @property {string[]} flags the flags of `estlab fusion` that make it (a report's trial needs `--datasets DIR` too)
 * @property {string} [report] a report's trial: its name (`trial1`)
 * @property {TrialParams} [params] a generated trial: what it was made from
 * @property {boolean} platforms whether its readings have their platforms (and so their
 *   intensities and the heading's σ of its own); else the sensor's pose alone
 */

/**
 * `trial` with what the page says of it.
 *
 * @param {FusionTrial} trial
 * @param {Omit<LoadedTrial, 'trial' | 'platforms'>} fields
 * @returns {LoadedTrial}
 */
function loaded(trial, fields) {
  return { trial, platforms: trial.intensity().some(Number.isFinite), ...fields };
}

/** "trial1" as people write it: "trial 1". */
const trialTitle = (name) => name.replace(/^trial(\d+)$/, 'trial $1');

/**
 * The trial generated from `params` (checked by the library, whose message names the
 * field that is out of range).
 *
 * @param {typeof import('estlab-wasm/estlab_wasm.js')} estlab
 * @param {TrialParams} params
 * @returns {LoadedTrial}
 */
export function generated(estlab, params) {
  return loaded(estlab.FusionTrial.generate(JSON.stringify(params)), {
    kind: 'generated',
    name: `the generated trial of seed ${params.seed} (${params.waypoints} waypoints)`,
    short: `seed ${params.seed}`,
    flags: ['--seed', String(params.seed), '--waypoints', String(params.waypoints)],
    params,
  });
}

/**
 * The reader's own trial file; the parser's message names the file, the line and the
 * column that is wrong.
 *
 * @param {typeof import('estlab-wasm/estlab_wasm.js')} estlab
 * @param {File} file
 * @returns {Promise<LoadedTrial>}
 */
export async function fromFile(estlab, file) {
  return loaded(estlab.FusionTrial.parseCsv(await file.text(), file.name), {
    kind: 'file',
    name: `your file ${file.name}`,
    short: file.name,
    flags: ['--trial', file.name],
  });
}

/**
 * The report's trials the server has (none without `estlab serve --datasets`), in the
 * order it sends them.
 *
 * @param {typeof import('estlab-wasm/estlab_wasm.js')} estlab
 * @returns {Promise<LoadedTrial[]>}
 */
export async function reportTrials(estlab) {
  const response = await fetch('/api/datasets/northstar');
  if (!response.ok) throw new Error(`the report's trials did not load: the server answered ${response.status}`);
  /** @type {NamedTrial[]} */
  const named = await response.json();
  return named.map(({ name, trial }) => loaded(estlab.FusionTrial.fromJson(JSON.stringify(trial)), {
    kind: 'report',
    name: `the report's ${trialTitle(name)}`,
    short: trialTitle(name),
    flags: ['--report-trial', name],
    report: name,
  }));
}

/** The command line that makes the same run as the page, with the filter's `settingsFlags`. */
export function commandText(loaded, settingsFlags) {
  const datasets = loaded.kind === 'report' ? ['--datasets', 'DIR'] : [];
  return ['estlab fusion', ...datasets, ...loaded.flags, ...settingsFlags].join(' ');
}
