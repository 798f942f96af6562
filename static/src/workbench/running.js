// Running the file in this browser: each phase of the exercise's job (a function's tests,
// a run of its loop) in a Web Worker under its time limit; the verdict, as the wasm build
// of `labs` grades the outputs so far exactly as the server grades a submission; and the
// runs, each with its exercise's views.
import { showError } from '../controls.js';
import { fmt } from '../format.js';
import { element, notImplemented, testItem } from '../results/render.js';
import { Runner } from '../sandbox/runner.js';
import { ServerRunner } from '../sandbox/server-runner.js';

/** @typedef {import('../types/Job').Job} Job */
/** @typedef {import('../types/RunPhase').RunPhase} RunPhase */
/** @typedef {import('../types/FunctionPhase').FunctionPhase} FunctionPhase */
/** @typedef {import('../types/FunctionOutput').FunctionOutput} FunctionOutput */
/** @typedef {import('../types/RunOutput').RunOutput} RunOutput */
/** @typedef {import('../types/GradeResult').GradeResult} GradeResult */
/** @typedef {import('estlab-wasm/estlab_wasm.js').Grader} Grader */

/**
 * An exercise's view of its runs, the `runs` its folder's `web/workbench.js` exports:
 * `collect` makes what a run's view shows from the grader, the run's phase (with the
 * exercise's own data) and what the harness reported, and throws when the report is not
 * drawable (the run's test says why); a `View` in the runs' section shows one at a time.
 *
 * @template [Shown=unknown]
 * @typedef {{
 *   collect: (grader: Grader, phase: RunPhase, output: RunOutput) => Shown,
 *   View: new (box: HTMLElement) => { show: (shown: Shown) => void },
 * }} ExerciseRuns
 */

/**
 * The tests and runs of the file in `editor` on the variant `identity` says. `estlab`:
 * the wasm build (the grader); `lab`: the exercise; `exerciseRuns`: how its runs are collected
 * from the harness's outputs, and drawn (the `runs` of its folder's `web/workbench.js`); `worker`: the Web
 * Worker's script; `ui`: the toolbar's buttons (`runTests`, `runLoops`, `stop`, and
 * `submit`, off while a run goes on), the lines under them (`status`, `score`,
 * `runSummary`, and `error`, the page's error box), the list of tests (`tests`), the runs'
 * section and its choice (`runs`, `runChoice`), and all of the results (`results`).
 */
export class Runs {
  /**
   * @param {{
   *   estlab: typeof import('estlab-wasm/estlab_wasm.js'),
   *   lab: string,
   *   exerciseRuns: ExerciseRuns,
   *   worker: string,
   *   editor: import('./editor.js').Editor,
   *   identity: import('./identity.js').Identity,
   *   ui: {
   *     runTests: HTMLButtonElement, runLoops: HTMLButtonElement, submit: HTMLButtonElement,
   *     stop: HTMLButtonElement, status: HTMLElement, score: HTMLElement, runSummary: HTMLElement,
   *     error: HTMLElement, tests: HTMLElement, runs: HTMLElement, runChoice: HTMLSelectElement,
   *     results: HTMLElement,
   *   },
   * }} parts
   */
  constructor({ estlab, lab, exerciseRuns, worker, editor, identity, ui }) {
    this.estlab = estlab;
    this.lab = lab;
    this.exerciseRuns = exerciseRuns;
    // JavaScript runs in this browser's Web Workers; another language on the server.
    this.runners = {
      browser: new Runner(worker),
      server: new ServerRunner({ lab, language: () => editor.language, seed: () => this.state.seed }),
    };
    this.editor = editor;
    this.identity = identity;
    this.ui = ui;
    this.state = {
      /** @type {Grader | null} */
      grader: null,
      /** @type {Job | null} */
      job: null,
      /** @type {number | null} */
      seed: null,
      /** @type {Map<string, FunctionOutput>} The harness's outputs so far, by function and by run name. */
      functions: new Map(),
      /** @type {Map<string, RunOutput>} */
      runs: new Map(),
      /** @type {Map<string, unknown>} The views of the runs, by run name. */
      views: new Map(),
      /** @type {string | null} The file the outputs are of. */
      source: null,
      /** @type {GradeResult | null} */
      result: null,
      busy: false,
      /** @type {{ show: (shown: unknown) => void } | null} */
      runView: null,
    };
    ui.runTests.addEventListener('click', async () => {
      await this.runTests(null);
      this.reportRun();
    });
    ui.runLoops.addEventListener('click', async () => {
      await this.runLoops();
      this.reportRun();
    });
    ui.stop.addEventListener('click', () => this.runner().cancel());
    ui.runChoice.addEventListener('change', () => this.showRun());
  }

