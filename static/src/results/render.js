// How results are shown in the page: the small builders of nodes, links and tables that
// every page uses; each test of a grading result with its message and its failing cases in
// detail (the workbench's own verdict and the server's); and a submission the server has
// graded, with its score, late penalty, hidden cases, class challenge and regrades. The
// workbench and the student's page (/me) both show a server's result with
// `renderSubmission`.
import { fmt } from '../format.js';
import { site } from '../site.js';
import { moment, percent, scoreOf, span } from './format.js';

/** @typedef {import('../types/GradeResult').GradeResult} GradeResult */
/** @typedef {import('../types/Test').Test} Test */
/** @typedef {import('../types/Submission').Submission} Submission */
/** @typedef {import('../types/EarlierResult').EarlierResult} EarlierResult */
/** @typedef {import('../types/Challenge').Challenge} Challenge */

/** Failing cases shown in detail per test, and differing elements per case. */
const SHOWN = { failures: 2, mismatches: 12 };

/**
 * A new element `tag` of class `className` reading `text`.
 *
 * @template {keyof HTMLElementTagNameMap} K
 * @param {K} tag
 * @param {string | null} [className]
 * @param {string} [text]
 * @returns {HTMLElementTagNameMap[K]}
 */
export function element(tag, className, text) {
  const node = document.createElement(tag);
  if (className) node.className = className;
  if (text !== undefined) node.textContent = text;
  return node;
}

/**
 * A link to `href` reading `text`.
 *
 * @param {string} href
 * @param {string} text
 */
export function link(href, text) {
  const a = element('a', null, text);
  a.href = href;
  return a;
}

/**
 * A table's head and rows, from column titles and rows of cells (text or nodes).
 *
 * @param {HTMLElement} table
 * @param {string[]} titles
 * @param {Array<Array<string | number | Node>>} rows
 */
export function fillTable(table, titles, rows) {
  const head = element('thead');
  const tr = element('tr');
  for (const title of titles) {
    const th = element('th', null, title);
    th.scope = 'col';
    tr.append(th);
  }
  head.append(tr);
  const body = element('tbody');
  for (const cells of rows) {
    const row = element('tr');
    for (const cell of cells) {
      const td = element('td');
      td.append(cell instanceof Node ? cell : document.createTextNode(String(cell)));
      row.append(td);
    }
    body.append(row);
  }
  table.replaceChildren(head, body);
}

/**
 * The body of `table`: a row for each of `rows`, its first cell the row's heading and the
 * rest text.
 *
 * @param {HTMLTableElement} table
 * @param {string[][]} rows
 */
export function fillHeadedRows(table, rows) {
  table.tBodies[0].replaceChildren(...rows.map(([label, ...cells]) => {
    const row = element('tr');
    const heading = element('th', null, label);
    heading.scope = 'row';
    row.append(heading, ...cells.map((cell) => element('td', null, cell)));
    return row;
  }));
}

/**
 * Whether every failing case of a function's test throws the starter file's "not implemented".
 *
 * @param {Test} test
 */
export function notImplemented(test) {
  const failures = test.failures ?? [];
  const { kind, name } = test.subject;
  return kind === 'function' && test.status === 'failed' && test.points === 0 && failures.length > 0 &&
    failures.every((failure) => (failure.error ?? '').includes(`${name}: not implemented`));
}

/**
 * One test as an item of a list of tests. `ran`: whether the test was run (a test not run
 * shows its name only); `id`: the item's id; `action`: a node for the head (the
 * workbench's Run button).
 *
 * @param {Test} test
 * @param {{ ran?: boolean, id?: string | null, action?: Node | null }} [how]
 */
