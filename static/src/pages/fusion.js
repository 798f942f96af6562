// Fusing odometry with an indoor positioning sensor, computed in the browser by the wasm
// build of the reference model (labs::fusion): a trial (generated from a seed, one of the
// Northstar report's when the server has them, or the reader's own CSV file), the
// filter's settings, and what the filter makes of it, beside odometry, the sensor alone
// and the report's own estimate; and tuning on one trial, tested on another.
//
// The parts live in ../fusion/: the trials (trials.js), what the controls say
// (settings.js), a run taken out of wasm (run.js), the map (map.js), the errors over time
// (errors.js), the tables (tables.js) and the tuning (tuning.js); this page runs them as
// the controls change. A trial that does not load keeps the last run's plots, dimmed.
import { LogSlider, byId, download, fieldMessage, setText, showError } from '../controls.js';
import { fmt } from '../format.js';
import { drawErrors } from '../fusion/errors.js';
import { drawMap } from '../fusion/map.js';
import { runFilter } from '../fusion/run.js';
import {
  filterSettings, settingsFlags, settingsFromAddress, showSettings, tuningFunction, twoDigits,
} from '../fusion/settings.js';
import { captionErrors, showErrors, showReadings } from '../fusion/tables.js';
import { commandText, fromFile, generated, reportTrials } from '../fusion/trials.js';
import { showTuning, tuneAndTest } from '../fusion/tuning.js';
import { renderMath } from '../math.js';
import { plotsIn } from '../plots.js';
import { loadEstlab } from '../wasm.js';

/** @typedef {import('../fusion/trials.js').LoadedTrial} LoadedTrial */
/** @typedef {import('../types/FusionSettings').FusionSettings} FusionSettings */
/** @typedef {import('../types/TrialParams').TrialParams} TrialParams */
/** @typedef {import('../types/ReportFigures').ReportFigures} ReportFigures */

renderMath();
const estlab = await loadEstlab();
/** @type {{ settings: FusionSettings, trial: TrialParams, report_figures: Record<string, ReportFigures> }} */
const defaults = JSON.parse(estlab.fusionDefaults());
const plots = plotsIn(byId('fusion-plots'), 'fusion');
const degrees = Math.PI / 180;

const ui = {
  trial: byId('trial', HTMLSelectElement),
  generatedFields: byId('generated-fields'),
  seed: byId('seed', HTMLInputElement),
  waypoints: byId('waypoints', HTMLInputElement),
  fileFields: byId('file-fields'),
  file: byId('trial-file', HTMLInputElement),
  download: byId('download-trial', HTMLButtonElement),
  processXy: new LogSlider(byId('process-xy'), byId('process-xy-value'),
    (v) => `k_xy = ${fmt(twoDigits(v))}: σ grows ${fmt(100 * twoDigits(v), 3)} cm per metre moved`),
  processTheta: new LogSlider(byId('process-theta'), byId('process-theta-value'),
    (v) => `k_θ = ${fmt(twoDigits(v))}: σ_θ grows ${fmt(twoDigits(v) / degrees, 3)}° per metre moved or radian turned`),
  cXy: byId('c-xy', HTMLInputElement),
  cTheta: byId('c-theta', HTMLInputElement),
  fieldOfView: byId('field-of-view', HTMLInputElement),
  gate: byId('gate', HTMLInputElement),
  error: byId('error'),
  runView: byId('run-view'),
  stale: byId('run-stale'),
  command: byId('command'),
  tuningCode: byId('tuning-code'),
  tuningLanguage: byId('tuning-language', HTMLSelectElement),
  timing: byId('timing'),
  tuneReal: byId('tune-real'),
  tuneGenerated: byId('tune-generated'),
  tuneNone: byId('tune-none'),
  tuneNextSeed: byId('tune-next-seed', HTMLButtonElement),
};

/** The report's trials the server has (none without `--datasets`). */
let reports = /** @type {LoadedTrial[]} */ ([]);
/** The trial the controls say, or null while it does not load. */
let current = /** @type {LoadedTrial | null} */ (null);
/** Why the trial the controls say did not load (shown as an error), or null. */
let trialProblem = null;
/**
 * The run the plots show (null before the first), with its field of view and the name of
 * its trial: what a new size of the window redraws, and whose a dimmed plot is.
 */
let shown = null;
/** The loads of a trial begun: a later one supersedes an earlier one still reading its file. */
let loads = 0;

/** Frees `trial`'s wasm memory unless it is one of the report's, which the page keeps. */
function release(trial) {
  if (trial && trial.kind !== 'report') trial.trial.free();
}

/** What is wrong with a whole number typed into `input` (null: nothing); `name` names it. */
function wholeNumberProblem(input, name) {
  const text = input.value.trim();
  return /^\d{1,15}$/.test(text) ? null : `${name}: must be a whole number of 0 or more, got ${text === '' ? 'nothing' : `"${text}"`}`;
}

/** The field a message of the library about a generated trial concerns (by the name before its colon), or null. */
function fieldOf(message) {
  return { seed: ui.seed, waypoints: ui.waypoints }[message.slice(0, message.indexOf(':'))] ?? null;
}

