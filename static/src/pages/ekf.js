// EKF localization, computed in the browser by the wasm build of the reference filters:
// a data set (simulated, or the reader's own EL2320 files), the filter's settings, and
// the plots of the lab.
import { byId, download, fieldMessage, setText, showError } from '../controls.js';
import { decimal, fmt } from '../format.js';
import { renderMath } from '../math.js';
import { RunView, collect } from '../ekf/runview.js';
import { loadEstlab } from '../wasm.js';

renderMath();
const estlab = await loadEstlab();
const views = new RunView(byId('ekf-plots'), 'ekf');
const degrees = Math.PI / 180;

const ui = {
  kind: byId('dataset-kind', HTMLSelectElement),
  seed: byId('dataset-seed', HTMLInputElement),
  files: byId('dataset-files'),
  mapFile: byId('map-file', HTMLInputElement),
  sensorFile: byId('sensor-file', HTMLInputElement),
  rX: byId('r-x', HTMLInputElement),
  rY: byId('r-y', HTMLInputElement),
  rTheta: byId('r-theta', HTMLInputElement),
  qRange: byId('q-range', HTMLInputElement),
  qBearing: byId('q-bearing', HTMLInputElement),
  deltaM: byId('delta-m', HTMLInputElement),
  lambda: byId('lambda-m'),
  known: byId('known-associations', HTMLInputElement),
  error: byId('error'),
  summary: byId('summary'),
  command: byId('command'),
  stale: byId('stale'),
  settingsNote: byId('settings-note'),
};

/** The data set the controls say, or null while it does not load. */
let dataset = null;
/** The lab's settings for the last data set that loaded. */
let lab = null;
/** Whether the data set changed since the plots last showed a run. */
let newDataPending = false;
/** What the data set shown is called (`o3, seed 1`, or the files' names). */
let datasetName = '';
/** The name of the data set of the run the plots show, while they show one. */
let shownName = null;
/** Whether the settings were kept, not the lab's taken, when the data set last changed. */
let keptOnChange = false;

/**
 * The standard deviations the reader sets, each with the variance of the lab's settings
 * it stands for (`of`, `at`) and its unit.
 */
const sigmas = [
  { input: ui.rX, of: 'r', at: 0, unit: 1, name: 'metres' },
  { input: ui.rY, of: 'r', at: 1, unit: 1, name: 'metres' },
  { input: ui.rTheta, of: 'r', at: 2, unit: degrees, name: 'degrees' },
  { input: ui.qRange, of: 'q', at: 0, unit: 1, name: 'metres' },
  { input: ui.qBearing, of: 'q', at: 1, unit: degrees, name: 'degrees' },
];
const modeInput = (mode) => /** @type {HTMLInputElement} */ (document.querySelector(`input[name=mode][value="${CSS.escape(mode)}"]`));
/** The update the reader chose (`sequential`, `batch`). */
const checkedMode = () => /** @type {HTMLInputElement} */ (document.querySelector('input[name=mode]:checked')).value;

/**
 * The filter's settings, as `settings()` makes them and the data set's `labSettings` gives them.
 *
 * @typedef {{ mode: string, known_associations: boolean, r: number[], q: number[], delta_m: number }} Settings
 */

/**
 * A setting the reader can change: see `controls`.
 *
 * @typedef {object} Control
 * @property {(reference?: Settings) => number | string | boolean} value
 * @property {() => string} text
 * @property {(text: string) => void} read
 * @property {() => string | null} problem
 */

/**
 * Every setting the reader can change, by the name the address gives it (the control's
 * id; `mode` for the update): its value as the filter takes it (`value(reference)`: in
 * the settings `reference` instead), its text for the address, how a text of the address sets it, and what is
 * wrong with it (null: nothing).
 *
 * @type {Map<string, Control>}
 */
