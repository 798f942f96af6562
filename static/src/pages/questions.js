// The written questions of an assignment (/courses/{course}/{lab}/questions). A student
// answers each question in the field its kind takes (words with math, a number, a
// choice, a table) and every answer is saved as they type, a moment after they stop,
// until their cutoff; a written answer is shown typeset beside the field. Staff read the
// sets in full: the model answers and what numbers and choices are checked against, and
// their instructors edit the sets' TOML here. Above the sets, peer review: a student's
// sheets to review and their own marks; staff's rounds.
import { markdownBlock, renderInto } from '../markdown.js';
import { showReviews } from '../questions/reviewing.js';
import { showRounds } from '../questions/rounds.js';
import { showSets } from '../questions/sets.js';
import { getJson, postJson } from '../results/http.js';
import { element } from '../results/render.js';

/** @typedef {import('../types/Written').Written} Written */
/** @typedef {import('../types/QuestionSet').QuestionSet} QuestionSet */
/** @typedef {import('../types/Question').Question} Question */
/** @typedef {import('../types/Answer').Answer} Answer */
/** @typedef {import('../types/SavedAnswer').SavedAnswer} SavedAnswer */

/** How long after the last keystroke an answer is saved, ms. */
const SAVE_AFTER = 800;

const root = /** @type {HTMLElement} */ (document.getElementById('questions'));
const { course = '', lab = '' } = root.dataset;
const api = `/api/courses/${encodeURIComponent(course)}/labs/${encodeURIComponent(lab)}`;
const status = /** @type {HTMLElement} */ (document.getElementById('questions-status'));
const note = /** @type {HTMLElement} */ (document.getElementById('questions-note'));

/** @param {string} iso */
const moment = (iso) => new Date(iso).toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });

/**
 * Saves one question's answer a moment after the last change, and says how it went.
 */
class Saver {
  /**
   * @param {number} part
   * @param {string} question
   * @param {HTMLElement} said where the outcome is said
   */
  constructor(part, question, said) {
    this.part = part;
    this.question = question;
    this.said = said;
    /** @type {ReturnType<typeof setTimeout> | undefined} */
    this.timer = undefined;
  }

  /** @param {() => Answer} read the answer as the fields hold it now */
  changed(read) {
    clearTimeout(this.timer);
    this.said.textContent = 'Not saved yet…';
    this.timer = setTimeout(() => this.save(read()), SAVE_AFTER);
  }

  /** @param {Answer} answer */
  async save(answer) {
    try {
      /** @type {SavedAnswer} */
      const saved = await postJson(`${api}/answers`, { part: this.part, question: this.question, answer });
      this.said.textContent = `Saved ${moment(saved.saved_at)}.`;
      this.said.classList.remove('error');
    } catch (error) {
      this.said.textContent = `Not saved: ${error instanceof Error ? error.message : error}`;
      this.said.classList.add('error');
    }
  }
}

/**
 * The field (or fields) of `question` for a student, filled with `saved`; each change
 * goes to `saver`.
 *
 * @param {Question} question
 * @param {string} label what the question is called, for the fields' labels
 * @param {Answer | undefined} saved
 * @param {Saver} saver
 * @param {boolean} closed whether the cutoff has passed (the fields are read only)
 */
function answerField(question, label, saved, saver, closed) {
  const box = element('div', 'answer');
  switch (question.kind) {
    case 'text': {
      const area = element('textarea');
      area.rows = 5;
      area.setAttribute('aria-label', `Your answer to ${label} (Markdown, $…$ for math)`);
      area.value = saved?.kind === 'text' ? saved.value : '';
      const preview = element('div', 'markdown preview');
      preview.setAttribute('role', 'group');
      preview.setAttribute('aria-label', `Your answer to ${label}, typeset`);
      const show = () => {
        renderInto(preview, area.value);
        preview.hidden = !area.value.trim();
      };
      area.addEventListener('input', () => {
        show();
        saver.changed(() => ({ kind: 'text', value: area.value }));
      });
      area.disabled = closed;
      show();
      box.append(area, preview);
      break;
    }
    case 'number': {
      const input = element('input');
      input.type = 'text';
      input.inputMode = 'decimal';
      input.setAttribute('aria-label', `Your answer to ${label}${question.unit ? `, in ${question.unit}` : ''}`);
      input.value = saved?.kind === 'number' ? saved.value : '';
      input.addEventListener('input', () => saver.changed(() => ({ kind: 'number', value: input.value })));
      input.disabled = closed;
      box.append(input);
      if (question.unit) box.append(' ', element('span', 'unit', question.unit));
      break;
    }
    case 'choice': {
      const group = element('fieldset', 'choices');
      group.append(element('legend', null, `Your choice for ${label}`));
      question.options.forEach((option, i) => {
        const choice = element('label', 'choice');
        const radio = element('input');
        radio.type = 'radio';
        radio.name = `${saver.part}-${question.id}`;
        radio.value = String(i);
        radio.checked = saved?.kind === 'choice' && saved.value === i;
        radio.disabled = closed;
        radio.addEventListener('change', () => saver.changed(() => ({ kind: 'choice', value: i })));
        choice.append(radio, markdownBlock('option', option));
        group.append(choice);
      });
      box.append(group);
      break;
    }
    case 'table': {
      const cells = saved?.kind === 'table' ? saved.value : [];
      const table = element('table', 'answer-table');
      const head = element('tr');
      head.append(element('th'));
      for (const column of question.columns) {
        const th = element('th');
        th.scope = 'col';
        renderInto(th, column);
        head.append(th);
      }
      table.append(element('thead'));
      table.tHead?.append(head);
      /** @type {HTMLInputElement[][]} */
      const inputs = [];
      const body = element('tbody');
      question.rows.forEach((row, r) => {
        const tr = element('tr');
        const th = element('th');
        th.scope = 'row';
        renderInto(th, row);
        tr.append(th);
        inputs.push(question.columns.map((column, c) => {
          const input = element('input');
          input.type = 'text';
          input.value = cells[r]?.[c] ?? '';
          input.setAttribute('aria-label', `${label}: ${row}, ${column}`);
          input.disabled = closed;
          input.addEventListener('input', () => saver.changed(() => ({
            kind: 'table', value: inputs.map((line) => line.map((i) => i.value)),
          })));
          const td = element('td');
          td.append(input);
          tr.append(td);
          return input;
        }));
        body.append(tr);
      });
      table.append(body);
      const scroll = element('div', 'table-scroll');
      scroll.tabIndex = 0;
      scroll.setAttribute('role', 'region');
      scroll.setAttribute('aria-label', `the table of ${label} (scrolls sideways on a narrow screen)`);
      scroll.append(table);
      box.append(scroll);
      break;
    }
  }
  return box;
}

