// The instructor's side of a course's exercise: the class at a glance (a table of the
// students, the scores and each test's pass rate as pictures, what the class gets wrong,
// the class challenge's ranking, regrading, the exports, the staff's actions), and one student's page (their
// submissions, one read beside its result or compared with another line by line, an
// extension). Everything comes from the course's API; the server checks that the reader
// is staff.
import { Compartment } from '@codemirror/state';
import { EditorView, basicSetup } from 'codemirror';
import { structuredPatch } from 'diff';
import { BarChart } from 'echarts/charts';
import * as echarts from 'echarts/core';
import { byId } from '../controls.js';
import { fmt } from '../format.js';
import { Plot, colours } from '../plots.js';
import { instant, lateness, moment, percent, zone } from '../results/format.js';
import { getJson, postJson } from '../results/http.js';
import { LANGUAGES } from '../workbench/editor.js';
import { element, fillTable, link, renderSubmission } from '../results/render.js';

/** @typedef {import('../types/Regrade').Regrade} Regrade */
/** @typedef {import('../types/Change').Change} Change */
/** @typedef {import('../types/ClassAnswer').ClassAnswer} ClassAnswer */
/** @typedef {import('../types/StudentAnswer').StudentAnswer} StudentAnswer */
/** @typedef {import('../types/Submission').Submission} Submission */

// The plots module draws lines and points; the class's pictures are bars.
echarts.use([BarChart]);

const root = byId('dashboard');
const { course, lab, student } = root.dataset;
const api = `/api/courses/${encodeURIComponent(course)}`;

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A score or nothing, for a cell. */
const score = (value) => (value === null || value === undefined ? '–' : percent(value));
/** A moment in the reader's time zone. */
const when = moment;

// ---------------------------------------------------------------------------------------
// Regrades: started here, followed until done, with the scores they changed.

/** @param {Regrade} regrade */
function describeRegrade(regrade) {
  const progress = regrade.finished_at
    ? `done: ${regrade.total} submission(s) regraded`
    : `${regrade.done} of ${regrade.total} regraded…`;
  const box = element('div', 'regrade');
  box.dataset.id = String(regrade.id);
  box.append(element('p', null,
    `Regrade ${regrade.id} of ${regrade.scope}, asked by ${regrade.requested_by} with ${regrade.grader}: ${progress}`));
  if (!regrade.finished_at) {
    const bar = element('progress');
    bar.max = regrade.total;
    bar.value = regrade.done;
    bar.setAttribute('aria-label', `regrade ${regrade.id}: ${regrade.done} of ${regrade.total} submissions`);
    box.append(bar);
  }
  if (regrade.changed.length === 0) {
    box.append(element('p', 'unchanged', regrade.finished_at ? 'No score changed.' : 'No score has changed so far.'));
  } else {
    const table = element('table', 'changed');
    fillTable(table, ['Student', 'Submission', 'Before', 'After', 'Change'], regrade.changed.map((c) => {
      const delta = (c.new_score ?? 0) - (c.old_score ?? 0);
      return [
        link(`/courses/${course}/${lab}/students/${encodeURIComponent(c.student)}`, c.student),
        c.submission,
        score(c.old_score),
        score(c.new_score),
        `${delta >= 0 ? '+' : '−'}${percent(Math.abs(delta))}`,
      ];
    }));
    box.append(table);
  }
  return box;
}

/** Shows the regrade at `url` in `box` as it goes, until it is done; resolves to it then. */
async function follow(url, box) {
  for (;;) {
    /** @type {Regrade} */
    const progress = await getJson(url);
    box.replaceChildren(describeRegrade(progress));
    if (progress.finished_at) return progress;
    await sleep(1000);
  }
}

/** The boxes of the regrades this page follows now, by id: a redrawn list keeps them. */
const followed = new Map();

function followInto(id, box) {
  followed.set(id, box);
  return follow(`${api}/regrades/${id}`, box).finally(() => followed.delete(id));
}

/** Starts a regrade of `scope` and follows it in `box` (and `status`) until it is done. */
async function regrade(scope, status, box) {
  try {
    /** @type {import('../types/RegradeStarted').RegradeStarted} */
    const started = await postJson(`${api}/regrades`, { lab, scope });
    status.textContent = `Regrading ${started.total} submission(s) in the background…`;
    const done = await followInto(started.id, box);
    status.textContent = `Regrade done: ${done.changed.length} score(s) changed.`;
  } catch (error) {
    status.textContent = `Not regraded: ${error.message}`;
  }
}

/**
 * The scores an extension or a waiver changed, in `box`: a row per submission, before and after.
 *
 * @param {HTMLElement} box
 * @param {import('../types/Rejudged').Rejudged[]} changed
 */
