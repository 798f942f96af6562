// The student's workbench of an exercise (the page's `data-lab`: the EKF localization's,
// odometry's): an editor that keeps the file in this browser, the tests (the student's
// functions run in a Web Worker, the wasm build of `labs` makes the cases and judges the
// outputs, exactly as the server does), the runs of the exercise's loop with their views
// (the EKF's data sets with the lab's views, odometry's paths over the reference's), and
// the submission to the server: as the signed-in student once the server runs courses,
// under any id on a server without. With `?submission=ID` it shows an earlier submission,
// read-only, beside its result.
import { javascript } from '@codemirror/lang-javascript';
import { EditorView, basicSetup } from 'codemirror';
import { byId, download, showError } from '../controls.js';
import { datasetRuns } from '../ekf/workbench.js';
import { fmt } from '../format.js';
import { pathRuns } from '../odometry/workbench.js';
import { lateness, percent, span } from '../results/format.js';
import { getJson, pollSubmission } from '../results/http.js';
import { element, link, notImplemented, renderSubmission, testItem, testKey } from '../results/render.js';
import { Runner } from '../sandbox/runner.js';
import { loadEstlab } from '../wasm.js';

const COURSE = 'el2320';
/** The seed of the variant graded without a student id, as `estlab grade` without --seed. */
const PUBLIC_VARIANT = 1;
const MAX_SOURCE = 256 * 1024;
const workbench = byId('workbench').dataset;
/** The exercise of this workbench, by name (`labs::Exercise`). */
const LAB = workbench.lab;
/** Every exercise's workbench path, by the exercise's name. */
const WORKBENCHES = JSON.parse(workbench.workbenches);
/** How this exercise's runs are collected from the harness's outputs, and drawn. */
const RUNS = { 'ekf-localization': datasetRuns, odometry: pathRuns }[LAB];
/** The file is saved per exercise; the student id once for all. */
const STORAGE = { source: `estlab:${LAB}:source`, student: 'estlab:student' };

/** Who is signed in and what they have to do (GET /api/me), or why that is not known. */
async function whoAmI() {
  try {
    return await getJson('/api/me');
  } catch (error) {
    return { courses: null, problem: error.message };
  }
}

const [estlab, me] = await Promise.all([loadEstlab(), whoAmI()]);
const ui = {
  who: byId('who'),
  studentField: byId('student-field'),
  student: byId('student'),
  seed: byId('seed'),
  runTests: byId('run-tests'),
  runLoops: byId('run-datasets'),
  submit: byId('submit'),
  stop: byId('stop'),
  saved: byId('saved'),
  status: byId('status'),
  error: byId('error'),
  score: byId('score'),
  submission: byId('submission'),
  tests: byId('tests'),
  runs: byId('runs'),
  runChoice: byId('run-choice'),
  runSummary: byId('run-summary'),
  results: byId('results'),
};
const starter = byId('starter').value;
const runner = new Runner(workbench.worker);
/** What the button that runs the exercise's loop says: "Run data sets", "Run paths". */
const runsLabel = ui.runLoops.textContent;

// ---------------------------------------------------------------------------------------
// The file: edited, saved as it is typed, reset, downloaded and uploaded.

/**
 * What both editors share: long lines wrap (a phone shows a third of an 80-column line),
 * and the text area has a name and a place in the keyboard's order, so that a screen
 * reader says what it is and the keyboard reaches (and scrolls) it, editable or not.
 */
const editorBasics = (name) => [
  basicSetup,
  javascript(),
  EditorView.lineWrapping,
  EditorView.contentAttributes.of({ 'aria-label': name, tabindex: '0' }),
];

const editor = new EditorView({
  doc: localStorage.getItem(STORAGE.source) ?? starter,
  extensions: [
    ...editorBasics('your code'),
    EditorView.updateListener.of((update) => {
      if (update.docChanged) edited();
    }),
  ],
  parent: byId('editor'),
});

function source() {
  return editor.state.doc.toString();
}

function replaceSource(text) {
  editor.dispatch({ changes: { from: 0, to: editor.state.doc.length, insert: text } });
}

function edited() {
  try {
    localStorage.setItem(STORAGE.source, source());
    ui.saved.textContent = 'Saved in this browser.';
  } catch (error) {
    ui.saved.textContent = `Not saved in this browser (${error.message}): download your file to keep it.`;
  }
  if (state.source !== null && state.source !== source()) {
    ui.tests.classList.add('stale');
    ui.status.textContent = 'Your code changed since these results: run the tests again.';
  }
}

