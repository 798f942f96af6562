// The instructor's side of a course's exercise: the class at a glance (a table of the
// students, what the class gets wrong, regrading, the exports, the staff's actions), and
// one student's page (their submissions, one read beside its result, an extension).
// Everything comes from the course's API; the server checks that the reader is staff.
import { javascript } from '@codemirror/lang-javascript';
import { EditorView, basicSetup } from 'codemirror';
import { byId } from '../controls.js';
import { ApiError, element, getJson, link, percent, renderSubmission, span } from '../student/results.js';

const root = byId('dashboard');
const { course, lab, student } = root.dataset;
const api = `/api/courses/${encodeURIComponent(course)}`;

/** POSTs `body` as JSON; an answer other than 2xx throws an ApiError with the server's text. */
async function postJson(url, body) {
  const response = await fetch(url, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  });
  const answer = await response.json().catch(() => ({}));
  if (!response.ok) throw new ApiError(answer.error ?? `${response.status} ${response.statusText}`, response.status);
  return answer;
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A score or nothing, for a cell. */
const score = (value) => (value === null || value === undefined ? '–' : percent(value));
/** A moment in the reader's time zone. */
const when = (text) => (text ? new Date(text).toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' }) : '–');

/** A table's head and rows, from column titles and rows of cells (text or nodes). */
function fillTable(table, titles, rows) {
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

// ---------------------------------------------------------------------------------------
// Regrades: started here, followed until done, with the scores they changed.

function describeRegrade(regrade) {
  const progress = regrade.finished_at
    ? `done: ${regrade.total} submission(s) regraded`
    : `${regrade.done} of ${regrade.total} regraded…`;
  const box = element('div', 'regrade');
  box.dataset.id = regrade.id;
  box.append(element('p', null,
    `Regrade ${regrade.id} of ${regrade.scope}, asked by ${regrade.requested_by} with ${regrade.grader}: ${progress}`));
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

/** Starts a regrade of `scope` and follows it in `box` (and `status`) until it is done. */
async function regrade(scope, status, box) {
  try {
    const started = await postJson(`${api}/regrades`, { lab, scope });
    status.textContent = `Regrading ${started.total} submission(s) in the background…`;
    for (;;) {
      const progress = await getJson(started.url);
      box.replaceChildren(describeRegrade(progress));
      if (progress.finished_at) break;
      await sleep(500);
    }
    status.textContent = 'Regrade done.';
  } catch (error) {
    status.textContent = `Not regraded: ${error.message}`;
  }
}

// ---------------------------------------------------------------------------------------
// The class.

/** The class's rows with what the table sorts and filters on. */
function classRows(answer) {
  return answer.students.map((s) => ({
    student: s,
    name: s.name || s.id,
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

function showClass(answer) {
  const rows = classRows(answer);
  const policy = answer.policy;
  byId('facts').textContent =
    `Due ${when(policy.due)}, taken until ${when(policy.cutoff)}, ${percent(policy.penalty_per_day)} off per day late; ` +
    `the ${policy.counts} graded submission counts. Graded with ${answer.grader}.`;
  byId('grader').textContent = answer.grader;
  let sortBy = 0;
  let descending = false;
  const table = byId('class-table');
  const draw = () => {
    const filter = byId('filter').value;
    const below = Number(byId('below').value) / 100;
    const find = byId('find').value.trim().toLowerCase();
    const shown = rows.filter((r) => {
      if ((filter === 'dropped') !== r.student.dropped) return false;
      if (filter === 'not-submitted' && r.student.submissions > 0) return false;
      if (filter === 'below' && !(r.counting === null || r.counting < below)) return false;
      if (filter === 'late' && !r.late) return false;
      return !find || r.name.toLowerCase().includes(find) || r.student.id.toLowerCase().includes(find);
    });
    const key = COLUMNS[sortBy][1];
    shown.sort((a, b) => {
      const [x, y] = [key(a), key(b)];
      const order = typeof x === 'number' ? x - y : String(x).localeCompare(String(y));
      return descending ? -order : order;
    });
    fillTable(table, COLUMNS.map(([title]) => title), shown.map((r) => [
      link(`/courses/${course}/${lab}/students/${encodeURIComponent(r.student.id)}`, r.name),
      r.student.id,
      r.student.submissions,
      score(r.counting),
      score(r.latest),
      r.late ? `late, −${percent(r.student.counting.penalty)}` : (r.student.counting ? 'on time' : '–'),
      when(r.last),
    ]));
    // Each column's title sorts by it; again, the other way round.
    table.querySelectorAll('th').forEach((th, i) => {
      th.setAttribute('aria-sort', i === sortBy ? (descending ? 'descending' : 'ascending') : 'none');
      const button = element('button', 'link', th.textContent);
      button.type = 'button';
      button.addEventListener('click', () => {
        descending = i === sortBy ? !descending : false;
        sortBy = i;
        draw();
      });
      th.replaceChildren(button);
    });
    byId('count').textContent = `${shown.length} of ${rows.length} student(s)`;
  };
  for (const id of ['filter', 'below', 'find']) byId(id).addEventListener('input', draw);
  draw();

  const mistakes = byId('mistakes');
  mistakes.replaceChildren(...answer.mistakes.map((m) => {
    const item = element('li', 'mistake');
    item.dataset.kind = m.kind;
    item.append(element('strong', null, `${m.students.length} student(s): `), document.createTextNode(m.text), element('br'));
    m.students.forEach((id, i) => {
      if (i > 0) item.append(', ');
      item.append(link(`/courses/${course}/${lab}/students/${encodeURIComponent(id)}`, id));
    });
    return item;
  }));
  if (answer.mistakes.length === 0) mistakes.replaceChildren(element('li', null, 'No classic mistake in the submissions that count.'));

  byId('regrades').replaceChildren(...answer.regrades.map(describeRegrade));
}

async function showAudit() {
  const log = await getJson(`${api}/audit`);
  fillTable(byId('audit'), ['When', 'Who', 'What', 'Detail'],
    log.map((entry) => [when(entry.at), entry.actor, entry.action, entry.detail]));
}

async function classPage() {
  const url = `${api}/labs/${encodeURIComponent(lab)}/class`;
  showClass(await getJson(url));
  await showAudit();
  byId('regrade-all').addEventListener('click', async () => {
    if (!window.confirm('Regrade every submission of the assignment with the grader as it is now?')) return;
    const box = element('div');
    byId('regrades').prepend(box);
    await regrade({ kind: 'assignment' }, byId('regrade-status'), box);
    showClass(await getJson(url));
    await showAudit();
  });
}

// ---------------------------------------------------------------------------------------
// One student.

async function studentPage() {
  const url = `${api}/labs/${encodeURIComponent(lab)}/students/${encodeURIComponent(student)}`;
  const source = new EditorView({
    doc: '',
    extensions: [basicSetup, javascript(), EditorView.editable.of(false), EditorView.lineWrapping],
    parent: byId('source'),
  });
  const show = async (id) => {
    const submission = await getJson(`/api/submissions/${id}`);
    source.dispatch({ changes: { from: 0, to: source.state.doc.length, insert: submission.source ?? '' } });
    renderSubmission(byId('result'), submission, { open: true });
  };
  const refresh = async () => {
    const answer = await getJson(url);
    const { member, policy, extension } = answer;
    byId('student-facts').textContent =
      `${member.name || member.login} (${member.login}, ${member.email || 'no email'})${member.dropped ? ', dropped from the roster' : ''}. ` +
      `Due ${when(policy.due)}, taken until ${when(policy.cutoff)}` +
      (extension ? `, by an extension ${extension.granted_by} granted on ${when(extension.granted_at)}.` : '.');
    fillTable(byId('student-submissions'), ['#', 'Submitted', 'Status', 'Score', 'Late', 'Counts as'],
      answer.submissions.slice().reverse().map((s) => [
        s.id, when(s.submitted_at), s.status, score(s.score),
        s.late_seconds > 0 ? `${span(s.late_seconds)} (−${percent(s.penalty)})` : 'on time', score(s.final_score),
      ]));
    const choose = byId('view-submission');
    choose.replaceChildren(...answer.submissions.slice().reverse().map((s) => new Option(`submission ${s.id}`, s.id)));
    if (answer.submissions.length > 0) await show(choose.value);
  };
  byId('view-submission').addEventListener('change', (event) => show(event.target.value));
  byId('extension-form').addEventListener('submit', async (event) => {
    event.preventDefault();
    const form = new FormData(event.target);
    const cutoff = String(form.get('cutoff')).trim();
    try {
      await postJson(`${api}/extensions`, { lab, student, due: String(form.get('due')).trim(), ...(cutoff ? { cutoff } : {}) });
      byId('extension-status').textContent = 'Extension granted.';
      await refresh();
    } catch (error) {
      byId('extension-status').textContent = `Not granted: ${error.message}`;
    }
  });
  byId('regrade-student').addEventListener('click', async () => {
    await regrade({ kind: 'student', of: student }, byId('regrade-student-status'), byId('regrade-student-status'));
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
