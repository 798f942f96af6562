// The EKF, the UKF and the particle filter on a robot of an MRCLAM-like data set,
// computed in the browser by the wasm build of the reference (labs::mrclam): a robot
// generated from a seed, or one of the real recordings the server offers (`--datasets`);
// the noise learned from it; the three filters side by side, their particles and sigma
// points at a chosen step, their errors, consistency and time.
import { LogSlider, byId, fieldMessage, setText, showError } from '../controls.js';
import { fmt } from '../format.js';
import { renderMath } from '../math.js';
import { drawCloseUp, drawErrors, drawMap, drawNees } from '../mrclam/plots.js';
import { showFilters, showNoise } from '../mrclam/tables.js';
import { plotsIn } from '../plots.js';
import { loadEstlab } from '../wasm.js';

/** @typedef {import('../mrclam/plots.js').FilterView} FilterView */
/** @typedef {import('../mrclam/plots.js').RobotView} RobotView */
/** @typedef {import('../types/MrclamEntry').MrclamEntry} MrclamEntry */
/** @typedef {import('../types/MrclamFilter').MrclamFilter} MrclamFilter */
/** @typedef {import('../types/MrclamNoise').MrclamNoise} MrclamNoise */
/** @typedef {import('../types/MrclamSettings').MrclamSettings} MrclamSettings */
/** @typedef {import('../types/MrclamDatasetParams').MrclamDatasetParams} MrclamDatasetParams */

renderMath();
const estlab = await loadEstlab();
/** @type {{ dataset: MrclamDatasetParams, settings: MrclamSettings, consistent_inside: number }} */
const defaults = JSON.parse(estlab.mrclamDefaults());
const plots = plotsIn(byId('mrclam-plots'), 'mrclam');
/** How many steps keep their particles and sigma points, for the time slider. */
const SNAPSHOTS = 100;
/** The particle counts the slider offers; the page starts at 500, where a real robot's run stays near a second. */
const PARTICLES = [50, 100, 200, 500, 1000, 2000, 5000];
const PAGE_PARTICLES = 500;
/** @type {[MrclamFilter, string][]} */
const FILTERS = [['ekf', 'EKF'], ['ukf', 'UKF'], ['particle', 'particle filter']];

const ui = {
  data: byId('data', HTMLSelectElement),
  generatedFields: byId('generated-fields'),
  seed: byId('seed', HTMLInputElement),
  robot: byId('robot', HTMLSelectElement),
  rho: new LogSlider(byId('rho'), byId('rho-value'), (v) => `ρ = ${fmt(v, 2)}: R₂ times ${fmt(v, 2)}`),
  particles: byId('particles', HTMLInputElement),
  particlesValue: byId('particles-value'),
  when: byId('when', HTMLInputElement),
  whenValue: byId('when-value'),
  error: byId('error'),
  runView: byId('run-view'),
  timing: byId('timing'),
  command: byId('command'),
};

/**
 * The robot the controls say, in wasm memory, with what the page shows of it; null
 * while none loads.
 *
 * @type {{ handle: import('estlab-wasm/estlab_wasm.js').MrclamRobot, view: RobotView, noise: MrclamNoise,
 *           truth: MrclamNoise | null, drift: import('../types/PositionErrors').PositionErrors, flags: string[] } | null}
 */
let robot = null;
/** The filters' runs on it. */
let views = /** @type {FilterView[]} */ ([]);
/** The real recordings' JSON, by data set and robot, fetched once. */
const recordings = new Map();
/** Loads begun: a later one supersedes an earlier one still fetching. */
let loads = 0;

/** The real robots the server offers, as choices of the data menu. */
async function offerRealRobots() {
  const response = await fetch('/api/datasets/mrclam');
  if (!response.ok) return;
  /** @type {MrclamEntry[]} */
  const entries = await response.json();
  for (const e of entries) {
    const option = document.createElement('option');
    option.value = `real:${e.dataset}:${e.robot}`;
    option.textContent = `MRCLAM data set ${e.dataset}, robot ${e.robot} (real, ${fmt(e.steps / 50, 3)} s)`;
    ui.data.append(option);
  }
}