  /** What runs the file in its language. */
  runner() {
    return this.editor.language === 'javascript' ? this.runners.browser : this.runners.server;
  }

  /** Whether a run goes on. */
  get busy() {
    return this.state.busy;
  }

  /** The seed of the results shown, or null while there are none. */
  shownSeed() {
    const { state } = this;
    return state.functions.size + state.runs.size > 0 ? state.seed : null;
  }

  /** The file changed to `text`: results of another file say so. */
  edited(text) {
    const { state, ui } = this;
    if (state.source !== null && state.source !== text) {
      ui.tests.classList.add('stale');
      ui.status.textContent = 'Your code changed since these results: run the tests again.';
    }
  }

  /** Makes the grader of the current seed (at a run), forgetting results of another one. */
  useSeed() {
    const { state } = this;
    const current = this.identity.seed();
    if (state.seed === current) return this.identity.showVariant();
    state.grader?.free();
    state.grader = new this.estlab.Grader(this.lab, current);
    state.job = JSON.parse(state.grader.job());
    state.seed = current;
    state.functions.clear();
    state.runs.clear();
    state.views.clear();
    state.source = null;
    this.identity.showVariant();
    this.render();
  }

  // -------------------------------------------------------------------------------------
  // Running: each phase of the job in the worker, under its time limit.

  setBusy(busy) {
    const { ui } = this;
    this.state.busy = busy;
    for (const button of [ui.runTests, ui.runLoops, ui.submit, ...ui.tests.querySelectorAll('button')]) button.disabled = busy;
    ui.stop.disabled = !busy;
  }

  /**
   * Runs `phases` of `kind` on the current file, storing each output in `into`.
   *
   * @template {FunctionPhase | RunPhase} P
   * @template {FunctionOutput | RunOutput} O
   * @param {'function' | 'run'} kind
   * @param {P[]} phases
   * @param {Map<string, O>} into
   * @param {(phase: P, output: O) => void} [after]
   */
  async runPhases(kind, phases, into, after = () => {}) {
    const { state, ui } = this;
    if (state.busy) return;
    this.useSeed();
    const text = this.editor.source();
    if (state.source !== text) {
      state.functions.clear();
      state.runs.clear();
      state.views.clear();
      state.source = text;
    }
    showError(ui.error, null);
    this.setBusy(true);
    try {
      for (const phase of phases) {
        const what = 'function' in phase ? phase.function : phase.name;
        ui.status.textContent = `Running ${what}…`;
        const output = await this.runner().phase(kind, text, phase, (during) => {
          ui.status.textContent = `Running ${what}: ${during}`;
        });
        into.set(what, output);
        after(phase, output);
        this.render();
        if (output.stopped?.cause === 'you stopped it') break;
      }
    } finally {
      this.setBusy(false);
      this.render();
    }
  }

  /** @param {string[] | null} functions The functions to test, or all. */
  runTests(functions) {
    const { state } = this;
    this.useSeed();
    const phases = state.job.functions.filter((phase) => !functions || functions.includes(phase.function));
    return this.runPhases('function', phases, state.functions);
  }