const controls = new Map([
  ...sigmas.map(/** @returns {[string, Control]} */ (sigma) => [sigma.input.id, {
    value: (reference) => decimal(reference ? reference[sigma.of][sigma.at] : variance(sigma.input, sigma.unit)),
    text: () => sigma.input.value,
    read: (text) => { sigma.input.value = text; },
    problem: () => {
      const value = Number(sigma.input.value);
      return sigma.input.value !== '' && Number.isFinite(value) && value > 0 ? null
        : `A standard deviation must be a number above 0 (in ${sigma.name}), got ${sigma.input.value === '' ? 'nothing' : sigma.input.value}.`;
    },
  }]),
  ['delta-m', {
    value: (reference) => decimal(reference ? reference.delta_m : Number(ui.deltaM.value)),
    text: () => ui.deltaM.value,
    read: (text) => { ui.deltaM.value = text; },
    // A probability: δ_M = 1 rejects nothing, δ_M = 0 would reject every reading.
    problem: () => {
      const value = Number(ui.deltaM.value);
      return ui.deltaM.value !== '' && value > 0 && value <= 1 ? null
        : `δ_M is the share of good readings the gate keeps: a number in (0, 1], got ${ui.deltaM.value === '' ? 'nothing' : ui.deltaM.value}.`;
    },
  }],
  ['mode', {
    value: (reference) => (reference ? reference.mode : checkedMode()),
    text: checkedMode,
    read: (text) => { if (modeInput(text)) modeInput(text).checked = true; },
    problem: () => null,
  }],
  ['known-associations', {
    value: (reference) => (reference ? reference.known_associations : ui.known.checked),
    text: () => String(ui.known.checked),
    read: (text) => { if (['true', 'false'].includes(text)) ui.known.checked = text === 'true'; },
    problem: () => null,
  }],
]);

/** The settings the reader changed themselves, by name: only these stay when the data set changes. */
const edited = new Set();

/** The names of the settings that differ from `lab`'s. */
const differing = (names, lab) => [...names].filter((name) => controls.get(name).value() !== controls.get(name).value(lab));

/**
 * The variance an input of standard deviations (in `unit`s) stands for. An input filled
 * from the lab's settings shows a rounded value but keeps the lab's variance until the
 * reader edits it, so that the lab's settings run as the lab has them.
 */
function variance(input, unit = 1) {
  if (input.dataset.variance && input.value === input.dataset.shown) return Number(input.dataset.variance);
  // The variance of the decimal typed, without float noise, so that the page runs what
  // its command line says: 0.2 m is 0.04 m², not 0.04000000000000001.
  return decimal((Number(input.value) * unit) ** 2);
}

function showVariance(input, value, unit = 1) {
  input.value = fmt(Math.sqrt(value) / unit, 4);
  input.dataset.shown = input.value;
  input.dataset.variance = String(value);
}

/**
 * The filter settings the controls say: standard deviations become variances. Every
 * number is the decimal it stands for, to 12 significant digits (the lab's 0.1² is 0.01,
 * not 0.010000000000000002), so that the command line the page prints, with each number
 * in its shortest form, runs exactly what the page ran.
 */
function settings() {
  const variances = (matrix) => sigmas.filter((sigma) => sigma.of === matrix).map((sigma) => decimal(variance(sigma.input, sigma.unit)));
  return {
    mode: checkedMode(),
    known_associations: ui.known.checked,
    r: variances('r'),
    q: variances('q'),
    delta_m: decimal(Number(ui.deltaM.value)),
  };
}

/** The settings in which `current` differs from `lab`, named as the controls name them. */
function differences(current, lab) {
  const same = (a, b) => a.length === b.length && a.every((v, i) => decimal(v) === decimal(b[i]));
  const named = [
    ['R', !same(current.r, lab.r)],
    ['Q', !same(current.q, lab.q)],
    ['δ_M', decimal(current.delta_m) !== decimal(lab.delta_m)],
    ['the update', current.mode !== lab.mode],
    ['known associations', current.known_associations !== lab.known_associations],
  ];
  return named.filter(([, differs]) => differs).map(([name]) => name);
}

/** Sets the controls to the lab's settings for the current data, except those named in `keep`. */
function labSettings(keep = new Set()) {
  for (const sigma of sigmas) {
    if (!keep.has(sigma.input.id)) showVariance(sigma.input, lab[sigma.of][sigma.at], sigma.unit);
  }
  if (!keep.has('delta-m')) ui.deltaM.value = lab.delta_m;
  if (!keep.has('known-associations')) ui.known.checked = lab.known_associations;
  if (!keep.has('mode')) modeInput(lab.mode).checked = true;
}

