// The report (/courses/{course}/{lab}/report): the runs the lab asks for, each with the
// student's own code on the whole data set and their analysis beside it (saved as they
// type, typeset beneath), then their answers to the question sets as they stand; handed
// in with the code, printed to PDF from the browser (a print style sheet: A4 figures, no
// controls). Staff see the class's reports (?student=ID opens one) and judge each part:
// pass or revise, with a comment the student reads.
import { markdownBlock, renderInto } from '../markdown.js';
import { shownAnswer } from '../questions/reviewing.js';
import { drawRuns, madeRuns } from '../report/runs.js';
import { getJson, postJson } from '../results/http.js';
import { element, link } from '../results/render.js';

/** @typedef {import('../types/ReportView').ReportView} ReportView */
/** @typedef {import('../types/ReportLine').ReportLine} ReportLine */
/** @typedef {import('../types/ReportPart').ReportPart} Part */
/** @typedef {import('../types/PartMark').PartMark} PartMark */
/** @typedef {import('../types/ReportState').ReportState} ReportState */

/** How long after the last keystroke an analysis is saved, ms. */
const SAVE_AFTER = 800;

const root = /** @type {HTMLElement} */ (document.getElementById('report'));
const { course = '', lab = '', folder = '' } = root.dataset;
/** Whether staff read the page: the class's reports, and any student's. */
const staffPage = root.dataset.staff === 'true';
const api = `/api/courses/${encodeURIComponent(course)}/labs/${encodeURIComponent(lab)}`;
const status = /** @type {HTMLElement} */ (document.getElementById('report-status'));
const errorBox = /** @type {HTMLElement} */ (document.getElementById('report-error'));
const body = /** @type {HTMLElement} */ (document.getElementById('report-body'));
const classBox = /** @type {HTMLElement} */ (document.getElementById('report-class'));
const runsStatus = /** @type {HTMLElement} */ (document.getElementById('report-runs-status'));

/** @param {unknown} error */
const message = (error) => (error instanceof Error ? error.message : String(error));

/** @param {string} iso */
const moment = (iso) => new Date(iso).toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });

/** What each state is called where people read it. @type {Record<ReportState, string>} */
const STATES = {
  draft: 'not handed in',
  handed_in: 'handed in, waiting for staff',
  accepted: 'accepted',
  revise: 'to be revised',
};

/** @param {string} text */
function fail(text) {
  errorBox.textContent = text;
  errorBox.hidden = false;
}

/**
 * The facts at the top: whose report, its state, the submission whose runs it shows, and
 * whether the lab is passed.
 *
 * @param {ReportView} view
 */
function facts(view) {
  const list = element('dl', 'report-facts');
  /** @type {[string, string][]} */
  const rows = [
    ['Student', `${view.name} (${view.student})`],
    ['Report', STATES[view.state] + (view.handed_in_at ? ` (hand-in ${view.handed_in}, ${moment(view.handed_in_at)})` : '')],
    ['Code', view.submission
      ? `submission ${view.submission.id} in ${view.submission.language}, ${moment(view.submission.submitted_at)}` +
        (view.submission.score === null ? '' : `, score ${Math.round(view.submission.score * 100)} %`)
      : 'no submission yet'],
    ['Lab', view.lab_passed ? 'passed' : `not passed yet (the submission that counts ${view.code_passes ? 'passes every test'
      : view.counting_score === null ? 'is none yet' : `scores ${Math.round(view.counting_score * 100)} %, not every test`}; report ${STATES[view.state]})`],
  ];
  if (view.reviewed_by && view.reviewed_at) rows.push(['Judged', `by ${view.reviewed_by}, ${moment(view.reviewed_at)}`]);
  for (const [term, value] of rows) list.append(element('dt', null, term), element('dd', null, value));
  return list;
}

/**
 * Staff's mark of a part, as the student reads it.
 *
 * @param {PartMark | undefined} mark
 */
function shownMark(mark) {
  if (!mark) return null;
  const box = element('div', `part-mark ${mark.verdict}`);
  box.append(element('p', 'verdict', mark.verdict === 'pass' ? 'Staff: passes.' : 'Staff: to be revised.'));
  if (mark.comment) box.append(markdownBlock('comment', mark.comment));
  return box;
}