  /** Runs the exercise's loop with the student's functions: every run of the job. */
  runLoops() {
    const { state } = this;
    this.useSeed();
    return this.runPhases('run', state.job.runs, state.runs, (phase, output) => {
      state.views.delete(phase.name);
      try {
        state.views.set(phase.name, this.exerciseRuns.collect(state.grader, phase, output));
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
  reportRun() {
    const { ui } = this;
    ui.runSummary.textContent = ui.score.hidden ? ui.status.textContent : `${ui.status.textContent} ${ui.score.textContent}`;
    ui.runSummary.hidden = false;
    const { top } = ui.results.getBoundingClientRect();
    if (top < 0 || top > window.innerHeight - 100) ui.results.scrollIntoView({ block: 'start' });
  }

  // -------------------------------------------------------------------------------------
  // The verdict: the wasm build grades the outputs so far, as the server grades a submission.

  /**
   * Whether `test` ran: a function's, or a run's (`square`; `o3` of `o3/sequential`).
   *
   * @param {import('../types/Test').Test} test
   */
  testRan(test) {
    const { kind, name } = test.subject;
    if (kind === 'function') return this.state.functions.has(name);
    return [...this.state.runs.keys()].some((run) => run === name || run.startsWith(`${name}/`));
  }

  /** The browser's verdict on `text` for `seed` when every test of it ran, or null. */
  completeResult(text, seed) {
    const { state } = this;
    const mine = state.result;
    const complete = mine && state.source === text && state.seed === seed &&
      mine.tests.every((test) => this.testRan(test));
    return complete ? mine : null;
  }

  /**
   * The Run button of a function's test, or nothing for a run's test.
   *
   * @param {import('../types/Subject').Subject} subject
   */
  runButton(subject) {
    const { state } = this;
    const key = subject.name;
    if (subject.kind !== 'function' || !state.job.functions.some((phase) => phase.function === key)) return null;
    const button = element('button', 'run', 'Run');
    button.type = 'button';
    button.disabled = state.busy;
    button.title = `Run the tests of ${key} only`;
    button.setAttribute('aria-label', button.title);
    button.addEventListener('click', () => this.runTests([key]));
    return button;
  }

  render() {
    const { state, ui } = this;
    if (!state.grader) return;
    const outputs = { functions: [...state.functions.values()], runs: [...state.runs.values()] };
    /** @type {GradeResult} */
    const result = JSON.parse(state.grader.grade(JSON.stringify(outputs), this.editor.language));
    state.result = result;
    ui.tests.classList.toggle('stale', state.source !== null && state.source !== this.editor.source());
    ui.tests.replaceChildren(...result.tests.map((test) => testItem(test, {
      ran: this.testRan(test), id: `test-${test.subject.name}`, action: this.runButton(test.subject),
    })));
    const ran = result.tests.filter((test) => this.testRan(test));
    if (ran.length === 0) {
      ui.score.hidden = true;
      if (!state.busy) ui.status.textContent = 'Nothing run yet.';
    } else {
      ui.score.hidden = false;
      const passed = ran.filter((test) => test.status === 'passed').length;
      const notRun = result.tests.length - ran.length;
      const todo = ran.filter((test) => notImplemented(test)).map((test) => test.subject.name);
      // Where the tests ran: JavaScript in this browser, another language on the server.
      const where = this.editor.language === 'javascript' ? 'In your browser' : 'On the server';
      ui.score.textContent = `${where}: ${fmt(result.points, 4)} of ${result.max_points} points (${Math.round(100 * result.score)}%), ` +
        `${passed} of ${result.tests.length} tests pass` + (notRun ? `, ${notRun} not run yet.` : '.') +
        (todo.length ? ` ${todo.length === 1 ? '1 function' : `${todo.length} functions`} not implemented yet: ${todo.join(', ')}.` : '');
      if (!state.busy && !ui.tests.classList.contains('stale')) ui.status.textContent = 'Done.';
    }
    this.showRuns();
  }

  // -------------------------------------------------------------------------------------
  // The runs, each with its exercise's views.

  showRuns() {
    const { ui } = this;
    const names = [...this.state.views.keys()];
    ui.runs.hidden = names.length === 0;
    if (!names.length) return;
    const chosen = names.includes(ui.runChoice.value) ? ui.runChoice.value : names[0];
    ui.runChoice.replaceChildren(...names.map((name) => new Option(name, name, false, name === chosen)));
    this.showRun();
  }

  showRun() {
    const { state, ui } = this;
    const view = state.views.get(ui.runChoice.value);
    if (!view) return;
    state.runView ??= new this.exerciseRuns.View(ui.runs);
    state.runView.show(view);
  }
}
