// The student's workbench for the EKF localization: an editor that keeps the file in
// this browser, the tests (the student's functions run in a Web Worker, the wasm build of
// `labs` makes the cases and judges the outputs, exactly as the server does), the runs
// on the data sets with the lab's views, and the submission to the server.
import { javascript } from '@codemirror/lang-javascript';
import { EditorView, basicSetup } from 'codemirror';
import { byId, download, showError } from '../controls.js';
import { RunView, collect } from '../ekf/runview.js';
import { fmt } from '../format.js';
import { Runner } from '../student/runner.js';
import { loadEstlab } from '../wasm.js';

const COURSE = 'el2320';
/** The seed of the variant graded without a student id, as `estlab grade` without --seed. */
const PUBLIC_VARIANT = 1;
const MAX_SOURCE = 256 * 1024;
const STORAGE = { source: 'estlab:ekf-localization:source', student: 'estlab:student' };
/** Failing cases shown in detail per test, and differing elements per case. */
const SHOWN = { failures: 2, mismatches: 12 };

const estlab = await loadEstlab();
const ui = {
  student: byId('student'),
  seed: byId('seed'),
  runTests: byId('run-tests'),
  runDatasets: byId('run-datasets'),
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
};
const starter = byId('starter').value;
const runner = new Runner(byId('workbench').dataset.worker);

// ---------------------------------------------------------------------------------------
// The file: edited, saved as it is typed, reset, downloaded and uploaded.