/**
 * Staff's controls for a part: pass or revise, and a comment; `marks` keeps what they hold.
 *
 * @param {Part} part
 * @param {PartMark | undefined} mark the last judgement
 * @param {Map<string, () => PartMark>} marks
 */
function rubricField(part, mark, marks) {
  const box = element('fieldset', 'rubric');
  box.append(element('legend', null, `Your judgement of “${part.title}”`));
  const name = `verdict-${part.id}`;
  /** @type {HTMLInputElement[]} */
  const radios = [];
  for (const [verdict, text] of [['pass', 'passes'], ['revise', 'to be revised']]) {
    const label = element('label');
    const radio = document.createElement('input');
    radio.type = 'radio';
    radio.name = name;
    radio.value = verdict;
    radio.checked = mark?.verdict === verdict;
    radios.push(radio);
    label.append(radio, ` ${text}`);
    box.append(label);
  }
  const commentLabel = element('label', 'comment-field', 'Comment (Markdown, the student reads it)');
  const comment = document.createElement('textarea');
  comment.rows = 2;
  comment.value = mark?.comment ?? '';
  commentLabel.append(comment);
  box.append(commentLabel);
  marks.set(part.id, () => {
    const chosen = radios.find((r) => r.checked);
    if (!chosen) throw new Error(`“${part.title}” has no verdict yet: every part is judged`);
    return { part: part.id, verdict: /** @type {PartMark['verdict']} */ (chosen.value), comment: comment.value };
  });
  return box;
}

/**
 * The saves of analyses not sent yet or not answered yet, by run: each a function that
 * sends the field's text now (if it is waiting) and resolves once every save of it is
 * answered. Hand-in waits for them all.
 *
 * @type {Map<string, () => Promise<void>>}
 */
const pending = new Map();

/**
 * The student's analysis of a run: a field saved as they type (while the report is theirs
 * to change), one save after another, typeset beneath, which is what prints.
 *
 * @param {ReportView} view
 * @param {Part} part
 */
function analysis(view, part) {
  const box = element('div', 'analysis');
  const text = view.analyses[part.id] ?? '';
  const typeset = markdownBlock('analysis-text', text || '(no analysis yet)');
  if (!view.may_change) {
    box.append(element('h3', null, 'Analysis'), typeset);
    return box;
  }
  const label = element('label', 'analysis-field', `Your analysis of “${part.title}”`);
  const field = document.createElement('textarea');
  field.rows = 6;
  field.value = text;
  label.append(field);
  const said = element('p', 'saved');
  said.setAttribute('role', 'status');
  /** @type {ReturnType<typeof setTimeout> | undefined} */
  let timer;
  let waiting = false;
  /** The saves sent so far, one after another. */
  let saving = Promise.resolve();
  const send = () => {
    clearTimeout(timer);
    if (waiting) {
      waiting = false;
      const value = field.value;
      saving = saving.then(async () => {
        try {
          await postJson(`${api}/report/analyses`, { run: part.id, text: value });
          said.textContent = `Saved ${moment(new Date().toISOString())}.`;
          said.classList.remove('error');
        } catch (error) {
          said.textContent = `Not saved: ${message(error)}`;
          said.classList.add('error');
          throw error;
        }
      });
    }
    return saving;
  };
  pending.set(part.id, send);
  field.addEventListener('input', () => {
    renderInto(typeset, field.value || '(no analysis yet)');
    said.textContent = 'Not saved yet…';
    waiting = true;
    clearTimeout(timer);
    timer = setTimeout(() => send().catch(() => {}), SAVE_AFTER);
  });
  box.append(label, said, element('h3', 'print-only', 'Analysis'), typeset);
  return box;
}

/**
 * A question set with the student's answers, read only.
 *
 * @param {ReportView} view
 * @param {number} index
 */
function answersOf(view, index) {
  const set = view.sets[index];
  const box = element('div', 'report-answers');
  if (!set) return box;
  set.questions.forEach((question, i) => {
    const article = element('article', 'question');
    const title = element('h3');
    title.append(`${i + 1}. `);
    const named = element('span');
    renderInto(named, question.title);
    title.append(...(named.firstElementChild?.childNodes ?? []));
    const answer = view.answers.find((a) => a.part === index && a.question === question.id);
    article.append(title, markdownBlock('prompt', question.prompt), shownAnswer(question, answer?.answer));
    box.append(article);
  });
  return box;
}