byId('reset').addEventListener('click', () => {
  if (source() === starter) return;
  if (confirm('Replace your code with the starter file? Your current code will be lost (download it first to keep it).')) {
    replaceSource(starter);
  }
});
byId('download').addEventListener('click', () => download(workbench.file, source(), 'text/javascript'));
// A real button, reachable with the keyboard, opens the file chooser.
byId('upload-button').addEventListener('click', () => byId('upload').click());
byId('upload').addEventListener('change', async (event) => {
  const file = event.target.files[0];
  event.target.value = '';
  if (!file) return;
  if (file.size > MAX_SOURCE) {
    showError(ui.error, `${file.name}: ${file.size} bytes; a file may have at most ${MAX_SOURCE / 1024} KB.`);
    return;
  }
  showError(ui.error, null);
  replaceSource(await file.text());
});

// ---------------------------------------------------------------------------------------
// Who submits, and the variant: the signed-in student's own, or, on a server without
// courses, the one the typed student id gives.

const state = {
  grader: null,
  job: null,
  seed: null,
  /** The harness's outputs so far, by function and by run name. */
  functions: new Map(),
  runs: new Map(),
  /** The views of the runs, by run name. */
  views: new Map(),
  /** The file the outputs are of. */
  source: null,
  result: null,
  busy: false,
  runView: null,
};

/**
 * Who is at the keyboard, as /api/me says: `mode` is 'open' (a server without courses:
 * anyone submits under any id), 'student' (signed in), 'staff', 'anonymous' (a server with
 * courses, nobody signed in) or 'unknown' (the server did not answer); `assignment` is the
 * student's assignment of this exercise, with its `standing` as the server decided it
 * when it answered (open, late with the penalty a submission would lose, or closed).
 */
const account = { about: me, mode: 'unknown', assignment: null };

function modeOf(about) {
  if (about.courses === false) return 'open';
  if (about.courses !== true) return 'unknown';
  if (!about.member) return 'anonymous';
  return about.member.role === 'student' ? 'student' : 'staff';
}

/** Takes in what /api/me answered, and shows it. */
function know(about) {
  account.about = about;
  account.mode = modeOf(about);
  account.assignment = (about.assignments ?? []).find((a) => a.lab === LAB) ?? null;
  showWho();
  showVariant();
  scheduleRefresh();
}

/** Asks the server again who is signed in (after a submission, say), keeping what is known if it does not answer. */
async function refreshAccount() {
  const about = await whoAmI();
  if (about.courses !== null) know(about);
}

/** How often the standing is asked for again: it reads in minutes. */
const REFRESH_MS = 60_000;
let refreshTimer = null;

/**
 * Asks the server again in a minute, or sooner when the standing changes before then (the
 * due date or the cutoff passes): the server alone says whether a submission is late and
 * what it costs. A page out of sight asks again when it is seen.
 */
function scheduleRefresh() {
  clearTimeout(refreshTimer);
  if (account.mode !== 'student') return;
  const standing = account.assignment?.standing;
  const next = standing?.state === 'open' ? standing.seconds_left
    : standing?.state === 'late' ? standing.seconds_to_cutoff : Infinity;
  const wait = Math.min(REFRESH_MS, 1000 * (next + 1));
  refreshTimer = setTimeout(() => {
    if (document.visibilityState === 'visible') refreshAccount();
  }, wait);
}

document.addEventListener('visibilitychange', () => {
  if (document.visibilityState === 'visible' && account.mode === 'student') refreshAccount();
});

const localTime = (at) => new Date(at).toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });

/** The assignment's due date and what a submission now would be (as the server last said): on time, late and its penalty, or refused. */
function deadline() {
  const a = account.assignment;
  if (!a) return 'Your course has not opened this exercise yet: submissions are not taken.';
  const { standing } = a;
  const due = `Due ${localTime(a.due)}`;
  if (standing.state === 'open') return `${due}: ${span(standing.seconds_left)} left.`;
  if (standing.state === 'closed') {
    return `${due}: closed, no more submissions are taken (the last were taken until ${localTime(a.cutoff)}).`;
  }
  const cost = standing.penalty > 0 ? `loses ${percent(standing.penalty)} of its score` : 'has no late penalty';
  return `${due}: a submission now is ${span(standing.late_seconds)} late and ${cost}; ` +
    `the last are taken until ${localTime(a.cutoff)}, ${span(standing.seconds_to_cutoff)} from now.`;
}