/** Says beside each setting what is wrong with it; whether all are right. */
function checkSettings() {
  let right = true;
  for (const [name, control] of controls) {
    const problem = control.problem();
    if (problem) right = false;
    if (name !== 'mode') fieldMessage(byId(name), problem);
  }
  return right;
}

/**
 * The address follows the data set and the settings that differ from the lab's, so that
 * a link opens the same run (a link cannot carry the reader's own files: it names their
 * settings only).
 */
function showAddress() {
  const address = new URLSearchParams();
  if (ui.kind.value !== 'files') {
    address.set('kind', ui.kind.value);
    address.set('seed', ui.seed.value);
  }
  for (const name of lab ? differing(controls.keys(), lab) : []) address.set(name, controls.get(name).text());
  const url = `${location.pathname}?${address}`;
  if (url !== location.pathname + location.search) history.replaceState(null, '', url);
}

/**
 * The plots, the summary and the command are of a run that is no longer what the
 * controls say (`why`): the summary and the command go, the plots stay, dimmed, with a
 * note saying whose they are. null: they are current again.
 */
function markStale(why) {
  const stale = why !== null && shownName !== null;
  ui.stale.hidden = !stale;
  setText(ui.stale, stale ? `${why} The plots below are still those of the last run, on ${shownName}, dimmed.` : '');
  byId('ekf-plots').classList.toggle('stale', stale);
  for (const element of [ui.summary, ui.command.closest('p')]) element.hidden = why !== null;
  if (why !== null) {
    ui.summary.textContent = '';
    ui.command.textContent = '';
    delete ui.command.dataset.flags;
  }
}

/** Says whether the settings are the lab's for this data, and if not, where they differ. */
function describeSettings(current) {
  const differ = differences(current, lab);
  const whose = ui.kind.value === 'files' ? "the lab's settings (o3's, for your own files)" : `the lab's settings for ${ui.kind.value}`;
  if (!differ.length) {
    setText(ui.settingsNote, `These are ${whose}.`);
  } else {
    setText(ui.settingsNote, (keptOnChange ? 'Your settings, kept when the data set changed: ' : 'Your own settings: ') +
      `${differ.join(', ')} ${differ.length === 1 ? 'differs' : 'differ'} from ${whose}; the button “the lab's settings” sets those.`);
  }
}

/** No data set (`why`): nothing runs until one loads, as the controls no longer say the old one. */
function noData(why) {
  showAddress();
  dataset?.free();
  dataset = null;
  markStale(why);
}

async function loadDataset() {
  const kind = ui.kind.value;
  ui.files.hidden = kind !== 'files';
  // A seed makes a simulated data set; uploaded files have none.
  ui.seed.closest('label').hidden = kind === 'files';
  for (const id of ['download-map', 'download-sensor']) byId(id, HTMLButtonElement).disabled = kind === 'files';
  let next;
  try {
    if (kind === 'files') {
      const [map, sensor] = [ui.mapFile.files[0], ui.sensorFile.files[0]];
      if (!map || !sensor) {
        showError(ui.error, 'Choose a map file and a sensor file.');
        noData('No run yet: choose both files.');
        return;
      }
      next = estlab.Dataset.parse(await map.text(), map.name, await sensor.text(), sensor.name);
      datasetName = `${sensor.name} on ${map.name}`;
    } else {
      next = estlab.Dataset.simulate(kind, Number(ui.seed.value));
      datasetName = `${kind}, seed ${ui.seed.value}`;
    }
  } catch (error) {
    showError(ui.error, error.message);
    noData('No run: the data did not load.');
    return;
  }
  // A setting stays the reader's when they changed it themselves (at first: when the link
  // set it); every other becomes the lab's for the new data, those set by another
  // control too (the lab's settings of the data before).
  const kept = new Set(lab ? differing(edited, lab) : edited);
  keptOnChange = lab !== null && kept.size > 0;
  dataset?.free();
  dataset = next;
  lab = JSON.parse(dataset.labSettings());
  labSettings(kept);
  edited.clear();
  for (const name of kept) edited.add(name);
  newDataPending = true;
  update();
}