/** The button that prints the report: on once its runs are drawn (or cannot be). */
const print = element('button', 'no-print', 'Print or save as PDF');
print.type = 'button';
print.addEventListener('click', () => window.print());

/**
 * The buttons: print, and for the student hand in (while the report is theirs to change).
 *
 * @param {ReportView} view
 */
function tools(view) {
  const box = element('div', 'report-tools no-print');
  box.append(print);
  if (view.staff || !view.may_change) return box;
  const handIn = element('button', 'primary', view.state === 'revise' ? 'Hand in the revised report' : 'Hand in the report');
  handIn.type = 'button';
  const submission = view.submission;
  handIn.disabled = !submission;
  handIn.addEventListener('click', async () => {
    if (!submission) return;
    if (!confirm(`Hand in the report? It shows the runs of submission ${submission.id}, and it cannot be changed until staff have read it.`)) return;
    try {
      await Promise.all([...pending.values()].map((send) => send()));
      show(await postJson(`${api}/report/hand-in`, { submission: submission.id }));
      status.textContent = 'Your report is handed in.';
    } catch (error) {
      fail(`Not handed in: ${message(error)}`);
    }
  });
  box.append(handIn);
  box.append(element('p', 'note', submission
    ? `Analyses are taken until the cutoff, ${moment(view.cutoff)}${view.state === 'revise' ? ' (a report sent back is taken after it too)' : ''}.`
    : 'Submit your code first: the report shows the runs of your latest submission.'));
  return box;
}

/**
 * Staff's button to save their judgement of every part.
 *
 * @param {ReportView} view
 * @param {Map<string, () => PartMark>} marks
 */
function rubricTools(view, marks) {
  const tools = element('div', 'report-tools no-print');
  const save = element('button', 'primary', 'Save the judgement');
  save.type = 'button';
  const said = element('p', 'saved');
  said.setAttribute('role', 'status');
  save.disabled = view.handed_in === 0;
  save.addEventListener('click', async () => {
    try {
      const parts = [...marks.values()].map((read) => read());
      show(await postJson(`${api}/reports/${encodeURIComponent(view.student)}/rubric`, { handed_in: view.handed_in, parts }));
      status.textContent = 'The judgement is saved: the student reads it now.';
    } catch (error) {
      said.textContent = `Not saved: ${message(error)}`;
      said.classList.add('error');
    }
  });
  tools.append(save, said);
  if (view.handed_in === 0) tools.append(element('p', 'note', 'The student has not handed the report in yet.'));
  return tools;
}

/**
 * The whole report.
 *
 * @param {ReportView} view
 */
function show(view) {
  errorBox.hidden = true;
  classBox.hidden = true;
  body.hidden = false;
  const marks = new Map();
  pending.clear();
  const byPart = new Map(view.rubric.map((m) => [m.part, m]));
  const heading = element('h2', 'report-title', `Report of ${view.name}`);
  /** @type {Map<string, HTMLElement>} */
  const boxes = new Map();
  const sections = view.parts.map((part, i) => {
    const section = element('section', part.ask ? 'report-run' : 'report-set');
    const title = element('h2', null, `${i + 1}. ${part.title}`);
    title.id = `part-${i}`;
    section.setAttribute('aria-labelledby', title.id);
    section.append(title);
    if (part.ask) {
      // The runs of the same submission drawn already stay as they are.
      let runBox = drawn?.submission === view.submission?.id ? drawn?.boxes.get(part.id) : undefined;
      if (!runBox) {
        runBox = element('div', 'run-views');
        runBox.append(element('p', 'note', view.submission ? 'The run is being made…' : 'No submission yet: nothing to run.'));
      }
      boxes.set(part.id, runBox);
      section.append(runBox, markdownBlock('ask', part.ask), analysis(view, part));
    } else {
      section.append(answersOf(view, Number(part.id.replace('questions-', '')) - 1));
    }
    const mark = byPart.get(part.id);
    if (view.staff) section.append(rubricField(part, mark, marks));
    else if (view.reviewed === view.handed_in) {
      const shown = shownMark(mark);
      if (shown) section.append(shown);
    }
    return section;
  });
  body.replaceChildren(heading, facts(view), tools(view), ...sections);
  if (view.staff) body.append(rubricTools(view, marks));
  if (view.staff) {
    body.prepend(link(location.pathname, '← the class’s reports'));
  }
  document.title = `Report of ${view.name} · ${course}`;
  const submission = view.submission?.id ?? null;
  if (drawn?.submission === submission) {
    drawn.boxes = boxes;
    return;
  }
  drawn = { submission, boxes };
  drawReportRuns(view, drawn);
}