const editor = new EditorView({
  doc: localStorage.getItem(STORAGE.source) ?? starter,
  extensions: [
    basicSetup,
    javascript(),
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
byId('download').addEventListener('click', () => download('ekf_localization.js', source(), 'text/javascript'));
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
// The variant: the student's id gives the seed of their own cases and data sets.

const state = {
  grader: null,
  job: null,
  seed: null,
  /** The harness's outputs so far, by function and by run name. */
  functions: new Map(),
  runs: new Map(),
  /** The views of the data-set runs, by run name. */
  views: new Map(),
  /** The file the outputs are of. */
  source: null,
  result: null,
  busy: false,
  runView: null,
};

ui.student.value = localStorage.getItem(STORAGE.student) ?? '';

function seed() {
  const student = ui.student.value.trim();
  return student ? estlab.studentSeed(COURSE, student) : PUBLIC_VARIANT;
}

/**
 * Says which variant the id gives, as it is typed; results of another variant stay until
 * the next run, and the note says whose they are.
 */
function showVariant() {
  const current = seed();
  let note = ui.student.value.trim()
    ? `your own variant: seed ${current}`
    : `no id yet: the public variant, seed ${current}`;
  const shown = state.functions.size + state.runs.size > 0;
  if (shown && state.seed !== current) {
    note += `. The results below are for seed ${state.seed}: run again for this variant.`;
  }
  ui.seed.textContent = note;
}

/** Makes the grader of the current seed (at a run), forgetting results of another one. */
function useSeed() {
  const current = seed();
  if (state.seed === current) return showVariant();
  state.grader?.free();
  state.grader = new estlab.Grader(current);
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
  for (const button of [ui.runTests, ui.runDatasets, ui.submit, ...ui.tests.querySelectorAll('button')]) button.disabled = busy;
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

function runDatasets() {
  useSeed();
  return runPhases('run', state.job.runs, state.runs, (phase, output) => {
    state.views.delete(phase.name);
    let run;
    let dataset;
    try {
      run = state.grader.studentRun(JSON.stringify(output));
      dataset = state.grader.dataset(phase.name);
      state.views.set(phase.name, collect(run, dataset));
    } catch {
      // The run's test says what went wrong.
    } finally {
      run?.free();
      dataset?.free();
    }
  });
}

ui.runTests.addEventListener('click', () => runTests(null));
ui.runDatasets.addEventListener('click', runDatasets);
ui.stop.addEventListener('click', () => runner.cancel());
ui.runChoice.addEventListener('change', showRun);

// ---------------------------------------------------------------------------------------
// The verdict: the wasm build grades the outputs so far, as the server grades a submission.

/** The test's key: the function it tests, or the data set of a data-set test. */
function testKey(test) {
  const [first] = test.name.split(/[:\s]/);
  return first;
}

function testRan(key) {
  if (state.functions.has(key)) return true;
  return [...state.runs.keys()].some((name) => name.startsWith(`${key}/`));
}

function render() {
  if (!state.grader) return;
  const outputs = { functions: [...state.functions.values()], runs: [...state.runs.values()] };
  const result = JSON.parse(state.grader.grade(JSON.stringify(outputs)));
  state.result = result;
  ui.tests.classList.toggle('stale', state.source !== null && state.source !== source());
  ui.tests.replaceChildren(...result.tests.map(testItem));
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
  document.body.dataset.ready = 'true';
  showRuns();
}

/** Whether every failing case of a function's test throws the starter file's "not implemented". */
function notImplemented(test, key) {
  const failures = test.failures ?? [];
  return test.status === 'failed' && test.points === 0 && failures.length > 0 &&
    failures.every((failure) => (failure.error ?? '').includes(`${key}: not implemented`));
}

function element(tag, className, text) {
  const node = document.createElement(tag);
  if (className) node.className = className;
  if (text !== undefined) node.textContent = text;
  return node;
}

function testItem(test) {
  const key = testKey(test);
  const ran = testRan(key);
  const item = element('li', 'test');
  item.id = `test-${key}`;
  item.dataset.status = ran ? test.status : 'not-run';
  const head = element('div', 'head');
  const mark = { passed: '✓', failed: '✗', 'not-run': '○' }[item.dataset.status];
  head.append(element('span', 'mark', mark), element('span', 'name', test.name),
    element('span', 'points', ran ? `${fmt(test.points, 3)} / ${test.max_points}` : 'not run'));
  const isFunction = state.job.functions.some((phase) => phase.function === key);
  if (isFunction) {
    const button = element('button', 'run', 'Run');
    button.type = 'button';
    button.disabled = state.busy;
    button.title = `Run the tests of ${key} only`;
    button.setAttribute('aria-label', button.title);
    button.addEventListener('click', () => runTests([key]));
    head.append(button);
  }
  item.append(head);
  if (!ran) return item;
  const details = element('details');
  const todo = ran && notImplemented(test, key);
  // A function still as the starter file has it: one line, not a case-by-case account.
  details.open = test.status === 'failed' && !todo;
  details.append(element('summary', null, test.status === 'passed' ? 'passed'
    : todo ? `not implemented yet: every case throws "${key}: not implemented"` : 'why it fails'));
  const failures = (test.failures ?? []).slice(0, todo ? 1 : SHOWN.failures);
  const shown = new Set(failures.map((failure) => failure.case));
  const { summary, rest } = partsOf(test.message, shown);
  details.append(element('pre', 'message', summary));
  for (const failure of failures) details.append(failureView(failure));
  if (rest) details.append(element('pre', 'message more', rest));
  item.append(details);
  return item;
}

/**
 * A function test's message in three parts: the lines before its first failing case (the
 * count, what stopped the code), then the cases shown in detail (`shown`, by id), then the
 * lines of the failing cases not shown in detail and the count of the rest.
 */
function partsOf(message, shown) {
  const summary = [];
  const rest = [];
  let current = summary;
  for (const line of message.split('\n')) {
    const id = line.match(/^(\w+\/\w+) \(/)?.[1];
    if (id) current = shown.has(id) ? null : rest;
    else if (line.startsWith('... and ')) current = rest;
    current?.push(line);
  }
  return { summary: summary.join('\n'), rest: rest.join('\n') };
}

const json = (value) => JSON.stringify(value, null, 1);

function failureView(failure) {
  const box = element('div', 'failure');
  box.append(element('h4', null, `${failure.case}: ${failure.note}`));
  if (failure.error) box.append(element('p', 'thrown', failure.error));
  if (failure.hint) box.append(element('p', 'hint', `Hint: ${failure.hint.text}`));
  const mismatches = failure.mismatches ?? [];
  if (mismatches.length) {
    const table = element('table', 'mismatches');
    const header = element('tr');
    for (const title of ['element', 'expected', 'got', '']) header.append(element('th', null, title));
    table.append(header);
    for (const m of mismatches.slice(0, SHOWN.mismatches)) {
      const row = element('tr');
      row.append(element('td', null, m.path), element('td', null, show(m.expected)), element('td', null, show(m.got)),
        element('td', 'problem', m.problem.replaceAll('_', ' ')));
      table.append(row);
    }
    box.append(table);
    // The server keeps the first few differing elements and counts the rest.
    const differing = Math.max(failure.differing ?? 0, mismatches.length);
    const listed = Math.min(mismatches.length, SHOWN.mismatches);
    if (differing > listed) box.append(element('p', 'more', `… and ${differing - listed} more elements differ.`));
  }
  const all = element('details', 'case');
  all.append(element('summary', null, 'the arguments, the expected output and yours'));
  all.append(element('pre', null, `arguments: ${json(failure.args)}\nexpected: ${json(failure.expected)}\ngot: ${failure.got === undefined ? '(nothing)' : json(failure.got)}`));
  box.append(all);
  return box;
}

function show(value) {
  return typeof value === 'number' ? fmt(value, 12) : JSON.stringify(value);
}

// ---------------------------------------------------------------------------------------
// The data-set runs, with the experiment page's views.

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
  state.runView ??= new RunView(ui.runs, 'code');
  state.runView.show(view, true);
  byId('summary').textContent = view.report;
  showPrefix(ui.runChoice.value);
}

/**
 * Where the run is shown, what part of the data set grading runs through (a prefix, so
 * that the server grades within a second), and a link to the whole data set on the
 * experiment page with the same update.
 */
function showPrefix(name) {
  const phase = state.job.runs.find((run) => run.name === name);
  const note = byId('prefix');
  if (!phase) {
    note.replaceChildren();
    return;
  }
  const readings = phase.steps.reduce((n, step) => n + step.z[0].length, 0);
  const seconds = phase.steps.reduce((t, step) => t + step.delta_t, 0);
  const link = element('a', null, 'the whole data set on the experiment page');
  link.href = `/ekf?kind=${phase.dataset}&seed=${state.grader.dataSeed(name)}&mode=${phase.mode}`;
  note.replaceChildren(
    `Grading runs the first ${readings} readings of this data set (${fmt(seconds, 3)} s of ${phase.steps.length} time steps), ` +
      'which keeps a grading on the server within a second; the map shows only that much of the path. See ',
    link, ' with the reference filter.');
}

// ---------------------------------------------------------------------------------------
// Submitting: the server stores the file, grades it on its own, and says so.

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

async function submit() {
  const student = ui.student.value.trim();
  if (!student) {
    showError(ui.error, 'Enter your student id before you submit: the server grades your own variant.');
    ui.student.focus();
    return;
  }
  showError(ui.error, null);
  ui.submit.disabled = true;
  ui.submission.hidden = false;
  ui.submission.dataset.status = 'queued';
  ui.submission.textContent = 'Sending your file…';
  const text = source();
  try {
    const response = await fetch('/api/submissions', {
      method: 'POST',
      headers: { 'content-type': 'application/json' },
      body: JSON.stringify({ student, course: COURSE, source: text }),
    });
    const answer = await response.json().catch(() => ({}));
    if (!response.ok) throw new Error(answer.error ?? `${response.status} ${response.statusText}`);
    ui.submission.textContent = `Submission ${answer.id} is stored; the server is grading it…`;
    let submission;
    do {
      await sleep(400);
      const poll = await fetch(answer.url);
      submission = await poll.json();
      if (!poll.ok) throw new Error(submission.error ?? `${poll.status} ${poll.statusText}`);
    } while (submission.status !== 'graded');
    showSubmission(submission, text);
  } catch (error) {
    ui.submission.dataset.status = 'failed';
    ui.submission.textContent = `The submission did not go through: ${error.message}. Your code is still here; try again.`;
  } finally {
    ui.submit.disabled = state.busy;
  }
}

function showSubmission(submission, text) {
  const result = submission.result;
  ui.submission.dataset.status = result.gradable ? 'graded' : 'not-gradable';
  if (!result.gradable) {
    ui.submission.textContent = `Submission ${submission.id} could not be graded (${result.reason}). That costs you nothing: submit again.`;
    return;
  }
  let line = `The server's grade for submission ${submission.id}: ${fmt(result.points, 4)} of ${result.max_points} points (${Math.round(100 * result.score)}%).`;
  const mine = state.result;
  const complete = mine && state.source === text && state.seed === submission.seed &&
    mine.tests.every((test) => testRan(testKey(test)));
  if (complete) {
    line += mine.points === result.points ? ' The same as in your browser.' : ` In your browser: ${fmt(mine.points, 4)} points.`;
  }
  if (result.hidden_cases) {
    // The browser knows only the shown cases; the server's differ at every submission.
    const hidden = result.tests.flatMap((test) => (test.failures ?? []).filter((f) => f.hidden));
    line += ' The server also graded hidden cases of every function and ran your filter on data sets you have not seen, which your browser cannot: a function earns the smaller of its pass rates on the shown and the hidden cases.';
    for (const failure of hidden) {
      line += `\nHidden case ${failure.case} (${failure.note}) fails` +
        (failure.error ? `: ${failure.error}` : '') + (failure.hint ? `. Hint: ${failure.hint.text}` : '.');
    }
  }
  ui.submission.textContent = line;
}

ui.submit.addEventListener('click', submit);

useSeed();
render();