function showRejudged(box, changed) {
  if (changed.length === 0) {
    box.replaceChildren();
    return;
  }
  const table = element('table', 'changed');
  const counts = (final, penalty) => `${score(final)} (−${percent(penalty)})`;
  fillTable(table, ['Submission', 'Before', 'After'], changed.map((c) => [
    c.submission, counts(c.old_final, c.old_penalty), counts(c.new_final, c.new_penalty),
  ]));
  box.replaceChildren(table);
}

// ---------------------------------------------------------------------------------------
// The class.

/** A text as search compares it: without accents, in lower case ("Björn" is "bjorn"). */
const folded = (text) => text.normalize('NFD').replace(/\p{M}/gu, '').toLowerCase();

/**
 * The class's rows with what the table sorts and filters on.
 *
 * @param {ClassAnswer} answer
 */
function classRows(answer) {
  return answer.students.map((s) => ({
    student: s,
    name: s.name || s.id,
    found: folded([s.name, s.id, s.email].join('\n')),
    counting: s.counting?.final_score ?? null,
    latest: s.latest?.final_score ?? null,
    late: Boolean(s.counting && s.counting.late_seconds > 0),
    last: s.latest?.submitted_at ?? '',
  }));
}

const COLUMNS = [
  ['Name', (r) => r.name],
  ['Id', (r) => r.student.id],
  ['Submissions', (r) => r.student.submissions],
  ['Score that counts', (r) => r.counting ?? -1],
  ['Latest score', (r) => r.latest ?? -1],
  ['Late', (r) => (r.late ? r.student.counting.penalty : -1)],
  ['Last submitted', (r) => r.last],
];

/**
 * The class table's rows, order and test columns (one per test of the class, its cell a
 * mark for the submission that counts); the filters are read from the page at each
 * drawing.
 */
const table = { rows: [], tests: [], sortBy: 0, descending: false, selected: new Set(), shown: [] };

/** A test's cell: passed, failed, or not run (no graded submission counts). */
function testMark(passed) {
  if (passed === undefined) return '–';
  const mark = element('span', passed ? 'pass' : 'fail', passed ? '✓' : '✗');
  mark.title = passed ? 'passed' : 'failed';
  mark.setAttribute('aria-label', mark.title);
  return mark;
}

/** The columns: the student's own, then one per test (sorted by failed first). */
function columns() {
  return [...COLUMNS, ...table.tests.map((name) => [name, (r) => (r.student.tests[name] === undefined ? -1 : Number(r.student.tests[name]))])];
}

function drawTable() {
  const tableElement = byId('class-table');
  const filter = byId('filter', HTMLSelectElement).value;
  const below = Number(byId('below', HTMLInputElement).value) / 100;
  const find = folded(byId('find', HTMLInputElement).value.trim());
  const shown = table.rows.filter((r) => {
    if ((filter === 'dropped') !== r.student.dropped) return false;
    if (filter === 'not-submitted' && r.student.submissions > 0) return false;
    if (filter === 'below' && !(r.counting === null || r.counting < below)) return false;
    if (filter === 'late' && !r.late) return false;
    return !find || r.found.includes(find);
  });
  const all = columns();
  const key = all[Math.min(table.sortBy, all.length - 1)][1];
  shown.sort((a, b) => {
    const [x, y] = [key(a), key(b)];
    const order = typeof x === 'number' ? x - y : String(x).localeCompare(String(y));
    return table.descending ? -order : order;
  });
  table.shown = shown;
  fillTable(tableElement, ['Select', ...all.map(([title]) => title)], shown.map((r) => [
    pick(r),
    link(`/courses/${course}/${lab}/students/${encodeURIComponent(r.student.id)}`, r.name),
    r.student.id,
    r.student.submissions,
    score(r.counting),
    score(r.latest),
    r.student.counting ? lateness(r.student.counting) : '–',
    when(r.last),
    ...table.tests.map((name) => testMark(r.student.tests[name])),
  ]));
  tableElement.querySelectorAll('tbody tr').forEach((tr, i) => { /** @type {HTMLElement} */ (tr).dataset.student = shown[i].student.id; });
  // Each column's title sorts by it; again, the other way round (the first column selects).
  tableElement.querySelectorAll('th').forEach((th, column) => {
    if (column === 0) return;
    const i = column - 1;
    th.setAttribute('aria-sort', i === table.sortBy ? (table.descending ? 'descending' : 'ascending') : 'none');
    const button = element('button', 'link', th.textContent);
    button.type = 'button';
    button.addEventListener('click', () => {
      table.descending = i === table.sortBy ? !table.descending : false;
      table.sortBy = i;
      drawTable();
    });
    th.replaceChildren(button);
  });
  byId('count').textContent = `${shown.length} of ${table.rows.length} ${table.rows.length === 1 ? 'student' : 'students'}`;
}

