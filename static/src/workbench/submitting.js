// Submitting: the server stores the file, grades it on its own, and says so. A refusal
// shows the server's reason; nothing here ever touches the editor.
import { showError } from '../controls.js';
import { fmt } from '../format.js';
import { pollSubmission } from '../results/http.js';
import { element, link, renderSubmission } from '../results/render.js';
import { COURSE } from './identity.js';

/**
 * The Submit button's work: sends the file in `editor` as `identity` says who submits, and
 * shows the server's result beside the browser's (`runs`). `lab`: the exercise; `ui`: the
 * button (`submit`), the student id's field (`student`), the page's error box (`error`)
 * and where the submission is shown (`submission`).
 */
export class Submitter {
  constructor({ lab, editor, identity, runs, ui }) {
    this.lab = lab;
    this.editor = editor;
    this.identity = identity;
    this.runs = runs;
    this.ui = ui;
    ui.submit.addEventListener('click', () => this.submit());
  }

  async submit() {
    const { identity, ui } = this;
    const text = this.editor.source();
    const body = { source: text, lab: this.lab, language: this.editor.language };
    if (identity.typedId()) {
      const student = ui.student.value.trim();
      if (identity.mode === 'open' && !student) {
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
    /** @type {Partial<import('../types/Accepted').Accepted> & { error?: string }} What the server answered. */
    let answer;
    try {
      const response = await fetch('/api/submissions', {
        method: 'POST',
        headers: { 'content-type': 'application/json' },
        body: JSON.stringify(body),
      });
      answer = await response.json().catch(() => ({}));
      if (!response.ok) {
        this.refused(answer.error ?? `${response.status} ${response.statusText}`, response.status);
        return;
      }
      const submission = await pollSubmission(answer.url, (during) => {
        if (during.status !== 'graded') renderSubmission(ui.submission, during);
      });
      this.show(submission, text);
    } catch (error) {
      ui.submission.dataset.status = 'failed';
      ui.submission.replaceChildren(element('p', 'verdict', answer?.id
        ? `Submission ${answer.id} is stored, but its grade could not be read: ${error.message}. Your code is still here.`
        : `The submission did not go through: ${error.message}. Your code is still here; try again.`));
    } finally {
      ui.submit.disabled = this.runs.busy;
      // The deadline's standing, the history, a session that ended: as the server has them now.
      if (identity.mode !== 'open') await identity.refresh();
    }
  }

  /** The server did not take the file: its reason, and for someone not signed in, where to sign in. */
  refused(message, status) {
    const { submission } = this.ui;
    submission.dataset.status = 'refused';
    const line = element('p', 'verdict', `Not submitted: ${message}`);
    if (status === 401) {
      line.append(' ', link('/signin', 'Sign in'), ' with the code your teacher gave you, then submit again: your file stays in this browser.');
    }
    submission.replaceChildren(line);
  }

  /** The graded `submission` of `text`, compared with the browser's verdict when that is of the same file and variant. */
  show(submission, text) {
    const box = this.ui.submission;
    let comparison = '';
    const mine = this.runs.completeResult(text, submission.seed);
    if (mine && submission.result?.gradable) {
      // Where the file's own run was: this browser, or the server for another language.
      const where = this.editor.language === 'javascript' ? 'in your browser' : 'in your run on the server';
      comparison = mine.points === submission.result.points ? `The same as ${where}.` : `${where[0].toUpperCase()}${where.slice(1)}: ${fmt(mine.points, 4)} points.`;
    }
    renderSubmission(box, submission, { comparison });
    if (this.identity.mode === 'student') {
      box.append(element('p', 'links'));
      box.lastChild.append(link(`${location.pathname}?submission=${submission.id}`, `Open submission ${submission.id}`),
        ' · ', link('/me', 'all your submissions'));
    }
  }
}
