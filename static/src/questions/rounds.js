// Staff run peer review from the questions page: open a round for a question set (how
// many classmates review each sheet, and the share of right marks above which the bonus
// is earned), follow it (each student's reviews handed in, and the marks of their own
// sheet so far), let a student who answered late join, give a leaver's sheets to others,
// and close it, after which each student reads their marks.
import { getJson, postJson } from '../results/http.js';
import { element } from '../results/render.js';

/** @typedef {import('../types/RoundView').RoundView} RoundView */
/** @typedef {import('../types/QuestionSet').QuestionSet} QuestionSet */

/** @param {number | null} share */
const percent = (share) => (share === null ? '–' : `${Math.round(share * 100)} %`);

/**
 * A button that POSTs `body` to `url`, says how it went in `said`, and redraws.
 *
 * @param {string} text
 * @param {string} url
 * @param {unknown} body
 * @param {HTMLElement} said
 * @param {() => Promise<void>} redraw
 */
function action(text, url, body, said, redraw) {
  const button = element('button', null, text);
  button.type = 'button';
  button.addEventListener('click', async () => {
    try {
      await postJson(url, body);
      // Said once the rounds show it, so that what the status says is on the page.
      await redraw();
      said.textContent = `${text}: done.`;
    } catch (error) {
      said.textContent = `${text}: ${error instanceof Error ? error.message : error}`;
    }
  });
  return button;
}

/**
 * One round's table and actions.
 *
 * @param {RoundView} round
 * @param {string} api
 * @param {HTMLElement} said
 * @param {() => Promise<void>} redraw
 */
function roundBox(round, api, said, redraw) {
  const box = element('section', 'round');
  box.dataset.round = String(round.id);
  const open = round.closed_at === null;
  const reviews = round.students.reduce((n, s) => n + s.reviewing, 0);
  const handedIn = round.students.reduce((n, s) => n + s.submitted, 0);
  box.append(
    element('h3', null, `Round ${round.id}: ${round.title} (${open ? 'open' : 'closed'})`),
    element('p', null, `${round.students.length} sheets, ${round.per_sheet} reviews each; ${handedIn} of ${reviews} reviews handed in; the bonus above ${percent(round.bonus_above)} right.`),
  );
  const url = `${api}/rounds/${round.id}`;
  const table = element('table', 'round-table');
  const head = element('tr');
  for (const title of ['Student', 'Reviews handed in', 'Marks of their sheet', 'Right', 'Bonus', '']) {
    const th = element('th', null, title);
    th.scope = 'col';
    head.append(th);
  }
  table.append(head);
  for (const student of round.students) {
    const tr = element('tr');
    tr.dataset.student = student.student;
    const bonus = student.tally.bonus === null ? '–' : student.tally.bonus ? 'yes' : 'no';
    tr.append(
      element('td', null, `${student.name} (${student.student})`),
      element('td', null, `${student.submitted} of ${student.reviewing}`),
      element('td', null, String(student.tally.marks)),
      element('td', null, percent(student.tally.share)),
      element('td', null, bonus),
    );
    const cell = element('td');
    if (open && student.submitted < student.reviewing) {
      cell.append(action('Give their sheets to others', url, { action: 'reassign', student: student.student }, said, redraw));
    }
    tr.append(cell);
    table.append(tr);
  }
  const scroll = element('div', 'table-scroll');
  scroll.tabIndex = 0;
  scroll.setAttribute('role', 'region');
  scroll.setAttribute('aria-label', `round ${round.id}'s students (scrolls sideways on a narrow screen)`);
  scroll.append(table);
  box.append(scroll);
  if (open) {
    if (round.waiting.length) {
      const waiting = element('p', 'waiting', 'Answered since the round opened: ');
      for (const student of round.waiting) {
        waiting.append(action(`Let ${student} join`, url, { action: 'join', student }, said, redraw), ' ');
      }
      box.append(waiting);
    }
    box.append(element('p', 'toolbar'));
    box.lastElementChild?.append(action(`Close round ${round.id}`, url, { action: 'close' }, said, redraw));
  }
  return box;
}

/**
 * The rounds of the assignment and the form that opens one, drawn into `section`.
 *
 * @param {HTMLElement} section
 * @param {string} api
 * @param {QuestionSet[]} sets
 */
export async function showRounds(section, api, sets) {
  const heading = element('h2', null, 'Peer review rounds');
  heading.id = 'rounds-title';
  section.setAttribute('aria-labelledby', heading.id);
  const said = element('p', 'status');
  said.setAttribute('role', 'status');
  const list = element('div', 'rounds');
  const redraw = async () => {
    /** @type {RoundView[]} */
    const rounds = await getJson(`${api}/rounds`);
    list.replaceChildren(...rounds.map((round) => roundBox(round, api, said, redraw)));
  };

  const form = element('form', 'inline-form');
  const set = element('select');
  sets.forEach((s, i) => set.append(new Option(s.title, String(i))));
  const perSheet = element('input');
  perSheet.type = 'number';
  perSheet.min = '1';
  perSheet.max = '10';
  perSheet.value = '2';
  const bonus = element('input');
  bonus.type = 'number';
  bonus.min = '0';
  bonus.max = '99';
  bonus.value = '30';
  const labelled = (text, field) => {
    const label = element('label', null, `${text} `);
    label.append(field);
    return label;
  };
  const open = element('button', null, 'Open a round');
  open.type = 'submit';
  form.append(labelled('Set', set), labelled('Reviews of each sheet', perSheet), labelled('Bonus above, % right', bonus), open);
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    try {
      /** @type {RoundView} */
      const round = await postJson(`${api}/rounds`, {
        part: Number(set.value), per_sheet: Number(perSheet.value), bonus_above: Number(bonus.value) / 100,
      });
      await redraw();
      said.textContent = `Round ${round.id} is open: ${round.students.length} sheets handed out.`;
    } catch (error) {
      said.textContent = `No round opened: ${error instanceof Error ? error.message : error}`;
    }
  });
  const explain = element('p', 'note', 'A round hands each sheet of a set, as it stands, to classmates who answered it too (never their own, each sheet as often as every other); they mark each answer right or wrong against the model answer. Students who answer later may join; the sheets of one who left go to others. Once closed, each student reads their marks.');
  section.replaceChildren(heading, explain, form, said, list);
  await redraw();
}