/** The line above the toolbar: who submits, and the deadline. */
function showWho() {
  const { about, mode } = account;
  const member = about.member;
  const name = member ? member.name || member.login : '';
  ui.studentField.hidden = !(mode === 'open' || mode === 'unknown');
  ui.who.hidden = false;
  ui.who.dataset.mode = mode;
  if (mode === 'open') {
    ui.who.replaceChildren('This server runs no course: anyone may submit under any student id, and results are open to all.');
  } else if (mode === 'unknown') {
    ui.who.replaceChildren(`The server did not say who is signed in (${about.problem}): a submission may be refused.`);
  } else if (mode === 'anonymous') {
    ui.who.replaceChildren('This server runs a course: ', link('/signin', 'sign in'),
      ` with your code to submit. Run tests and ${runsLabel} need no sign-in (on the public variant).`);
  } else if (mode === 'staff') {
    ui.who.replaceChildren(`Signed in as ${name} (${member.role} of ${member.course}): staff do not submit. ` +
      `Run tests and ${runsLabel} work, on the public variant.`);
  } else {
    const who = element('span', 'signed-in', `Signed in as ${name} (${member.login}), ${member.course}`);
    const when = element('span', 'deadline', member.dropped
      ? `You are no longer on the roster of ${member.course}: new submissions are not taken.`
      : deadline());
    when.id = 'deadline';
    ui.who.replaceChildren(who, ' (', link('/me', 'your submissions'), '). ', when);
  }
}

ui.student.value = localStorage.getItem(STORAGE.student) ?? '';

/** Whether the student id typed in the field says who submits (a server without courses). */
const typedId = () => account.mode === 'open' || account.mode === 'unknown';

/**
 * A variant named by the link (`?seed=N`), as the results of estlab's Gradescope and
 * PrairieLearn packages name it, or null.
 */
const linkedSeed = (() => {
  const text = new URLSearchParams(location.search).get('seed') ?? '';
  return /^\d{1,16}$/.test(text) && Number(text) < 2 ** 53 ? Number(text) : null;
})();

function seed() {
  if (account.mode === 'student') return account.about.seed;
  if (linkedSeed !== null) return linkedSeed;
  const student = typedId() ? ui.student.value.trim() : '';
  return student ? estlab.studentSeed(COURSE, student) : PUBLIC_VARIANT;
}

/**
 * Says which variant the id gives, as it is typed; results of another variant stay until
 * the next run, and the note says whose they are.
 */
function showVariant() {
  const current = seed();
  let note;
  if (account.mode === 'student') note = `your own variant: seed ${current}`;
  else if (linkedSeed !== null) {
    note = `the variant of your link: seed ${current}`;
    if (typedId()) note += ' (Submit sends your file to this server, which grades the variant of your student id)';
  }
  else if (!typedId()) note = `the public variant, seed ${current}`;
  else if (ui.student.value.trim()) note = `your own variant: seed ${current}`;
  else note = `no id yet: the public variant, seed ${current}`;
  const shown = state.functions.size + state.runs.size > 0;
  if (shown && state.seed !== null && state.seed !== current) {
    note += `. The results below are for seed ${state.seed}: run again for this variant.`;
  }
  ui.seed.textContent = note;
}

/** Makes the grader of the current seed (at a run), forgetting results of another one. */
function useSeed() {
  const current = seed();
  if (state.seed === current) return showVariant();
  state.grader?.free();
  state.grader = new estlab.Grader(LAB, current);
  state.job = JSON.parse(state.grader.job());
  state.seed = current;
  state.functions.clear();
  state.runs.clear();
  state.views.clear();
  state.source = null;
  showVariant();
  render();
}

ui.student.addEventListener('input', showVariant);
ui.student.addEventListener('change', () => {
  localStorage.setItem(STORAGE.student, ui.student.value.trim());
  showVariant();
});

// ---------------------------------------------------------------------------------------
// Running: each phase of the job in the worker, under its time limit.