/** Loads the trial the controls say, and runs the filter on it. */
async function loadTrial() {
  const ticket = ++loads;
  const choice = ui.trial.value;
  ui.generatedFields.hidden = choice !== 'generated';
  ui.fileFields.hidden = choice !== 'file';
  for (const input of [ui.seed, ui.waypoints]) fieldMessage(input, null);
  /** @type {LoadedTrial | null} */
  let next = null;
  let problem = null;
  try {
    if (choice === 'generated') {
      problem = wholeNumberProblem(ui.seed, 'seed') ?? wholeNumberProblem(ui.waypoints, 'waypoints');
      if (!problem) next = generated(estlab, { ...defaults.trial, seed: Number(ui.seed.value), waypoints: Number(ui.waypoints.value) });
    } else if (choice === 'file') {
      const file = ui.file.files[0];
      if (file) next = await fromFile(estlab, file);
    } else {
      next = reports.find((r) => `report:${r.report}` === choice) ?? null;
    }
  } catch (error) {
    problem = error.message;
  }
  if (ticket !== loads) {
    release(next);
    return;
  }
  if (problem && choice === 'generated' && fieldOf(problem)) fieldMessage(fieldOf(problem), problem, { live: false });
  if (next !== current) release(current);
  current = next;
  trialProblem = problem;
  update();
}

/**
 * The plots, tables and command are of a run that is no longer what the controls say
 * (`why`): the command goes, the rest stays, dimmed, with a note saying whose it is. null:
 * they are current again.
 */
function markStale(why) {
  const stale = why !== null && shown !== null;
  ui.runView.classList.toggle('stale', stale);
  ui.stale.hidden = !stale;
  setText(ui.stale, stale ? `${why} The plots and tables below are still those of the last run, on ${shown.subject}, dimmed.` : '');
  ui.command.closest('p').hidden = why !== null;
  if (why !== null) {
    setText(ui.command, '');
    delete ui.command.dataset.flags;
  }
}

/** The values beside the controls that are not log sliders. */
function showValues(s) {
  const sigma = (c, intensity) => c / intensity;
  setText(byId('c-xy-value'), `c_xy = ${fmt(s.noise.c_xy)}: σ = ${fmt(100 * sigma(s.noise.c_xy, 1500), 2)} cm at intensity 1500, ${fmt(100 * sigma(s.noise.c_xy, 500), 2)} cm at 500`);
  const heading = `c_θ = ${fmt(s.noise.c_theta)}: σ_θ = ${fmt(sigma(s.noise.c_theta, 1500) / degrees, 2)}° at intensity 1500`;
  setText(byId('c-theta-value'), current?.platforms
    ? `${heading}; not used on this trial, whose platforms give the heading's σ by error propagation`
    : heading);
  setText(byId('field-of-view-value'), `${fmt(s.field_of_view)} m round the point under the detector`);
  setText(byId('gate-value'), s.gate === 1
    ? '1: the gate is off, no reading is rejected'
    : `${s.gate}: a reading is rejected when its Mahalanobis distance is above χ²₃ = ${fmt(estlab.fusionGateThreshold(s.gate))}`);
}

/** Which tuning the trials on offer allow. */
function showTuneButtons() {
  const real = ['trial1', 'trial2'].every((name) => reports.some((r) => r.report === name));
  const onGenerated = ui.trial.value === 'generated';
  ui.tuneReal.hidden = !real;
  ui.tuneGenerated.hidden = !onGenerated;
  ui.tuneNextSeed.disabled = current?.kind !== 'generated';
  ui.tuneNone.hidden = real || onGenerated;
}

/**
 * The address follows the trial (not a reader's file: a link cannot carry it) and the
 * settings that differ from the round ones, by the command line's names, so that a link
 * opens the same run: /fusion?trial=generated&seed=7&waypoints=6&gate=0.99.
 */
function showAddress(s) {
  const address = new URLSearchParams();
  const choice = ui.trial.value;
  if (choice !== 'file') address.set('trial', choice);
  if (choice === 'generated') {
    address.set('seed', ui.seed.value);
    address.set('waypoints', ui.waypoints.value);
  }
  const [flags, round] = [settingsFlags(s), settingsFlags(defaults.settings)];
  for (let i = 0; i < flags.length; i += 2) {
    if (flags[i + 1] !== round[i + 1]) address.set(flags[i].slice(2), flags[i + 1]);
  }
  const url = `${location.pathname}?${address}`;
  if (url !== location.pathname + location.search) history.replaceState(null, '', url);
}