/** The command that makes the same run with the estlab command line. */
function commandLine(current) {
  // The numbers the page runs, each in its shortest form (see settings).
  const flags = ['--R', current.r.map(String).join(','), '--Q', current.q.map(String).join(','), '--delta-m', String(current.delta_m)];
  if (current.mode === 'batch') flags.push('--batch');
  if (current.known_associations) flags.push('--known-associations');
  const kind = ui.kind.value;
  if (kind === 'files') {
    return { flags, text: ['estlab run', ui.sensorFile.files[0].name, ui.mapFile.files[0].name, ...flags].join(' ') };
  }
  const stem = `${kind}_${ui.seed.value}`;
  const simulate = `estlab simulate --kind ${kind} --seed ${ui.seed.value} --out data`;
  return { flags, text: `${simulate} && ${['estlab run', `data/so_${stem}.txt`, `data/map_${stem}.txt`, ...flags].join(' ')}` };
}

/** Runs the filter and redraws (the data set's views too when it changed). */
function update() {
  if (!dataset) return;
  showAddress();
  if (!checkSettings()) {
    showError(ui.error, null);
    // Λ_M of a δ_M out of range means nothing: it comes back with a run.
    if (controls.get('delta-m').problem()) setText(ui.lambda, '');
    markStale('No run: a setting is out of range (the message is beside it).');
    return;
  }
  const newData = newDataPending;
  const start = performance.now();
  const current = settings();
  const lambda = estlab.lambdaM(current.delta_m);
  setText(ui.lambda, Number.isFinite(lambda)
    ? `Λ_M = ${fmt(lambda)}`
    : 'Λ_M = ∞: no reading is rejected');
  describeSettings(current);
  let run;
  try {
    run = dataset.run(JSON.stringify(current));
  } catch (error) {
    showError(ui.error, error.message);
    markStale(newData ? `No run on ${datasetName}.` : 'No run with these settings.');
    return;
  }
  showError(ui.error, null);
  const view = collect(run, dataset);
  run.free();
  views.show(view, newData);
  newDataPending = false;
  shownName = datasetName;
  markStale(null);
  setText(ui.summary, view.report);
  const command = commandLine(current);
  setText(ui.command, command.text);
  ui.command.dataset.flags = JSON.stringify(command.flags);
  byId('timing').textContent = `re-run and redraw: ${fmt(performance.now() - start, 2)} ms`;
  document.body.dataset.ready = 'true';
}

ui.kind.addEventListener('change', loadDataset);
ui.seed.addEventListener('change', loadDataset);
ui.mapFile.addEventListener('change', loadDataset);
ui.sensorFile.addEventListener('change', loadDataset);
for (const input of /** @type {NodeListOf<HTMLInputElement>} */ (document.querySelectorAll('#ekf-settings .filter input'))) {
  input.addEventListener('input', () => {
    edited.add(input.name === 'mode' ? 'mode' : input.id);
    update();
  });
}
byId('lab-settings').addEventListener('click', () => {
  labSettings();
  edited.clear();
  keptOnChange = false;
  update();
});
byId('download-map').addEventListener('click', () => download(`map_${ui.kind.value}_${ui.seed.value}.txt`, dataset.mapFile()));
byId('download-sensor').addEventListener('click', () => download(`so_${ui.kind.value}_${ui.seed.value}.txt`, dataset.sensorFile()));
// A link may choose the data set and any setting, as the address shows them (the
// workbench links its graded runs here, whole): /ekf?kind=outliers&seed=12&mode=batch.
// A setting of the link counts as the reader's own; one out of range is refused beside
// its field, as if typed.
const asked = new URLSearchParams(location.search);
if ([...ui.kind.options].some((option) => option.value === asked.get('kind') && option.value !== 'files')) {
  ui.kind.value = asked.get('kind');
}
if (/^\d{1,16}$/.test(asked.get('seed') ?? '')) ui.seed.value = asked.get('seed');
for (const [name, control] of controls) {
  if (!asked.has(name)) continue;
  control.read(asked.get(name));
  edited.add(name);
}
await loadDataset();
document.body.dataset.ready = 'true';