/** A row's box that selects its student, kept across redrawings. */
function pick(r) {
  const box = element('input');
  box.type = 'checkbox';
  box.className = 'pick';
  box.checked = table.selected.has(r.student.id);
  box.setAttribute('aria-label', `select ${r.name}`);
  box.addEventListener('change', () => {
    if (box.checked) table.selected.add(r.student.id);
    else table.selected.delete(r.student.id);
    showSelection();
  });
  return box;
}

/** Says how many students are selected, and offers what can be done to them. */
function showSelection() {
  const count = table.selected.size;
  byId('bulk-count').textContent = count === 0
    ? 'Select students in the table to act on several at once.'
    : `${count} ${count === 1 ? 'student' : 'students'} selected: ${[...table.selected].join(', ')}.`;
  byId('bulk-actions').hidden = count === 0;
  byId('select-none', HTMLButtonElement).disabled = count === 0;
}

/** Grants each selected student the extension the bulk form says, one after another. */
async function extendSelected() {
  const due = instant(byId('bulk-due', HTMLInputElement).value);
  const cutoffField = byId('bulk-cutoff', HTMLInputElement).value;
  const cutoff = cutoffField ? instant(cutoffField) : null;
  const status = byId('bulk-status');
  if (!due) {
    status.textContent = 'New due date: give the date and time.';
    return;
  }
  const students = [...table.selected];
  let changed = 0;
  const refused = [];
  for (const [i, student] of students.entries()) {
    status.textContent = `Granting extensions: ${i} of ${students.length}…`;
    try {
      /** @type {import('../types/Granted').Granted} */
      const granted = await postJson(`${api}/extensions`, { lab, student, due, cutoff });
      changed += granted.changed.length;
    } catch (error) {
      refused.push(`${student}: ${error.message}`);
    }
  }
  const done = students.length - refused.length;
  status.textContent = `Extended ${done} of ${students.length}: due ${when(due)}` +
    `${cutoff ? `, taken until ${when(cutoff)}` : ''}; ${changed} score(s) of submissions already made changed.` +
    (refused.length ? ` Not extended: ${refused.join('; ')}` : '');
}

/** @param {ClassAnswer} answer */
function showClass(answer) {
  const policy = answer.policy;
  byId('facts').textContent =
    `Due ${when(policy.due)}, taken until ${when(policy.cutoff)}, ${percent(policy.penalty_per_day)} off per day late; ` +
    `the ${policy.counts} graded submission counts. Graded with ${answer.grader}.`;
  byId('grader').textContent = answer.grader;
  table.rows = classRows(answer);
  table.tests = answer.tests.map((t) => t.name);
  drawTable();

  const names = new Map(answer.students.map((s) => [s.id, s.name || s.id]));
  const mistakes = byId('mistakes');
  mistakes.replaceChildren(...answer.mistakes.map((m) => {
    const item = element('li', 'mistake');
    item.dataset.kind = m.kind;
    const count = m.students.length === 1 ? '1 student' : `${m.students.length} students`;
    item.append(element('strong', null, `${count}, in ${m.functions.join(', ')}: `), document.createTextNode(m.text), element('br'));
    m.students.forEach((id, i) => {
      if (i > 0) item.append(', ');
      item.append(link(`/courses/${course}/${lab}/students/${encodeURIComponent(id)}`, `${names.get(id) ?? id} (${id})`));
    });
    return item;
  }));
  if (answer.mistakes.length === 0) mistakes.replaceChildren(element('li', null, 'No classic mistake in the submissions that count.'));

  showChallenge(answer, names);
  showLanguages(answer.languages);

  // Regrades still running (started elsewhere, or before this page was opened) are followed.
  byId('regrades').replaceChildren(...answer.regrades.map((r) => {
    if (followed.has(r.id)) return followed.get(r.id);
    const box = element('div', 'regrade-box');
    box.append(describeRegrade(r));
    if (!r.finished_at) followInto(r.id, box).catch(() => {});
    return box;
  }));
}

/**
 * The class challenge, where the exercise has one: what it measures, the reference's
 * figure, the ranking of the submissions that count, and whether students see their rank.
 *
 * @param {ClassAnswer} answer
 * @param {Map<string, string>} names
 */
