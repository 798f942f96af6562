// An earlier submission (?submission=ID): its file read-only beside its result, to load
// into the editor.
import { EditorView } from 'codemirror';
import { byId, showError } from '../controls.js';
import { lateness, localTime } from '../results/format.js';
import { getJson, pollSubmission } from '../results/http.js';
import { renderSubmission } from '../results/render.js';
import { site } from '../site.js';
import { Compartment } from '@codemirror/state';
import { LANGUAGES, editorBasics } from './editor.js';

/**
 * The viewer of a submission (#viewer). `lab`: this workbench's exercise; `identity`: who reads;
 * `editor`: the student's file, which the Load button replaces; `back()`: back to the
 * workbench.
 */
export class Viewer {
  constructor({ lab, identity, editor, back }) {
    this.lab = lab;
    this.identity = identity;
    this.box = byId('viewer');
    this.title = byId('viewer-title');
    this.facts = byId('viewer-facts');
    this.error = byId('viewer-error');
    this.panes = byId('viewer-panes');
    this.code = byId('viewer-code');
    this.result = byId('viewer-result');
    this.load = byId('load-submission');
    /** The submission shown, and the read-only editor of its file. */
    this.id = null;
    this.source = null;
    /** @type {import('../types/Language').Language} */
    this.language = 'javascript';
    this.view = null;
    /** @type {Compartment | null} */
    this.mode = null;
    this.load.addEventListener('click', async () => {
      const text = this.source;
      if (text === null) return;
      // Into the editor of its own language (the file of another stays kept in its own).
      editor.use(this.language);
      if (text !== editor.source()) {
        const replace = confirm(`Replace the file in your editor with submission ${this.id}? ` +
          'The file there now, saved in this browser, will be lost (download it first to keep it).');
        if (!replace) return;
        editor.replace(text);
      }
      const id = this.id;
      await back();
      editor.saved.textContent = `Submission ${id} is in the editor, saved in this browser.`;
      editor.view.focus();
    });
  }

  /**
   * @param {string} text
   * @param {import('../types/Language').Language} language
   */
  showSource(text, language) {
    this.mode ??= new Compartment();
    this.view ??= new EditorView({
      doc: '',
      extensions: [...editorBasics('the code submitted, read-only', this.mode, language), EditorView.editable.of(false)],
      parent: byId('viewer-source'),
    });
    this.view.dispatch({
      changes: { from: 0, to: this.view.state.doc.length, insert: text },
      effects: this.mode.reconfigure(LANGUAGES[language].mode()),
    });
  }

  async open(id) {
    if (this.id === id) return;
    this.id = id;
    this.source = null;
    this.title.textContent = `Submission ${id}`;
    this.facts.textContent = '';
    this.load.hidden = true;
    this.panes.hidden = true;
    this.result.replaceChildren();
    showError(this.error, null);
    const url = `/api/submissions/${encodeURIComponent(id)}`;
    /** @type {import('../types/Submission').Submission} */
    let submission;
    try {
      submission = await getJson(url);
    } catch (error) {
      const signIn = error.status === 404 && this.identity.mode === 'anonymous' ? ' Sign in to see your own.' : '';
      showError(this.error, error.status === 404
        ? `There is no such submission of yours (${id}).${signIn}`
        : `Submission ${id} could not be read: ${error.message}`);
      return;
    }
    if (submission.lab !== this.lab) {
      // Every exercise's workbench, from the server (`site.exercises`).
      const own = site.exercises[submission.lab]?.workbench;
      if (own === undefined) {
        showError(this.error, `Submission ${id} is of the exercise ${submission.lab}, which this server no longer has a workbench for.`);
        return;
      }
      // A link to the wrong workbench (an old one, or one edited by hand): the submission
      // opens in its own exercise's, where its file can be loaded, run and submitted again.
      this.facts.textContent = `Submission ${id} is of the exercise ${submission.lab}: opening it in that exercise's workbench…`;
      window.location.replace(`${own}?submission=${encodeURIComponent(id)}`);
      return;
    }
    const late = lateness(submission);
    const by = this.identity.mode === 'student' ? '' : ` by ${submission.student}`;
    this.facts.textContent = `Submitted${by} ${localTime(submission.submitted_at)}, ${late}; variant seed ${submission.seed}.`;
    this.panes.hidden = false;
    const hasSource = typeof submission.source === 'string';
    this.code.hidden = !hasSource;
    if (hasSource) {
      this.source = submission.source;
      this.language = submission.language;
      this.load.hidden = false;
      this.showSource(submission.source, submission.language);
    } else {
      this.facts.textContent += ' This server runs no course and shows nobody\'s code, only results.';
    }
    renderSubmission(this.result, submission, { open: true });
    if (submission.status !== 'graded') {
      pollSubmission(url, (during) => {
        if (this.id === id) renderSubmission(this.result, during, { open: true });
      }).catch((error) => {
        if (this.id === id) showError(this.error, `Submission ${id}: ${error.message}`);
      });
    }
  }
}