/** Robot `number` of the real data set `dataset`, fetched once. */
async function realRecording(dataset, number) {
  const key = `${dataset}:${number}`;
  if (!recordings.has(key)) {
    const response = await fetch(`/api/datasets/mrclam/robot?dataset=${dataset}&robot=${number}`);
    if (!response.ok) throw new Error(`robot ${number} of data set ${dataset}: the server answered ${response.status}`);
    recordings.set(key, await response.text());
  }
  return recordings.get(key);
}

/** Series of a robot that the page keeps. */
function robotView(handle, subject) {
  return {
    t: handle.t(),
    truth: [handle.truth(0), handle.truth(1)],
    posts: handle.posts(),
    blind: handle.blindStretch(),
    subject,
  };
}

/** Loads the robot the controls say, then runs the filters on it. */
async function loadRobot() {
  const ticket = ++loads;
  const choice = ui.data.value;
  ui.generatedFields.hidden = choice !== 'generated';
  fieldMessage(ui.seed, null);
  let next = null;
  let problem = null;
  try {
    if (choice === 'generated') {
      const text = ui.seed.value.trim();
      if (!/^\d{1,15}$/.test(text)) {
        problem = `seed: must be a whole number of 0 or more, got ${text === '' ? 'nothing' : `"${text}"`}`;
        fieldMessage(ui.seed, problem, { live: false });
      } else {
        const seed = Number(text);
        const number = Number(ui.robot.value);
        const handle = estlab.MrclamRobot.generate(JSON.stringify({ ...defaults.dataset, seed }), number);
        next = { handle, subject: `robot ${number} of the data set generated from seed ${seed}`, truth: defaults.dataset.noise,
          flags: ['--generate', String(seed), '--robot', String(number)] };
      }
    } else {
      const [, dataset, number] = choice.split(':');
      const json = await realRecording(dataset, number);
      const handle = estlab.MrclamRobot.fromJson(json);
      next = { handle, subject: `robot ${number} of MRCLAM data set ${dataset}`, truth: null,
        flags: ['--datasets', 'DIR', '--dataset', dataset, '--robot', number] };
    }
  } catch (error) {
    problem = error.message;
  }
  if (ticket !== loads) {
    next?.handle.free();
    return;
  }
  robot?.handle.free();
  if (!next) forgetRuns();
  robot = next && {
    ...next,
    view: robotView(next.handle, next.subject),
    noise: JSON.parse(next.handle.noise()),
    drift: JSON.parse(next.handle.drift()),
  };
  showError(ui.error, problem);
  ui.runView.classList.toggle('stale', robot === null);
  if (robot) update();
}

/** The particle count the slider says. */
const particles = () => PARTICLES[Number(ui.particles.value)];

/** Sets the particle slider to `count` (one it offers). */
function setParticles(count) {
  ui.particles.value = String(PARTICLES.indexOf(count));
  showParticles();
}

function showParticles() {
  setText(ui.particlesValue, `${particles()} particles`);
}

/** The settings the sliders say. */
function settings() {
  return { rho: Number(fmt(ui.rho.value, 3)), particles: particles(), seed: defaults.settings.seed };
}

/**
 * The address follows the robot and the settings, so that a link opens the same run:
 * /mrclam?data=generated&seed=7&robot=2&rho=10&particles=2000 (data=real:6:1 for a real
 * robot).
 */
function showAddress(s) {
  const address = new URLSearchParams({ data: ui.data.value });
  if (ui.data.value === 'generated') {
    address.set('seed', ui.seed.value);
    address.set('robot', ui.robot.value);
  }
  address.set('rho', String(s.rho));
  address.set('particles', String(s.particles));
  const url = `${location.pathname}?${address}`;
  if (url !== location.pathname + location.search) history.replaceState(null, '', url);
}

