// A student's part in peer review, on the questions page: the rounds they take part in,
// each sheet handed to them (anonymous, numbered for them) read beside the model answers
// and marked right or wrong with a comment, saved and then handed in; and, once a round
// is closed, what their own sheet received.
import { markdownBlock, renderInto } from '../markdown.js';
import { getJson, postJson } from '../results/http.js';
import { element } from '../results/render.js';

/** @typedef {import('../types/StudentRound').StudentRound} StudentRound */
/** @typedef {import('../types/SheetView').SheetView} SheetView */
/** @typedef {import('../types/Question').Question} Question */
/** @typedef {import('../types/Answer').Answer} Answer */
/** @typedef {import('../types/Mark').Mark} Mark */

/** @param {number | null | undefined} share */
const percent = (share) => (share === null || share === undefined ? '–' : `${Math.round(share * 100)} %`);

/**
 * An answer as its author gave it, read only.
 *
 * @param {Question} question
 * @param {Answer | undefined} answer
 */
export function shownAnswer(question, answer) {
  if (!answer) return element('p', 'unanswered', '(not answered)');
  switch (answer.kind) {
    case 'text':
      return markdownBlock('given', answer.value || '(empty)');
    case 'number':
      return element('p', 'given', `${answer.value}${question.kind === 'number' && question.unit ? ` ${question.unit}` : ''}`);
    case 'choice':
      return markdownBlock('given', question.kind === 'choice' ? question.options[answer.value] ?? '' : String(answer.value));
    case 'table': {
      const table = element('table', 'answer-table given');
      if (question.kind === 'table') {
        const head = element('tr');
        head.append(element('th'), ...question.columns.map((c) => {
          const th = element('th');
          renderInto(th, c);
          return th;
        }));
        table.append(head);
        question.rows.forEach((row, r) => {
          const tr = element('tr');
          const th = element('th');
          renderInto(th, row);
          tr.append(th, ...question.columns.map((_, c) => element('td', null, answer.value[r]?.[c] ?? '')));
          table.append(tr);
        });
      }
      return table;
    }
  }
  return element('p');
}

/**
 * The sheet `number` of `round`, to mark, drawn into `panel`.
 *
 * @param {HTMLElement} panel
 * @param {string} api the assignment's API path
 * @param {number} round
 * @param {number} number
 * @param {() => void} changed called once the review is handed in
 */
async function openSheet(panel, api, round, number, changed) {
  const url = `${api}/reviews/${round}/${number}`;
  /** @type {SheetView} */
  const sheet = await getJson(url);
  const readOnly = sheet.submitted || !sheet.open;
  const heading = element('h4', null, `Sheet ${number}${sheet.submitted ? ' (handed in)' : ''}`);
  heading.tabIndex = -1;
  const form = element('form', 'review-sheet');
  /** @type {{ id: string, right: HTMLInputElement, wrong: HTMLInputElement, comment: HTMLTextAreaElement }[]} */
  const fields = [];
  sheet.set.questions.forEach((question, i) => {
    const given = sheet.answers.find((a) => a.question === question.id);
    if (!given) return;
    const mark = sheet.marks.find((m) => m.question === question.id);
    const article = element('article', 'question');
    const title = element('h5', null, `${i + 1}. `);
    const named = element('span');
    renderInto(named, question.title);
    title.append(...(named.firstElementChild?.childNodes ?? []));
    article.append(title, markdownBlock('prompt', question.prompt));
    article.append(element('h6', null, 'The answer'), shownAnswer(question, given.answer));
    if (question.model) article.append(element('h6', null, 'Model answer'), markdownBlock('model', question.model));
    const group = element('fieldset', 'mark');
    group.append(element('legend', null, `Your mark for question ${i + 1}`));
    const choice = (value, text) => {
      const label = element('label', 'choice');
      const radio = element('input');
      radio.type = 'radio';
      radio.name = `mark-${question.id}`;
      radio.value = value;
      radio.disabled = readOnly;
      radio.checked = mark !== undefined && mark.correct === (value === 'right');
      label.append(radio, ` ${text}`);
      group.append(label);
      return radio;
    };
    const right = choice('right', 'Right');
    const wrong = choice('wrong', 'Wrong');
    const comment = element('textarea');
    comment.rows = 2;
    comment.value = mark?.comment ?? '';
    comment.disabled = readOnly;
    comment.setAttribute('aria-label', `Your comment on question ${i + 1}`);
    group.append(comment);
    article.append(group);
    fields.push({ id: question.id, right, wrong, comment });
    form.append(article);
  });
  const said = element('p', 'status');
  said.setAttribute('role', 'status');
  /** @param {boolean} submit */
  const send = async (submit) => {
    /** @type {Mark[]} */
    const marks = fields
      .filter((f) => f.right.checked || f.wrong.checked)
      .map((f) => ({ question: f.id, correct: f.right.checked, comment: f.comment.value }));
    try {
      await postJson(url, { marks, submit });
      said.textContent = submit ? 'Handed in.' : 'Saved.';
      if (submit) changed();
    } catch (error) {
      said.textContent = `Not ${submit ? 'handed in' : 'saved'}: ${error instanceof Error ? error.message : error}`;
    }
  };
  if (!readOnly) {
    const save = element('button', null, 'Save marks');
    save.type = 'button';
    save.addEventListener('click', () => send(false));
    const submit = element('button', null, 'Hand in the review');
    submit.type = 'submit';
    form.addEventListener('submit', (event) => {
      event.preventDefault();
      send(true);
    });
    const buttons = element('p', 'toolbar');
    buttons.append(save, ' ', submit);
    form.append(buttons);
  }
  form.append(said);
  panel.replaceChildren(heading, form);
  heading.focus();
}