function showChallenge(answer, names) {
  const challenge = answer.challenge;
  byId('challenge').hidden = challenge === null;
  if (challenge === null) return;
  const unit = challenge.unit;
  const without = challenge.without_figure === 0
    ? ''
    : ` ${challenge.without_figure} student(s) with a graded submission have no figure: their filter did not finish ` +
      'the held-out trials, or was graded before the challenge (a regrade runs it).';
  byId('challenge-about').textContent =
    `Each submission's filter also ran, with its own settings, over trials the class never sees: ` +
    `${challenge.measure}, lower the better, of each student's latest submission with the score that counts; ` +
    'beside it, how much it varies between the trials (its standard deviation over them). ' +
    `The reference filter with its default settings: ${fmt(challenge.reference, 4)} ${unit}. It earns no points.${without}`;
  byId('ranked', HTMLInputElement).checked = answer.ranked;
  fillTable(byId('challenge-table', HTMLTableElement), ['Rank', 'Student', `Figure (${unit})`, `Spread (${unit})`, 'Submission'],
    challenge.ranking.map((e) => [
      String(e.rank),
      link(`/courses/${course}/${lab}/students/${encodeURIComponent(e.student)}`,
        `${names.get(e.student) ?? e.student} (${e.student})`),
      fmt(e.figure, 4),
      e.spread === null ? '–' : fmt(e.spread, 4),
      String(e.submission),
    ]));
}

/**
 * Which languages the assignment takes, as its boxes show them.
 *
 * @param {import('../types/Language').Language[]} languages
 */
function showLanguages(languages) {
  for (const box of languageBoxes()) box.checked = languages.includes(/** @type {any} */ (box.value));
}

/** @returns {HTMLInputElement[]} */
function languageBoxes() {
  return [...document.querySelectorAll('#languages input[type=checkbox]')]
    .filter((box) => box instanceof HTMLInputElement);
}

/** Takes the assignment's files in the languages checked (one at least). */
async function setLanguages() {
  const boxes = languageBoxes();
  const status = byId('languages-status');
  const chosen = boxes.filter((box) => box.checked).map((box) => box.value);
  for (const box of boxes) box.disabled = true;
  try {
    /** @type {import('../types/LanguagesSet').LanguagesSet} */
    const set = await postJson(`${api}/labs/${encodeURIComponent(lab)}/languages`, { languages: chosen });
    showLanguages(set.languages);
    status.textContent = `Files are taken in ${boxes.filter((box) => box.checked).map((box) => box.parentElement.textContent.trim()).join(' and ')}.`;
  } catch (error) {
    status.textContent = `Not changed: ${error.message}`;
    const answer = /** @type {ClassAnswer} */ (await getJson(`${api}/labs/${encodeURIComponent(lab)}/class`));
    showLanguages(answer.languages);
  } finally {
    for (const box of boxes) box.disabled = false;
  }
}

/** Shows the students their rank in the class challenge, or stops. */
async function switchRanking() {
  const box = byId('ranked', HTMLInputElement);
  const status = byId('ranked-status');
  box.disabled = true;
  try {
    /** @type {import('../types/RankingSet').RankingSet} */
    const set = await postJson(`${api}/labs/${encodeURIComponent(lab)}/ranking`, { ranked: box.checked });
    box.checked = set.ranked;
    status.textContent = set.ranked ? 'Students see their rank.' : 'Students see their own figure only.';
  } catch (error) {
    box.checked = !box.checked;
    status.textContent = `Not changed: ${error.message}`;
  } finally {
    box.disabled = false;
  }
}

// ---------------------------------------------------------------------------------------
// The class's results as pictures, each said in words in its caption (and in full in its
// summary for screen readers): the scores that count, and each test's share passing.

/** The ten bins of the distribution, as the class API counts them: [0, 10 %), ..., [90 %, 100 %]. */
const BINS = Array.from({ length: 10 }, (_, i) => `${10 * i}–${10 * (i + 1)} %`);
/** The bins as the axis names them, short enough for a phone's width (the axis says %). */
const BIN_LABELS = BINS.map((bin) => bin.replace(' %', ''));

function median(values) {
  const sorted = values.slice().sort((a, b) => a - b);
  const middle = Math.floor(sorted.length / 2);
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
}

/** Says `text` in the figure's caption, before its save buttons. */
function caption(id, text) {
  byId(id).textContent = text;
}