/**
 * What staff read of `question` beside its prompt: what it is checked against and its
 * model answer.
 *
 * @param {Question} question
 */
function key(question) {
  const box = element('div', 'key');
  if (question.kind === 'number' && question.answer !== null) {
    box.append(element('p', 'checked', `Checked against ${question.answer} ± ${question.tolerance}${question.unit ? ` ${question.unit}` : ''}.`));
  }
  if (question.kind === 'choice' && question.correct !== null) {
    box.append(element('p', 'checked', `Checked against option ${question.correct + 1}.`));
  }
  if (question.model) {
    box.append(element('h4', null, 'Model answer'), markdownBlock('model', question.model));
  }
  return box;
}

/**
 * @param {Written} written
 */
function show(written) {
  const closed = !written.staff && !written.open;
  if (written.staff) {
    note.textContent = `You read the questions as staff: with the model answers and what numbers and choices are checked against${written.own ? ' (the exercise\'s own sets)' : ''}. Students answer here, and their answers are saved as they type.`;
  } else if (closed) {
    note.textContent = written.cutoff && Date.now() > new Date(written.cutoff).getTime()
      ? `The cutoff was ${moment(written.cutoff)}: your answers are kept as they were.`
      : 'Your answers are kept as they are: no more are taken from you.';
  } else {
    note.replaceChildren(
      `Your answers are saved as you type, until the cutoff${written.cutoff ? `, ${moment(written.cutoff)}` : ''}. Write math between $ signs: `,
      element('code', null, '$\\bar\\Sigma_t$'),
      ' is ',
    );
    const example = element('span');
    renderInto(example, '$\\bar\\Sigma_t$');
    note.append(...(example.firstElementChild?.childNodes ?? []), '.');
  }
  const sets = /** @type {HTMLElement} */ (document.getElementById('question-sets'));
  sets.replaceChildren(...written.sets.map((set, part) => {
    const section = element('section', 'question-set');
    const heading = element('h2', null, set.title);
    heading.id = `set-${part}`;
    section.setAttribute('aria-labelledby', heading.id);
    section.append(heading);
    if (set.introduction) section.append(markdownBlock('introduction', set.introduction));
    set.questions.forEach((question, i) => {
      const label = `question ${i + 1}`;
      const article = element('article', 'question');
      article.id = `q-${part}-${question.id}`;
      const title = element('h3');
      title.append(`${i + 1}. `);
      const named = element('span');
      renderInto(named, question.title);
      title.append(...(named.firstElementChild?.childNodes ?? []));
      article.append(title, markdownBlock('prompt', question.prompt));
      if (written.staff) {
        // What students answer in, read only, and the key.
        const shown = new Saver(part, question.id, element('p'));
        article.append(answerField(question, label, undefined, shown, true), key(question));
      } else {
        const saved = written.answers.find((a) => a.part === part && a.question === question.id);
        const said = element('p', 'saved');
        said.setAttribute('role', 'status');
        if (saved) said.textContent = `Saved ${moment(saved.saved_at)}.`;
        const saver = new Saver(part, question.id, said);
        article.append(answerField(question, label, saved?.answer, saver, closed), said);
      }
      section.append(article);
    });
    return section;
  }));
}

async function load() {
  try {
    /** @type {Written} */
    const written = await getJson(`${api}/questions`);
    show(written);
    const review = /** @type {HTMLElement} */ (document.getElementById('peer-review'));
    if (written.staff) {
      const sources = /** @type {HTMLElement} */ (document.getElementById('question-sources'));
      sources.hidden = false;
      showSets(sources, api, written, (changed) => {
        show(changed);
        showRounds(review, api, changed.sets);
      });
      review.hidden = false;
      await showRounds(review, api, written.sets);
    } else {
      await showReviews(review, api);
    }
    document.body.dataset.ready = 'true';
  } catch (error) {
    status.textContent = `The questions could not be read: ${error instanceof Error ? error.message : error}`;
    document.body.dataset.ready = 'true';
  }
}

load();