function setBusy(busy) {
  state.busy = busy;
  for (const button of [ui.runTests, ui.runLoops, ui.submit, ...ui.tests.querySelectorAll('button')]) button.disabled = busy;
  ui.stop.disabled = !busy;
}

/** Runs `phases` of `kind` on the current file, storing each output in `into`. */
async function runPhases(kind, phases, into, after = () => {}) {
  if (state.busy) return;
  useSeed();
  const text = source();
  if (state.source !== text) {
    state.functions.clear();
    state.runs.clear();
    state.views.clear();
    state.source = text;
  }
  showError(ui.error, null);
  setBusy(true);
  try {
    for (const phase of phases) {
      const what = kind === 'function' ? phase.function : phase.name;
      ui.status.textContent = `Running ${what}…`;
      const output = await runner.phase(kind, text, phase, (during) => {
        ui.status.textContent = `Running ${what}: ${during}`;
      });
      into.set(what, output);
      after(phase, output);
      render();
      if (output.stopped?.cause === 'you stopped it') break;
    }
  } finally {
    setBusy(false);
    render();
  }
}

function runTests(functions) {
  useSeed();
  const phases = state.job.functions.filter((phase) => !functions || functions.includes(phase.function));
  return runPhases('function', phases, state.functions);
}

/** Runs the exercise's loop with the student's functions: every run of the job. */
function runLoops() {
  useSeed();
  return runPhases('run', state.job.runs, state.runs, (phase, output) => {
    state.views.delete(phase.name);
    try {
      state.views.set(phase.name, RUNS.collect(state.grader, phase, output));
    } catch {
      // The run's test says what went wrong.
    }
  });
}

/**
 * After a run started from the toolbar: what it gave (the status and the score) under
 * the buttons, announced to a screen reader, and the results brought into view when they
 * lie off the screen (below the editor, on a phone).
 */
function reportRun() {
  ui.runSummary.textContent = ui.score.hidden ? ui.status.textContent : `${ui.status.textContent} ${ui.score.textContent}`;
  ui.runSummary.hidden = false;
  const { top } = ui.results.getBoundingClientRect();
  if (top < 0 || top > window.innerHeight - 100) ui.results.scrollIntoView({ block: 'start' });
}

ui.runTests.addEventListener('click', async () => {
  await runTests(null);
  reportRun();
});
ui.runLoops.addEventListener('click', async () => {
  await runLoops();
  reportRun();
});
ui.stop.addEventListener('click', () => runner.cancel());
ui.runChoice.addEventListener('change', showRun);

// ---------------------------------------------------------------------------------------
// The verdict: the wasm build grades the outputs so far, as the server grades a submission.

/** Whether the test of `key` ran: a function's, or a run's (`square`; `o3` of `o3/sequential`). */
function testRan(key) {
  if (state.functions.has(key)) return true;
  return [...state.runs.keys()].some((name) => name === key || name.startsWith(`${key}/`));
}

/** The Run button of a function's test, or nothing for a run's test. */
function runButton(key) {
  if (!state.job.functions.some((phase) => phase.function === key)) return null;
  const button = element('button', 'run', 'Run');
  button.type = 'button';
  button.disabled = state.busy;
  button.title = `Run the tests of ${key} only`;
  button.setAttribute('aria-label', button.title);
  button.addEventListener('click', () => runTests([key]));
  return button;
}

function render() {
  if (!state.grader) return;
  const outputs = { functions: [...state.functions.values()], runs: [...state.runs.values()] };
  const result = JSON.parse(state.grader.grade(JSON.stringify(outputs)));
  state.result = result;
  ui.tests.classList.toggle('stale', state.source !== null && state.source !== source());
  ui.tests.replaceChildren(...result.tests.map((test) => {
    const key = testKey(test);
    return testItem(test, { ran: testRan(key), id: `test-${key}`, action: runButton(key) });
  }));
  const ran = result.tests.filter((test) => testRan(testKey(test)));
  if (ran.length === 0) {
    ui.score.hidden = true;
    if (!state.busy) ui.status.textContent = 'Nothing run yet.';
  } else {
    ui.score.hidden = false;
    const passed = ran.filter((test) => test.status === 'passed').length;
    const notRun = result.tests.length - ran.length;
    const todo = ran.filter((test) => notImplemented(test, testKey(test))).map(testKey);
    ui.score.textContent = `In your browser: ${fmt(result.points, 4)} of ${result.max_points} points (${Math.round(100 * result.score)}%), ` +
      `${passed} of ${result.tests.length} tests pass` + (notRun ? `, ${notRun} not run yet.` : '.') +
      (todo.length ? ` ${todo.length === 1 ? '1 function' : `${todo.length} functions`} not implemented yet: ${todo.join(', ')}.` : '');
    if (!state.busy && !ui.tests.classList.contains('stale')) ui.status.textContent = 'Done.';
  }
  showRuns();
}

