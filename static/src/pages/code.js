// The student's workbench of an exercise (the page's `data-lab`, its folder
// `data-folder`): an editor that keeps the file in this browser, the tests (the student's
// functions run in a Web Worker, the wasm build of `labs` makes the cases and judges the
// outputs, exactly as the server does), the runs of the exercise's loop with the
// exercise's own views of them (its folder's `web/workbench.js`), and
// the submission to the server: as the signed-in student once the server runs courses,
// under any id on a server without. With `?submission=ID` it shows an earlier submission,
// read-only, beside its result. The parts live in ../workbench/; this page wires them.
import workbenches from 'estlab:workbenches';
import { byId } from '../controls.js';
import { loadEstlab } from '../wasm.js';
import { Editor } from '../workbench/editor.js';
import { Identity, whoAmI } from '../workbench/identity.js';
import { Runs } from '../workbench/running.js';
import { Submitter } from '../workbench/submitting.js';
import { Viewer } from '../workbench/viewing.js';

const workbench = byId('workbench').dataset;
/** The exercise of this workbench, by name (`labs::Exercise`). */
const LAB = workbench.lab;

// How this exercise's runs are collected from the harness's outputs, and drawn: its
// folder's `web/workbench.js`.
const [estlab, me, { runs: RUNS }] = await Promise.all([
  loadEstlab(), whoAmI(), workbenches[workbench.folder](),
]);
const ui = {
  who: byId('who'),
  studentField: byId('student-field'),
  student: byId('student', HTMLInputElement),
  seed: byId('seed'),
  runTests: byId('run-tests', HTMLButtonElement),
  runLoops: byId('run-datasets', HTMLButtonElement),
  submit: byId('submit', HTMLButtonElement),
  stop: byId('stop', HTMLButtonElement),
  saved: byId('saved'),
  status: byId('status'),
  error: byId('error'),
  score: byId('score'),
  submission: byId('submission'),
  tests: byId('tests'),
  runs: byId('runs'),
  runChoice: byId('run-choice', HTMLSelectElement),
  runSummary: byId('run-summary'),
  results: byId('results'),
};

// The parts need each other: the editor's changes mark the results stale, and the note
// on the variant says when the results are of another. The callbacks run only once
// every part is made.
const editor = new Editor({
  // The file is saved per exercise and language (JavaScript's where it always was), and
  // the language chosen per exercise.
  key: (language) => (language === 'javascript' ? `estlab:${LAB}:source` : `estlab:${LAB}:${language}`),
  // Each language's starter, as the page holds them.
  starters: Object.fromEntries([...document.querySelectorAll('textarea[data-starter]')]
    .map((area) => [/** @type {HTMLElement} */ (area).dataset.starter, /** @type {HTMLTextAreaElement} */ (area).value])),
  file: workbench.file,
  saved: ui.saved,
  error: ui.error,
  onEdit: (text) => runs.edited(text),
});
const identity = new Identity({
  estlab,
  lab: LAB,
  ui: { who: ui.who, studentField: ui.studentField, student: ui.student, seed: ui.seed },
  // What the button that runs the exercise's loop says: "Run data sets", "Run paths".
  runsLabel: ui.runLoops.textContent,
  resultsSeed: () => runs.shownSeed(),
});
const runs = new Runs({
  estlab,
  lab: LAB,
  exerciseRuns: RUNS,
  worker: workbench.worker,
  editor,
  identity,
  ui: {
    runTests: ui.runTests,
    runLoops: ui.runLoops,
    submit: ui.submit,
    stop: ui.stop,
    status: ui.status,
    error: ui.error,
    score: ui.score,
    tests: ui.tests,
    runs: ui.runs,
    runChoice: ui.runChoice,
    runSummary: ui.runSummary,
    results: ui.results,
  },
});
new Submitter({
  lab: LAB,
  editor,
  identity,
  runs,
  ui: { submit: ui.submit, student: ui.student, error: ui.error, submission: ui.submission },
});
const viewer = new Viewer({ lab: LAB, identity, editor, back: backToEditor });

/** Shows what the address asks for: a submission, or the workbench. */
async function route() {
  const id = new URLSearchParams(window.location.search).get('submission');
  viewer.box.hidden = id === null;
  byId('workbench').hidden = id !== null;
  if (id === null) {
    runs.showRuns();
    editor.view.requestMeasure();
  } else {
    ui.runs.hidden = true;
    await viewer.open(id);
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
window.addEventListener('popstate', route);

identity.know(me);
// A course may take this exercise's files in some languages only.
editor.restrict(identity.assignment?.languages ?? null);
runs.useSeed();
runs.render();
await route();
document.body.dataset.ready = 'true';