/** Runs the filter on the current trial with the settings the controls say, and redraws. */
function update() {
  const start = performance.now();
  const s = filterSettings(ui, defaults.settings);
  showAddress(s);
  showValues(s);
  setText(ui.tuningCode, tuningFunction(s, estlab.fusionGateThreshold(s.gate),
    /** @type {import('../types/Language').Language} */ (ui.tuningLanguage.value)));
  showTuneButtons();
  ui.download.disabled = current?.kind !== 'generated';
  if (!current) {
    showError(ui.error, trialProblem);
    markStale(trialProblem ? 'No run: the trial did not load.' : 'No run yet: choose a CSV file of your trial above.');
    return;
  }
  let v;
  try {
    v = runFilter(current.trial, s);
  } catch (error) {
    showError(ui.error, error.message);
    markStale('No run with these settings.');
    return;
  }
  showError(ui.error, null);
  shown = { v, fieldOfView: s.field_of_view, subject: current.name };
  drawMap(plots.map, v, s.field_of_view, current.name);
  drawErrors(plots, v);
  captionErrors(current.name);
  showErrors(v.summary, current.report ? defaults.report_figures[current.report] : undefined);
  showReadings(v.summary);
  markStale(null);
  const flags = settingsFlags(s);
  setText(ui.command, commandText(current, flags));
  ui.command.dataset.flags = JSON.stringify([...current.flags, ...flags]);
  setText(ui.timing, `re-run and redraw: ${fmt(performance.now() - start, 2)} ms`);
}

/**
 * Tunes on `train`, tests on `test`, applies the tuned settings and shows the trial
 * `choice` (the trial select's value), `seed` on a generated one.
 */
async function tuneThenShow(train, test, choice, seed = null) {
  const tuning = tuneAndTest(train, test, filterSettings(ui, defaults.settings), defaults.settings);
  showTuning(tuning);
  showSettings(ui, tuning.tuned);
  ui.trial.value = choice;
  if (seed !== null) ui.seed.value = String(seed);
  await loadTrial();
}

// --- the controls ---

// A link may choose the trial and any setting, as the address shows them.
const asked = new URLSearchParams(location.search);
showSettings(ui, settingsFromAddress(asked, defaults.settings));
ui.seed.value = /^\d{1,15}$/.test(asked.get('seed') ?? '') ? asked.get('seed') : String(defaults.trial.seed);
ui.waypoints.value = /^\d{1,3}$/.test(asked.get('waypoints') ?? '') ? asked.get('waypoints') : String(defaults.trial.waypoints);
// tuning() in the language the student last chose on the exercise's workbench.
const chosen = localStorage.getItem('estlab:sensor-fusion:choice');
if ([...ui.tuningLanguage.options].some((option) => option.value === chosen)) ui.tuningLanguage.value = chosen ?? '';
ui.tuningLanguage.addEventListener('change', update);
ui.trial.addEventListener('change', loadTrial);
ui.seed.addEventListener('input', loadTrial);
ui.waypoints.addEventListener('input', loadTrial);
ui.file.addEventListener('change', loadTrial);
for (const input of document.querySelectorAll('#fusion-controls input[type=range]')) {
  input.addEventListener('input', update);
}
byId('copy-tuning').addEventListener('click', async () => {
  const status = byId('copy-status');
  try {
    await navigator.clipboard.writeText(ui.tuningCode.textContent ?? '');
    status.textContent = 'Copied: paste it over the tuning() of your file.';
  } catch {
    status.textContent = 'This browser did not let the page copy: select the code and copy it.';
  }
});
byId('round-settings').addEventListener('click', () => {
  showSettings(ui, defaults.settings);
  update();
});
ui.download.addEventListener('click', () => {
  const { seed, waypoints } = current.params;
  download(`fusion_trial_seed${seed}_${waypoints}waypoints.csv`, current.trial.csv(), 'text/csv');
});
const reportNamed = (name) => reports.find((r) => r.report === name);
byId('tune-1-2').addEventListener('click', () => tuneThenShow(reportNamed('trial1'), reportNamed('trial2'), 'report:trial2'));
byId('tune-2-1').addEventListener('click', () => tuneThenShow(reportNamed('trial2'), reportNamed('trial1'), 'report:trial1'));
ui.tuneNextSeed.addEventListener('click', async () => {
  const params = current.params;
  const next = generated(estlab, { ...params, seed: params.seed + 1 });
  try {
    await tuneThenShow(current, next, 'generated', params.seed + 1);
  } finally {
    release(next);
  }
});
// A plot in the plane keeps a metre as long on x as on y: a new size of the window needs new axes.
let resizing = false;
window.addEventListener('resize', () => {
  if (resizing || !shown) return;
  resizing = true;
  requestAnimationFrame(() => {
    resizing = false;
    drawMap(plots.map, shown.v, shown.fieldOfView, shown.subject);
  });
});

// The report's trials, when the server has them, in the trial's choice before the reader's file.
try {
  reports = await reportTrials(estlab);
} catch (error) {
  setText(byId('real-trials'), error.message);
}
for (const r of reports) ui.trial.add(new Option(r.name, `report:${r.report}`), ui.trial.options.length - 1);
// A report's trial the server does not have, or a file (which no link carries), is not chosen.
if ([...ui.trial.options].some((o) => o.value === asked.get('trial') && o.value !== 'file')) ui.trial.value = asked.get('trial');
await loadTrial();
document.body.dataset.ready = 'true';