// ---------------------------------------------------------------------------------------
// The runs, each with its exercise's views.

function showRuns() {
  const names = [...state.views.keys()];
  ui.runs.hidden = names.length === 0;
  if (!names.length) return;
  const chosen = names.includes(ui.runChoice.value) ? ui.runChoice.value : names[0];
  ui.runChoice.replaceChildren(...names.map((name) => new Option(name, name, false, name === chosen)));
  showRun();
}

function showRun() {
  const view = state.views.get(ui.runChoice.value);
  if (!view) return;
  state.runView ??= new RUNS.View(ui.runs);
  state.runView.show(view);
}

// ---------------------------------------------------------------------------------------
// Submitting: the server stores the file, grades it on its own, and says so. A refusal
// shows the server's reason; nothing here ever touches the editor.

async function submit() {
  const text = source();
  const body = { source: text, lab: LAB };
  if (typedId()) {
    const student = ui.student.value.trim();
    if (account.mode === 'open' && !student) {
      showError(ui.error, 'Enter your student id before you submit: the server grades your own variant.');
      ui.student.focus();
      return;
    }
    if (student) Object.assign(body, { student, course: COURSE });
  }
  showError(ui.error, null);
  ui.submit.disabled = true;
  ui.submission.hidden = false;
  ui.submission.dataset.status = 'queued';
  ui.submission.replaceChildren(element('p', 'verdict', 'Sending your file…'));
  let answer;
  try {
    const response = await fetch('/api/submissions', {
      method: 'POST',
      headers: { 'content-type': 'application/json' },
      body: JSON.stringify(body),
    });
    answer = await response.json().catch(() => ({}));
    if (!response.ok) {
      refused(answer.error ?? `${response.status} ${response.statusText}`, response.status);
      return;
    }
    const submission = await pollSubmission(answer.url, (during) => {
      if (during.status !== 'graded') renderSubmission(ui.submission, during);
    });
    showSubmission(submission, text);
  } catch (error) {
    ui.submission.dataset.status = 'failed';
    ui.submission.replaceChildren(element('p', 'verdict', answer?.id
      ? `Submission ${answer.id} is stored, but its grade could not be read: ${error.message}. Your code is still here.`
      : `The submission did not go through: ${error.message}. Your code is still here; try again.`));
  } finally {
    ui.submit.disabled = state.busy;
    // The deadline's standing, the history, a session that ended: as the server has them now.
    if (account.mode !== 'open') await refreshAccount();
  }
}

/** The server did not take the file: its reason, and for someone not signed in, where to sign in. */
function refused(message, status) {
  ui.submission.dataset.status = 'refused';
  const line = element('p', 'verdict', `Not submitted: ${message}`);
  if (status === 401) {
    line.append(' ', link('/signin', 'Sign in'), ' with the code your teacher gave you, then submit again: your file stays in this browser.');
  }
  ui.submission.replaceChildren(line);
}

function showSubmission(submission, text) {
  let comparison = '';
  const mine = state.result;
  const complete = mine && state.source === text && state.seed === submission.seed &&
    mine.tests.every((test) => testRan(testKey(test)));
  if (complete && submission.result?.gradable) {
    comparison = mine.points === submission.result.points ? 'The same as in your browser.' : `In your browser: ${fmt(mine.points, 4)} points.`;
  }
  renderSubmission(ui.submission, submission, { comparison });
  if (account.mode === 'student') {
    ui.submission.append(element('p', 'links'));
    ui.submission.lastChild.append(link(`${location.pathname}?submission=${submission.id}`, `Open submission ${submission.id}`),
      ' · ', link('/me', 'all your submissions'));
  }
}

ui.submit.addEventListener('click', submit);

// ---------------------------------------------------------------------------------------
// An earlier submission (?submission=ID): its file read-only beside its result, to load
// into the editor.