/** @param {ClassAnswer} answer */
function drawDistribution(plot, answer) {
  const enrolled = answer.students.filter((s) => !s.dropped);
  const scores = enrolled.map((s) => s.counting?.final_score).filter((v) => v !== null && v !== undefined);
  const without = enrolled.length - scores.length;
  const none = without ? `; ${without} of the roster ${without === 1 ? 'has' : 'have'} no graded submission` : '';
  caption('distribution-caption', scores.length === 0
    ? `Scores that count: no student has a graded submission yet${none}.`
    : `Scores that count: ${scores.length} student${scores.length === 1 ? '' : 's'}, median ${percent(median(scores))}, ` +
      `${scores.filter((v) => v < 0.5).length} below 50 %${none}.`);
  plot.describe(`Students per band of the score that counts: ${BINS.map((bin, i) => `${bin}: ${answer.distribution[i]}`).join('; ')}.`);
  plot.set({
    animation: false,
    grid: { left: 56, right: 16, top: 28, bottom: 52 },
    tooltip: { trigger: 'axis', axisPointer: { type: 'shadow' }, formatter: ([item]) => `${BINS[item.dataIndex]}: ${item.value} ${item.value === 1 ? 'student' : 'students'}` },
    xAxis: { type: 'category', data: BIN_LABELS, name: 'score that counts (%)', nameLocation: 'middle', nameGap: 32, axisLabel: { fontSize: 10 } },
    yAxis: { type: 'value', name: 'students', nameLocation: 'middle', nameGap: 36, minInterval: 1 },
    series: [{
      id: 'students',
      type: 'bar',
      data: answer.distribution,
      itemStyle: { color: colours.odometry },
      label: { show: true, position: 'top', formatter: ({ value }) => (value ? String(value) : '') },
    }],
  });
}

/** @param {ClassAnswer} answer */
function drawTests(plot, answer) {
  const tests = answer.tests;
  const most = Math.max(0, ...tests.map((t) => t.of));
  if (tests.length === 0) {
    caption('tests-caption', 'Students passing each test: no graded submission counts yet.');
    plot.describe('No test has been graded yet.');
  } else {
    const share = (t) => (t.of ? t.passed / t.of : 0);
    const hardest = tests.reduce((a, b) => (share(b) < share(a) ? b : a));
    const all = tests.filter((t) => t.passed === t.of).length;
    caption('tests-caption', `Students passing each test, of ${most} with a graded submission that counts: ` +
      `${all} of ${tests.length} tests passed by all; fewest pass ${hardest.name} (${hardest.passed} of ${hardest.of}, ${percent(share(hardest))}).`);
    plot.describe(`Students passing each test: ${tests.map((t) => `${t.name}: ${t.passed} of ${t.of} (${percent(share(t))})`).join('; ')}.`);
  }
  // A bar per test, each as tall as a line of text; the names take at most 40 % of the width.
  plot.element.style.height = `${Math.max(160, 70 + 26 * tests.length)}px`;
  const names = Math.round(Math.min(210, Math.max(80, 0.4 * plot.element.clientWidth)));
  plot.set({
    animation: false,
    grid: { left: names + 10, right: 56, top: 16, bottom: 44 },
    tooltip: {
      trigger: 'axis',
      axisPointer: { type: 'shadow' },
      formatter: ([item]) => {
        const t = tests[item.dataIndex];
        return `${t.name}<br>${t.passed} of ${t.of} students pass (${percent(t.of ? t.passed / t.of : 0)})`;
      },
    },
    xAxis: { type: 'value', min: 0, max: 100, name: 'students passing (%)', nameLocation: 'middle', nameGap: 28 },
    yAxis: { type: 'category', inverse: true, data: tests.map((t) => t.name), axisLabel: { width: names, overflow: 'truncate' } },
    series: [{
      id: 'passing',
      type: 'bar',
      data: tests.map((t) => (t.of ? (100 * t.passed) / t.of : 0)),
      itemStyle: { color: colours.truth },
      label: { show: true, position: 'right', formatter: ({ dataIndex }) => `${tests[dataIndex].passed}/${tests[dataIndex].of}` },
    }],
  });
}

async function showAudit() {
  /** @type {import('../types/AuditEntry').AuditEntry[]} */
  const log = await getJson(`${api}/audit`);
  fillTable(byId('audit'), ['When', 'Who', 'What', 'Detail'],
    log.map((entry) => [when(entry.at), entry.actor, entry.action, entry.detail]));
}