/**
 * What the student's own sheet received in a closed round.
 *
 * @param {StudentRound} round
 */
function received(round) {
  const box = element('div', 'received');
  const tally = round.received?.tally;
  if (!round.received || !tally) return box;
  const bonus = tally.bonus === null ? '' : tally.bonus ? ': the bonus is yours' : ': no bonus';
  box.append(element('p', 'tally', `Your sheet: ${tally.correct} of ${tally.marks} marks right, ${percent(tally.share)}${bonus}.`));
  const list = element('ul', 'marks');
  for (const mark of round.received.marks) {
    const item = element('li', null, `${mark.question}: ${mark.correct ? 'right' : 'wrong'}${mark.comment ? ` (“${mark.comment}”)` : ''}`);
    list.append(item);
  }
  box.append(list);
  return box;
}

/**
 * The student's rounds, drawn into `section` (hidden when they take part in none).
 *
 * @param {HTMLElement} section
 * @param {string} api
 */
export async function showReviews(section, api) {
  /** @type {StudentRound[]} */
  const rounds = await getJson(`${api}/reviews`);
  section.hidden = rounds.length === 0;
  const heading = element('h2', null, 'Peer review');
  heading.id = 'review-title';
  const boxes = rounds.map((round) => {
    const box = element('section', 'round');
    box.dataset.round = String(round.id);
    box.append(element('h3', null, `Round ${round.id}: ${round.title} (${round.open ? 'open' : 'closed'})`));
    const panel = element('div', 'sheet-panel');
    if (round.sheets.length) {
      const list = element('ul', 'sheets');
      for (const sheet of round.sheets) {
        const item = element('li');
        const open = element('button', null, `${sheet.submitted ? 'Read' : 'Review'} sheet ${sheet.number}`);
        open.type = 'button';
        open.addEventListener('click', () => openSheet(panel, api, round.id, sheet.number, () => showReviews(section, api))
          .catch((error) => panel.replaceChildren(element('p', 'status', `Sheet ${sheet.number} could not be read: ${error instanceof Error ? error.message : error}`))));
        item.append(open, sheet.submitted ? ' handed in' : ' to review');
        list.append(item);
      }
      box.append(element('p', null, round.open
        ? 'Mark each answer right or wrong against the model answer, with a comment where it helps; save as you go, and hand each review in when every answer is marked. Whose sheet it is stays unknown to you.'
        : 'The round is closed.'), list);
    }
    box.append(received(round), panel);
    return box;
  });
  section.replaceChildren(heading, ...boxes);
  section.setAttribute('aria-labelledby', heading.id);
}