/** The controls as the address says (what it does not say, or says wrongly, stays as it is). */
function fromAddress() {
  const address = new URLSearchParams(location.search);
  const data = address.get('data');
  if (data && [...ui.data.options].some((o) => o.value === data)) ui.data.value = data;
  if (/^\d{1,15}$/.test(address.get('seed') ?? '')) ui.seed.value = address.get('seed');
  if ([...ui.robot.options].some((o) => o.value === address.get('robot'))) ui.robot.value = address.get('robot');
  const rho = Number(address.get('rho'));
  if (address.has('rho') && rho >= 0.1 && rho <= 100) ui.rho.value = rho;
  const count = Number(address.get('particles'));
  if (PARTICLES.includes(count)) setParticles(count);
}

/** Frees the runs the page shows and empties their tables (the plots stay, dimmed). */
function forgetRuns() {
  for (const v of views) v.free();
  views = [];
  for (const id of ['filters-table', 'noise-table']) byId(id, HTMLTableElement).tBodies[0].replaceChildren();
  setText(ui.command, '');
  setText(ui.timing, '');
}

/** Runs the three filters on the robot with the sliders' settings, and redraws. */
function update() {
  if (!robot) return;
  const s = settings();
  showAddress(s);
  forgetRuns();
  const runs = FILTERS.map(([kind, name]) => {
    const start = performance.now();
    const run = robot.handle.run(kind, JSON.stringify(s), SNAPSHOTS);
    const ms = performance.now() - start;
    return {
      kind, name, ms,
      x: run.estimate(0), y: run.estimate(1), sx: run.std(0), inside: run.inside(),
      errorX: Float64Array.from(run.estimate(0), (x, k) => x - robot.view.truth[0][k]),
      nees: run.nees(), snapshots: run.snapshotSteps(),
      samples: (i) => run.samples(i),
      ellipse: (k) => run.ellipse(k, 3, 64),
      summary: JSON.parse(run.summary()),
      free: () => run.free(),
    };
  });
  views = runs;
  ui.when.max = String(views[0].snapshots.length - 1);
  setText(ui.timing, `The three runs took ${views.map((v) => `${fmt(v.ms, 3)} ms (${v.name})`).join(', ')} in this browser.`);
  setText(ui.command, ['estlab', 'mrclam', ...robot.flags, '--rho', String(s.rho), '--particles', String(s.particles)].join(' '));
  showFilters(byId('filters-table', HTMLTableElement), views, robot.drift);
  showNoise(byId('noise-table', HTMLTableElement), robot.noise, s.rho, robot.truth);
  drawErrors(plots, robot.view, views);
  drawNees(plots.nees, robot.view, views);
  drawSnapshot();
}

/** The map at the time slider's step. */
function drawSnapshot() {
  if (!robot || !views.length) return;
  const i = Number(ui.when.value);
  const k = views[0].snapshots[i];
  setText(ui.whenValue, `t = ${fmt(robot.view.t[k], 4)} s (step ${k})`);
  drawMap(plots.map, robot.view, views, i);
  drawCloseUp(plots['close-up'], robot.view, views, i);
  for (const name of ['error-ekf', 'error-ukf', 'error-particle', 'nees']) plots[name].setMarker(robot.view.t[k], 'the map\'s time');
}

ui.rho.value = defaults.settings.rho;
ui.particles.max = String(PARTICLES.length - 1);
setParticles(PAGE_PARTICLES);
ui.particles.addEventListener('input', showParticles);
ui.data.addEventListener('change', loadRobot);
ui.robot.addEventListener('change', loadRobot);
ui.seed.addEventListener('change', loadRobot);
for (const input of [ui.rho.input, ui.particles]) input.addEventListener('change', update);
ui.when.addEventListener('input', drawSnapshot);
byId('reference-settings').addEventListener('click', () => {
  ui.rho.value = defaults.settings.rho;
  setParticles(defaults.settings.particles);
  update();
});
await offerRealRobots();
fromAddress();
await loadRobot();
document.body.dataset.ready = 'true';