/**
 * The runs drawn, or being drawn, and the submission they are of: a report shown again
 * after a hand-in or a judgement keeps them.
 *
 * @type {{ submission: number | null, boxes: Map<string, HTMLElement> } | null}
 */
let drawn = null;

/**
 * The runs, once the server has made them, into the boxes of `target` (which a later
 * showing of the report may take over), saying how it goes in the runs' own status line.
 *
 * @param {ReportView} view
 * @param {{ submission: number | null, boxes: Map<string, HTMLElement> }} target
 */
async function drawReportRuns(view, target) {
  const submission = view.submission;
  print.disabled = Boolean(submission);
  if (!submission) {
    document.body.dataset.ready = 'true';
    return;
  }
  const url = view.staff ? `${api}/reports/${encodeURIComponent(view.student)}/runs` : `${api}/report/runs`;
  /** @param {string} text */
  const notMade = (text) => {
    for (const box of target.boxes.values()) box.replaceChildren(element('p', 'note', text));
  };
  try {
    const runs = await madeRuns(url, runsStatus);
    if (runs.state === 'made') {
      await drawRuns({ lab, folder, seed: submission.seed, outputs: runs.outputs.runs, boxes: target.boxes });
      runsStatus.textContent = `The runs of submission ${runs.submission} on the whole data sets.`;
    } else if (runs.state === 'failed') {
      notMade('The run was not made.');
      runsStatus.textContent = `The runs could not be made: ${runs.reason}. Reload the page to try again.`;
    }
  } catch (error) {
    notMade('The run could not be read.');
    runsStatus.textContent = `The runs could not be read: ${message(error)}`;
  }
  print.disabled = false;
  document.body.dataset.ready = 'true';
}

/**
 * The class's reports, for staff.
 *
 * @param {ReportLine[]} lines
 */
function showClass(lines) {
  classBox.hidden = false;
  body.hidden = true;
  const table = element('table', 'report-class');
  const head = element('tr');
  const reviewed = lines[0]?.reviews.map((r) => `Review of set ${r.part + 1}`) ?? [];
  for (const title of ['Student', 'Code score', ...reviewed, 'Report', 'Lab']) head.append(element('th', null, title));
  table.append(element('caption', null, 'Each student’s code, review of their answers and report: open a report to read it and judge it.'), head);
  for (const line of lines) {
    const row = element('tr');
    const who = element('td');
    who.append(link(`?student=${encodeURIComponent(line.student)}`, `${line.name} (${line.student})`));
    if (line.dropped) who.append(' (dropped)');
    const reviews = line.reviews.map(({ tally }) => element('td', null, tally?.share == null ? '—'
      : `${Math.round(tally.share * 100)} %${tally.bonus ? ', bonus' : ''}`));
    row.append(
      who,
      element('td', null, line.score === null ? '—' : `${Math.round(line.score * 100)} %`),
      ...reviews,
      element('td', `state ${line.state}`, STATES[line.state]),
      element('td', null, line.lab_passed ? 'passed' : '—'),
    );
    table.append(row);
  }
  classBox.replaceChildren(element('h2', null, 'The class’s reports'), table);
  document.body.dataset.ready = 'true';
}

async function load() {
  const student = new URLSearchParams(location.search).get('student');
  try {
    if (!staffPage) show(await getJson(`${api}/report`));
    else if (student) show(await getJson(`${api}/reports/${encodeURIComponent(student)}`));
    else showClass(await getJson(`${api}/reports`));
  } catch (error) {
    fail(`The report could not be read: ${message(error)}`);
    document.body.dataset.ready = 'true';
  }
}

load();