async function classPage() {
  const url = `${api}/labs/${encodeURIComponent(lab)}/class`;
  const plots = {
    distribution: new Plot(byId('distribution-figure'), `${course}-${lab}-scores`),
    tests: new Plot(byId('tests-figure'), `${course}-${lab}-tests`),
  };
  /** @type {ClassAnswer | null} */
  let shown = null;
  /** @param {ClassAnswer} answer */
  const showAll = (answer) => {
    shown = answer;
    showClass(answer);
    drawDistribution(plots.distribution, answer);
    drawTests(plots.tests, answer);
  };
  // The test names' room follows the plot's width.
  let width = plots.tests.element.clientWidth;
  new ResizeObserver(() => {
    const now = plots.tests.element.clientWidth;
    if (shown && Math.abs(now - width) > 20) drawTests(plots.tests, shown);
    width = now;
  }).observe(plots.tests.element);
  const refresh = async () => {
    const status = byId('refresh-status');
    try {
      showAll(await getJson(url));
      await showAudit();
      status.textContent = `As of ${new Date().toLocaleTimeString()}.`;
    } catch (error) {
      status.textContent = `Not refreshed: ${error.message}`;
    }
  };
  for (const id of ['filter', 'below', 'find']) byId(id).addEventListener('input', drawTable);
  byId('bulk-zone').textContent = `Dates are in your time zone, ${zone}.`;
  byId('select-shown').addEventListener('click', () => {
    for (const r of table.shown) table.selected.add(r.student.id);
    drawTable();
    showSelection();
  });
  byId('select-none').addEventListener('click', () => {
    table.selected.clear();
    drawTable();
    showSelection();
  });
  byId('bulk-extension').addEventListener('submit', async (event) => {
    event.preventDefault();
    const button = /** @type {HTMLButtonElement} */ (event.submitter);
    button.disabled = true;
    await extendSelected();
    button.disabled = false;
    await refresh();
  });
  byId('bulk-regrade').addEventListener('click', async () => {
    const students = [...table.selected];
    const box = element('div', 'regrade-box');
    byId('bulk-regrade-box').replaceChildren(box);
    byId('bulk-regrade', HTMLButtonElement).disabled = true;
    await regrade({ kind: 'students', of: students }, byId('bulk-status'), box);
    byId('bulk-regrade', HTMLButtonElement).disabled = false;
    await refresh();
  });
  showAll(await getJson(url));
  await showAudit();
  byId('refresh-class').addEventListener('click', refresh);
  byId('ranked').addEventListener('change', switchRanking);
  for (const box of languageBoxes()) box.addEventListener('change', setLanguages);
  // The class as it fills, while the page is in view: every few seconds while a latest
  // submission waits for its grade (the table follows the gradings as they finish), else
  // every half minute.
  const pending = () => shown.students.some((s) => s.latest && s.latest.score === null);
  const poll = async () => {
    if (document.visibilityState === 'visible') await refresh();
    setTimeout(poll, pending() ? 3_000 : 30_000);
  };
  setTimeout(poll, pending() ? 3_000 : 30_000);
  byId('regrade-all').addEventListener('click', async () => {
    if (!window.confirm('Regrade every submission of the assignment with the grader as it is now?')) return;
    const box = element('div', 'regrade-box');
    byId('regrades').prepend(box);
    byId('regrade-all', HTMLButtonElement).disabled = true;
    await regrade({ kind: 'assignment' }, byId('regrade-status'), box);
    byId('regrade-all', HTMLButtonElement).disabled = false;
    await refresh();
  });
}

// ---------------------------------------------------------------------------------------
// One student.

/**
 * The line differences between two sources (`before` older, `after` newer) in `box`:
 * a count of lines added and removed, then each changed stretch with three lines of
 * context, every line numbered in both files and marked +, - or a space, so that a
 * reader who does not tell the colours apart reads the marks.
 *
 * @param {HTMLElement} box
 * @param {Submission} before
 * @param {Submission} after
 */
function showDiff(box, before, after) {
  const patch = structuredPatch(`submission ${before.id}`, `submission ${after.id}`,
    before.source ?? '', after.source ?? '', '', '', { context: 3 });
  let added = 0;
  let removed = 0;
  const table = element('table', 'diff');
  const body = element('tbody');
  for (const hunk of patch.hunks) {
    const head = element('tr', 'hunk');
    const cell = element('td', null,
      `Lines ${hunk.oldStart}–${hunk.oldStart + Math.max(0, hunk.oldLines - 1)} of submission ${before.id}, ` +
      `${hunk.newStart}–${hunk.newStart + Math.max(0, hunk.newLines - 1)} of submission ${after.id}`);
    cell.colSpan = 4;
    head.append(cell);
    body.append(head);
    let [old, now] = [hunk.oldStart, hunk.newStart];
    for (const line of hunk.lines) {
      const mark = line[0];
      if (mark === '\\') continue; // "No newline at end of file"
      const kind = mark === '+' ? 'added' : mark === '-' ? 'removed' : 'same';
      const row = element('tr', kind);
      row.append(
        element('td', 'number', kind === 'added' ? '' : String(old)),
        element('td', 'number', kind === 'removed' ? '' : String(now)),
        element('td', 'mark', mark === ' ' ? '' : mark),
        element('td', 'code', line.slice(1)),
      );
      row.cells[2].title = { added: `added in submission ${after.id}`, removed: `removed from submission ${before.id}`, same: '' }[kind];
      if (kind !== 'added') old += 1;
      if (kind !== 'removed') now += 1;
      if (kind === 'added') added += 1;
      if (kind === 'removed') removed += 1;
      body.append(row);
    }
  }
  const head = element('thead');
  const titles = element('tr');
  for (const title of [`#${before.id}`, `#${after.id}`, '±', 'line']) {
    const th = element('th', null, title);
    th.scope = 'col';
    titles.append(th);
  }
  head.append(titles);
  table.append(head, body);
  const summary = element('p', 'diff-summary', patch.hunks.length === 0
    ? `Submissions ${before.id} and ${after.id} have the same source.`
    : `From submission ${before.id} to submission ${after.id}: ${added} line(s) added (+), ${removed} removed (-).`);
  box.replaceChildren(summary, ...(patch.hunks.length ? [table] : []));
  box.dataset.added = String(added);
  box.dataset.removed = String(removed);
}