export function testItem(test, { ran = true, id = null, action = null } = {}) {
  const key = test.subject.name;
  const item = element('li', 'test');
  if (id) item.id = id;
  item.dataset.key = key;
  item.dataset.status = ran ? test.status : 'not-run';
  const head = element('div', 'head');
  const mark = { passed: '✓', failed: '✗', 'not-run': '○' }[item.dataset.status];
  head.append(element('span', 'mark', mark), element('span', 'name', test.name),
    element('span', 'points', ran ? `${fmt(test.points, 3)} / ${test.max_points}` : 'not run'));
  if (action) head.append(action);
  item.append(head);
  if (!ran) return item;
  const details = element('details');
  const todo = notImplemented(test);
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

function show(value) {
  return typeof value === 'number' ? fmt(value, 12) : JSON.stringify(value);
}

/** @param {import('../types/Failure').Failure} failure */
function failureView(failure) {
  const box = element('div', 'failure');
  // A title, not a heading: the panels it appears in sit under headings of any level.
  box.append(element('p', 'case-title', `${failure.case}: ${failure.note}${failure.hidden ? ' (a hidden case)' : ''}`));
  if (failure.error) box.append(element('p', 'thrown', failure.error));
  if (failure.hint) box.append(element('p', 'hint', `Hint: ${failure.hint.text}`));
  const mismatches = failure.mismatches ?? [];
  if (mismatches.length) {
    const table = element('table', 'mismatches');
    const header = element('tr');
    for (const title of ['element', 'expected', 'got', 'problem']) header.append(element('th', null, title));
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
  const given = failure.args !== undefined && failure.args !== null;
  const got = failure.got === undefined || failure.got === null ? '(nothing)' : json(failure.got);
  if (given) {
    const all = element('details', 'case');
    all.append(element('summary', null, 'the arguments, the expected output and yours'));
    all.append(element('pre', null, `arguments: ${json(failure.args)}\nexpected: ${json(failure.expected)}\ngot: ${got}`));
    box.append(all);
  } else if (!failure.hidden && failure.got !== undefined) {
    // The server keeps neither the arguments nor the expected output, only the answer.
    const yours = element('details', 'case');
    yours.append(element('summary', null, 'your output'));
    yours.append(element('pre', null, got));
    box.append(yours);
  }
  return box;
}

// ---------------------------------------------------------------------------------------
// A submission as the server has it.


/**
 * Fills `box` with the server's account of `submission`: while it waits, that it waits;
 * once graded, its score (and `comparison`, a sentence comparing it with the browser's),
 * its late penalty, its hidden cases, and every test of the server's result, folded
 * unless `open`; `reader` is the student, or their course's staff (it speaks of
 * "the student's" browser). Sets `box.dataset.status` to queued, graded, not-gradable.
 *
 * @param {HTMLElement} box
 * @param {Submission} submission
 * @param {{ comparison?: string, open?: boolean, reader?: 'student' | 'staff' }} [how]
 */
export function renderSubmission(box, submission, { comparison = '', open = false, reader = 'student' } = {}) {
  const result = submission.result;
  if (submission.status !== 'graded' || !result) {
    box.dataset.status = 'queued';
    box.replaceChildren(element('p', 'verdict', submission.status === 'grading'
      ? `Submission ${submission.id} is stored; the server is grading it…`
      : `Submission ${submission.id} is stored and waits for its grading…`));
    // No running grader grades its language: said, rather than a wait that never ends.
    if (submission.waiting_for) box.append(element('p', 'note', submission.waiting_for));
    return;
  }
  if (!result.gradable) {
    box.dataset.status = 'not-gradable';
    box.replaceChildren(element('p', 'verdict',
      `Submission ${submission.id} could not be graded (${result.reason}). That costs you nothing: submit again.`));
    return;
  }
  box.dataset.status = 'graded';
  let line = `The server's grade for submission ${submission.id}: ${fmt(result.points, 4)} of ${result.max_points} points (${Math.round(100 * result.score)}%).`;
  if (comparison) line += ` ${comparison}`;
  if (submission.waiver) {
    line += ` Submitted ${span(submission.late_seconds)} late; its late penalty was waived (${submission.waiver.reason}): it counts as ${percent(submission.final_score ?? 0)}.`;
  } else if (submission.late_seconds > 0) {
    line += ` Submitted ${span(submission.late_seconds)} late, which costs ${percent(submission.penalty)} of the score: it counts as ${percent(submission.final_score ?? 0)}.`;
  }
  /** @type {HTMLElement[]} */
  const parts = [element('p', 'verdict', line)];
  if (submission.earlier?.length) parts.push(regradeNote(submission));
  if (result.hidden_cases) {
    // The browser knows only the shown cases; the server's differ at every submission.
    const hidden = result.tests.flatMap((test) => (test.failures ?? []).filter((f) => f.hidden));
    // Said to the student, or about them to their course's staff.
    const [whose, who] = reader === 'staff' ? ["the student's", 'they have'] : ['your', 'you have'];
    // What the server ran the student's code on beyond what the browser knows.
    const runs = `${site.exercises[result.lab].hidden_runs.replace('{whose}', whose)} ${who} not seen`;
    let note = `The server also graded hidden cases of every function and ${runs}, which ${whose} browser cannot: ` +
      'a function earns the smaller of its pass rates on the shown and the hidden cases.';
    for (const failure of hidden) {
      note += `\nHidden case ${failure.case} (${failure.note}) fails` +
        (failure.error ? `: ${failure.error}` : '') + (failure.hint ? `. Hint: ${failure.hint.text}` : '.');
    }
    parts.push(element('p', 'hidden-cases', note));
  }
  if (result.challenge) parts.push(challengeNote(result.challenge));
  const passed = result.tests.filter((test) => test.status === 'passed').length;
  const tests = element('details', 'server-tests');
  tests.open = open;
  tests.append(element('summary', null, `The server's ${result.tests.length} tests: ${passed} pass`));
  const list = element('ol', 'tests');
  list.append(...result.tests.map((test) => testItem(test)));
  tests.append(list);
  parts.push(tests);
  box.replaceChildren(...parts);
}

/**
 * The class challenge's figure of a result: what it measures, the figure (or why there is
 * none) beside the reference's, and the settings and other figures, a line each.
 *
 * @param {Challenge} challenge
 */
function challengeNote(challenge) {
  const box = element('div', 'challenge');
  const spread = challenge.spread === null ? '' : ` ± ${fmt(challenge.spread, 4)}`;
  const figure = challenge.figure === null
    ? 'no figure'
    : `${fmt(challenge.figure, 4)}${spread} ${challenge.unit}`;
  box.append(element('p', null,
    `Class challenge (no points): ${challenge.measure}, ${figure}; the reference filter ` +
    `${fmt(challenge.reference, 4)} ${challenge.unit}.`));
  for (const line of challenge.message.split('\n')) box.append(element('p', 'detail', line));
  return box;
}

// ---------------------------------------------------------------------------------------
// A submission graded again: each regrade, when and with which grader, and what it changed.

/**
 * The tests whose points differ between two results: { name, before, after, max } each.
 *
 * @param {GradeResult | null} before
 * @param {GradeResult | null} after
 */
function changedTests(before, after) {
  // By what they test: a grader with another plan names a function's test by another
  // count of cases ("predict: 12 cases", "predict: 18 cases").
  /** @param {GradeResult | null} result */
  const bySubject = (result) => new Map((result?.gradable ? result.tests : [])
    .map((test) => [`${test.subject.kind} ${test.subject.name}`, test]));
  const [old, now] = [bySubject(before), bySubject(after)];
  const subjects = [...new Set([...old.keys(), ...now.keys()])];
  return subjects.flatMap((subject) => {
    const [a, b] = [old.get(subject)?.points ?? 0, now.get(subject)?.points ?? 0];
    if (Math.abs(a - b) < 1e-9) return [];
    const { name, max_points: max } = now.get(subject) ?? old.get(subject);
    return [{ name, before: a, after: b, max }];
  });
}

/**
 * That `submission` was graded again, once per regrade (its `earlier` results, oldest
 * first, each replaced by the next and the last by the current one): when, with which
 * grader, the score before and after, and each test whose points changed.
 *
 * @param {Submission} submission
 */
function regradeNote(submission) {
  const box = element('div', 'regraded');
  const steps = submission.earlier.map((before, i) => {
    const next = submission.earlier[i + 1];
    const after = next ?? { grader: submission.grader, graded_at: submission.graded_at, result: submission.result };
    return { before, after };
  });
  box.append(element('p', 'regraded-title', steps.length === 1
    ? `This submission was regraded: the result below replaced the one it first had.`
    : `This submission was regraded ${steps.length} times: the result below replaced the earlier ones, each kept.`));
  const list = element('ul', 'regrades');
  for (const { before, after } of steps) {
    const item = element('li', 'regrade-step');
    const same = before.result?.gradable === after.result?.gradable &&
      Math.abs((before.result?.score ?? 0) - (after.result?.score ?? 0)) < 1e-9;
    let text = `Regraded ${moment(after.graded_at)} with ${after.grader ?? 'an unnamed grader'}` +
      ` (first graded with ${before.grader ?? 'an earlier grader'}): `;
    text += same ? `the score stayed ${scoreOf(after.result)}.` : `the score went from ${scoreOf(before.result)} to ${scoreOf(after.result)}.`;
    if (!same && submission.penalty > 0 && before.result?.gradable && after.result?.gradable) {
      const counts = (result) => percent(result.score * (1 - submission.penalty));
      text += ` After the late penalty it counts as ${counts(after.result)} (was ${counts(before.result)}).`;
    }
    item.append(element('span', null, text));
    const tests = changedTests(before.result, after.result);
    if (tests.length) {
      const changed = element('ul', 'changed-tests');
      changed.append(...tests.map((t) => element('li', null,
        `${t.name}: ${fmt(t.before, 4)} → ${fmt(t.after, 4)} of ${t.max} points`)));
      item.append(changed);
    }
    list.append(item);
  }
  box.append(list);
  return box;
}