const viewer = {
  box: byId('viewer'),
  title: byId('viewer-title'),
  facts: byId('viewer-facts'),
  error: byId('viewer-error'),
  panes: byId('viewer-panes'),
  code: byId('viewer-code'),
  result: byId('viewer-result'),
  load: byId('load-submission'),
  /** The submission shown, and the read-only editor of its file. */
  id: null,
  source: null,
  view: null,
};

function showSource(text) {
  viewer.view ??= new EditorView({
    doc: '',
    extensions: [...editorBasics('the code submitted, read-only'), EditorView.editable.of(false)],
    parent: byId('viewer-source'),
  });
  viewer.view.dispatch({ changes: { from: 0, to: viewer.view.state.doc.length, insert: text } });
}

async function openSubmission(id) {
  if (viewer.id === id) return;
  viewer.id = id;
  viewer.source = null;
  viewer.title.textContent = `Submission ${id}`;
  viewer.facts.textContent = '';
  viewer.load.hidden = true;
  viewer.panes.hidden = true;
  viewer.result.replaceChildren();
  showError(viewer.error, null);
  const url = `/api/submissions/${encodeURIComponent(id)}`;
  let submission;
  try {
    submission = await getJson(url);
  } catch (error) {
    const signIn = error.status === 404 && account.mode === 'anonymous' ? ' Sign in to see your own.' : '';
    showError(viewer.error, error.status === 404
      ? `There is no such submission of yours (${id}).${signIn}`
      : `Submission ${id} could not be read: ${error.message}`);
    return;
  }
  if (submission.lab !== LAB) {
    const own = WORKBENCHES[submission.lab];
    if (own === undefined) {
      showError(viewer.error, `Submission ${id} is of the exercise ${submission.lab}, which this server no longer has a workbench for.`);
      return;
    }
    // A link to the wrong workbench (an old one, or one edited by hand): the submission
    // opens in its own exercise's, where its file can be loaded, run and submitted again.
    viewer.facts.textContent = `Submission ${id} is of the exercise ${submission.lab}: opening it in that exercise's workbench…`;
    window.location.replace(`${own}?submission=${encodeURIComponent(id)}`);
    return;
  }
  const late = lateness(submission);
  const by = account.mode === 'student' ? '' : ` by ${submission.student}`;
  viewer.facts.textContent = `Submitted${by} ${localTime(submission.submitted_at)}, ${late}; variant seed ${submission.seed}.`;
  viewer.panes.hidden = false;
  const hasSource = typeof submission.source === 'string';
  viewer.code.hidden = !hasSource;
  if (hasSource) {
    viewer.source = submission.source;
    viewer.load.hidden = false;
    showSource(submission.source);
  } else {
    viewer.facts.textContent += ' This server runs no course and shows nobody\'s code, only results.';
  }
  renderSubmission(viewer.result, submission, { open: true });
  if (submission.status !== 'graded') {
    pollSubmission(url, (during) => {
      if (viewer.id === id) renderSubmission(viewer.result, during, { open: true });
    }).catch((error) => {
      if (viewer.id === id) showError(viewer.error, `Submission ${id}: ${error.message}`);
    });
  }
}

/** Shows what the address asks for: a submission, or the workbench. */
async function route() {
  const id = new URLSearchParams(window.location.search).get('submission');
  viewer.box.hidden = id === null;
  byId('workbench').hidden = id !== null;
  if (id === null) {
    showRuns();
    editor.requestMeasure();
  } else {
    ui.runs.hidden = true;
    await openSubmission(id);
  }
}

function backToEditor() {
  window.history.pushState(null, '', location.pathname);
  return route();
}

byId('back-to-editor').addEventListener('click', (event) => {
  event.preventDefault();
  backToEditor();
});
viewer.load.addEventListener('click', async () => {
  const text = viewer.source;
  if (text === null) return;
  if (text !== source()) {
    const replace = confirm(`Replace the file in your editor with submission ${viewer.id}? ` +
      'The file there now, saved in this browser, will be lost (download it first to keep it).');
    if (!replace) return;
    replaceSource(text);
  }
  const id = viewer.id;
  await backToEditor();
  ui.saved.textContent = `Submission ${id} is in the editor, saved in this browser.`;
  editor.focus();
});
window.addEventListener('popstate', route);

know(me);
useSeed();
render();
await route();
document.body.dataset.ready = 'true';