async function studentPage() {
  const url = `${api}/labs/${encodeURIComponent(lab)}/students/${encodeURIComponent(student)}`;
  // The highlighting of each submission's language.
  const mode = new Compartment();
  const source = new EditorView({
    doc: '',
    extensions: [
      basicSetup, mode.of(LANGUAGES.javascript.mode()), EditorView.editable.of(false), EditorView.lineWrapping,
      // Named, and reachable by keyboard (read only, it is not editable content).
      EditorView.contentAttributes.of({ 'aria-label': "the submission's source, read only", tabindex: '0' }),
    ],
    parent: byId('source'),
  });
  // Reachable from the page (and its tests) through the element it shows in.
  Object.assign(byId('source'), { editor: source });
  const choose = byId('view-submission', HTMLSelectElement);
  const compare = byId('compare-submission', HTMLSelectElement);
  /** @type {Map<string, Submission>} Submissions read so far, by id (with their sources). */
  const read = new Map();
  /**
   * @param {string} id
   * @returns {Promise<Submission>}
   */
  const fetchSubmission = async (id) => {
    if (read.has(id)) return read.get(id);
    /** @type {Submission} */
    const submission = await getJson(`/api/submissions/${id}`);
    // A graded submission changes only at a regrade, which forgets what was read.
    if (submission.status === 'graded') read.set(id, submission);
    return submission;
  };
  /** Shows the chosen submission's result, and its source or its difference from the one compared. */
  const show = async () => {
    const id = choose.value;
    if (!id) return;
    const submission = await fetchSubmission(id);
    renderSubmission(byId('result'), submission, { open: true, reader: 'staff' });
    const other = compare.value;
    const diff = byId('diff');
    if (other && other !== id) {
      const them = await fetchSubmission(other);
      const [before, after] = Number(other) < Number(id) ? [them, submission] : [submission, them];
      showDiff(diff, before, after);
      diff.hidden = false;
      byId('source').hidden = true;
    } else {
      diff.hidden = true;
      byId('source').hidden = false;
      source.dispatch({
        changes: { from: 0, to: source.state.doc.length, insert: submission.source ?? '' },
        effects: mode.reconfigure(LANGUAGES[submission.language].mode()),
      });
    }
  };
  const showSafely = () => show().catch((error) => {
    byId('result').replaceChildren(element('p', 'error', `The submission could not be read: ${error.message}`));
  });
  const refresh = async () => {
    /** @type {StudentAnswer} */
    const answer = await getJson(url);
    const { member, policy, extension } = answer;
    // Headed by the student's name; the id stays beside it in the facts.
    byId('student-name').textContent = member.name || member.login;
    document.title = `${member.name || member.login} · ${course} · ${lab} · estlab`;
    byId('student-facts').textContent =
      `${member.name || member.login} (${member.login}, ${member.email || 'no email'})${member.dropped ? ', dropped from the roster' : ''}. ` +
      `Due ${when(policy.due)}, taken until ${when(policy.cutoff)}` +
      (extension ? `, by an extension ${extension.granted_by} granted on ${when(extension.granted_at)}.` : '.');
    const newest = answer.submissions.slice().reverse();
    fillTable(byId('student-submissions'), ['#', 'Submitted', 'Status', 'Score', 'Late', 'Counts as', ''],
      newest.map((s) => {
        const actions = element('span', 'actions');
        const view = element('button', 'link', 'Show');
        view.type = 'button';
        view.setAttribute('aria-label', `Show submission ${s.id}`);
        view.addEventListener('click', () => {
          choose.value = String(s.id);
          showSafely();
          byId('view-title').scrollIntoView();
        });
        actions.append(view);
        if (s.status === 'graded') {
          const again = element('button', 'link', 'Regrade');
          again.type = 'button';
          again.setAttribute('aria-label', `Regrade submission ${s.id}`);
          again.addEventListener('click', async () => {
            await regrade({ kind: 'submission', of: s.id }, byId('regrade-student-status'), byId('student-regrade'));
            read.delete(String(s.id));
            await refresh();
          });
          actions.append(' · ', again);
        }
        if (s.penalty > 0) {
          const waive = element('button', 'link', 'Waive penalty');
          waive.type = 'button';
          waive.setAttribute('aria-label', `Waive the late penalty of submission ${s.id}`);
          waive.addEventListener('click', () => {
            byId('waiver-submission', HTMLSelectElement).value = String(s.id);
            byId('waiver-reason').focus();
          });
          actions.append(' · ', waive);
        }
        return [
          s.id, when(s.submitted_at), s.status, score(s.score),
          lateness(s), score(s.final_score), actions,
        ];
      }));
    byId('student-submissions').querySelectorAll('tbody tr').forEach((tr, i) => { /** @type {HTMLElement} */ (tr).dataset.id = String(newest[i].id); });
    const penalised = newest.filter((s) => s.penalty > 0);
    const waiving = byId('waiver-submission', HTMLSelectElement);
    const picked = waiving.value;
    waiving.replaceChildren(...penalised.map((s) => new Option(`submission ${s.id} (${lateness(s)})`, String(s.id))));
    if (penalised.some((s) => String(s.id) === picked)) waiving.value = picked;
    byId('waiver-form').hidden = penalised.length === 0;
    const [shown, compared] = [choose.value, compare.value];
    choose.replaceChildren(...newest.map((s) => new Option(`submission ${s.id} (${score(s.score)})`, String(s.id))));
    compare.replaceChildren(new Option('(nothing: its source)', ''),
      ...newest.map((s) => new Option(`submission ${s.id} (${score(s.score)})`, String(s.id))));
    if (newest.some((s) => String(s.id) === shown)) choose.value = shown;
    if (newest.some((s) => String(s.id) === compared)) compare.value = compared;
    if (newest.length > 0) await show();
  };
  choose.addEventListener('change', showSafely);
  compare.addEventListener('change', showSafely);
  const extensionForm = byId('extension-form', HTMLFormElement);
  extensionForm.addEventListener('submit', async (event) => {
    event.preventDefault();
    const form = new FormData(extensionForm);
    const cutoff = String(form.get('cutoff')).trim();
    byId('extension-status').textContent = '';
    try {
      /** @type {import('../types/Granted').Granted} */
      const granted = await postJson(`${api}/extensions`, { lab, student, due: String(form.get('due')).trim(), ...(cutoff ? { cutoff } : {}) });
      read.clear();
      await refresh();
      // Said once the page shows the new dates and scores.
      byId('extension-status').textContent = `Extension granted: due ${when(granted.due)}, taken until ${when(granted.cutoff)}. ` +
        (granted.changed.length ? `It changed ${granted.changed.length} score(s):` : 'No score of the submissions already made changed.');
      showRejudged(byId('extension-changes'), granted.changed);
    } catch (error) {
      byId('extension-status').textContent = `Not granted: ${error.message}`;
    }
  });
  const waiverForm = byId('waiver-form', HTMLFormElement);
  waiverForm.addEventListener('submit', async (event) => {
    event.preventDefault();
    const form = new FormData(waiverForm);
    const id = String(form.get('submission'));
    byId('waiver-status').textContent = '';
    try {
      /** @type {import('../types/Waived').Waived} */
      const waived = await postJson(`${api}/submissions/${encodeURIComponent(id)}/waiver`, { reason: String(form.get('reason')).trim() });
      waiverForm.reset();
      read.delete(id);
      await refresh();
      byId('waiver-status').textContent = `The late penalty of submission ${id} is waived.`;
      showRejudged(byId('waiver-changes'), waived.changed);
    } catch (error) {
      byId('waiver-status').textContent = `Not waived: ${error.message}`;
    }
  });
  byId('regrade-student').addEventListener('click', async () => {
    await regrade({ kind: 'student', of: student }, byId('regrade-student-status'), byId('student-regrade'));
    read.clear();
    await refresh();
  });
  await refresh();
}

try {
  await (student ? studentPage() : classPage());
} catch (error) {
  root.prepend(element('p', 'error', `The dashboard could not be loaded: ${error.message}`));
}
document.body.dataset.ready = 'true';
