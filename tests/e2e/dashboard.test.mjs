// The instructor's side in headless Chromium against the real server: the instructor
// signs in from the link `estlab course create` prints and watches the class table fill
// as students submit (through the API, with their own sessions); the class's pictures say
// in their captions what they show; a student's page shows a submission beside its
// result and the line differences between two of them, and grants an extension that
// the audit log records. Then the grader changes (the server restarts with another
// secret, so the plan's hash and the hidden cases change), the whole assignment is
// regraded from the page, and the scores it lists as changed are those the API's kept
// results say changed; the gradebook CSV matches the class; the student sees on /me that
// their submission was regraded and what changed; a student and nobody signed in cannot
// open any of it.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, classTable, correct, estlab, launchBrowser, openPage, signIn, starter, startServer, tempDir, waitFor,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
const CLASS_PAGE = `/courses/${COURSE}/${LAB}`;
const CLASS_API = `/api/courses/${COURSE}/labs/${LAB}/class`;

/** The starter file: every function throws at once, so that it is graded quickly. */

/**
 * correct.js with calculate_odometry 2.4 % slow whenever the wheels' mean speed is above
 * 0.2 m/s: wrong for some cases only, so its points depend on which cases are drawn. Of
 * the few such files tried (a range too long beyond 6 m, a bearing off for landmarks
 * behind, a heading that turns 10 % too far, a Jacobian with a flipped sign, and this
 * one), this is one whose score, as submission 4 of student s3, differs between the two
 * secrets below (the hidden cases are drawn from the secret and the submission's id):
 * calculate_odometry earns 5 of 10 points with SECRET_BEFORE and 5.83 with SECRET_AFTER.
 */
const slowOdometry = correct.replace('const v = (v_R + v_L) / 2;', 'const v = v_R + v_L > 0.4 ? (v_R + v_L) / 2.05 : (v_R + v_L) / 2;');
assert.notEqual(slowOdometry, correct, 'the mistake is made in correct.js');

/** The server's secret before and after the grader changes: 32 fixed bytes each. */
const SECRET_BEFORE = Buffer.alloc(32, 0x11);
const SECRET_AFTER = Buffer.alloc(32, 0x22);

let server;
let browser;
/** The data directory, kept across the restart. */
const dataDir = tempDir();
/** The students: { id, name, email, code, link, cookie }. */
const students = {};
/** The instructor's page, in a browser context of their own. */
let staff;
/** Submissions by name: { id, student }. */
const sent = {};
/** The grader before the restart, as the class API names it. */
let graderBefore;

before(async () => {
  writeFileSync(join(dataDir, 'secret'), SECRET_BEFORE);
  server = await startServer({ dataDir });
  browser = await launchBrowser();
}, bounded);
after(async () => {
  await browser?.close();
  await server?.stop();
}, bounded);

/** A moment `days` from now, as the command line and the extension form take it. */
function fromNow(days) {
  return new Date(Date.now() + days * 86_400_000).toISOString().replace(/\.\d+Z$/, 'Z');
}

/** A request as a student (their cookie) or nobody; resolves to { status, body, location }. */
async function as(student, path, { method = 'GET', body } = {}) {
  const headers = student ? { cookie: student.cookie } : {};
  if (body !== undefined) headers['content-type'] = 'application/json';
  const response = await fetch(server.url + path, {
    method, headers, redirect: 'manual', body: body === undefined ? undefined : JSON.stringify(body),
  });
  const text = await response.text();
  let parsed = text;
  try { parsed = JSON.parse(text); } catch { /* a page */ }
  return { status: response.status, body: parsed, location: response.headers.get('location') };
}

/** Submits `source` as `student`; resolves to the new submission's id. */
async function submitAs(student, source) {
  const { status, body } = await as(student, '/api/submissions', { method: 'POST', body: { source } });
  assert.equal(status, 202, JSON.stringify(body));
  return body.id;
}

/** A submission once graded, read as its student. */
function graded(student, id) {
  return waitFor(`submission ${id} to be graded`, async () => (await as(student, `/api/submissions/${id}`)).body,
    (s) => s.status === 'graded', { timeout: 180_000, interval: 300 });
}

/** GETs an API path as the instructor, from their page (their session). */
function staffGet(path) {
  return staff.evaluate(async (url) => {
    const response = await fetch(url);
    return { status: response.status, body: await response.json() };
  }, path).then(({ status, body }) => {
    assert.equal(status, 200, `${path}: ${JSON.stringify(body)}`);
    return body;
  });
}

/** Goes to `path` in `page` and waits until its script says it is ready. */
async function visit(page, path) {
  await page.goto(server.url + path);
  await page.waitForSelector('body[data-ready=true]', { timeout: 60_000 });
}

const percent = (share) => (share === null || share === undefined ? '–' : `${Math.round(100 * share)} %`);

/** The problems a page had, less Chromium's line for each answer the test expected to be refused. */
function unexpected(page, ...statuses) {
  const expected = statuses.map((status) => `console: Failed to load resource: the server responded with a status of ${status}`);
  return page.problems.filter((problem) => {
    const i = expected.findIndex((e) => problem.startsWith(e));
    if (i < 0) return true;
    expected.splice(i, 1);
    return false;
  });
}

/** A CSV as rows of fields (quoted fields may hold commas, quotes and line breaks). */
function parseCsv(text) {
  const rows = [];
  let row = [];
  let field = '';
  let quoted = false;
  for (let i = 0; i < text.length; i++) {
    const c = text[i];
    if (quoted) {
      if (c === '"' && text[i + 1] === '"') { field += '"'; i++; } else if (c === '"') quoted = false; else field += c;
    } else if (c === '"') quoted = true;
    else if (c === ',') { row.push(field); field = ''; } else if (c === '\n') { row.push(field); rows.push(row); row = []; field = ''; } else if (c !== '\r') field += c;
  }
  if (field || row.length) { row.push(field); rows.push(row); }
  const [header, ...rest] = rows;
  return rest.map((cells) => Object.fromEntries(header.map((name, i) => [name, cells[i]])));
}

test('the instructor signs in from the link and watches the class table fill as students submit; the pictures say what they show', bounded, async () => {
  const where = ['--data', dataDir, '--url', server.url];
  const created = estlab('course', 'create', COURSE, '--title', 'Applied Estimation', ...where);
  const instructorLink = created.trim().split('\n').pop();
  const dir = tempDir();
  writeFileSync(join(dir, 'roster.csv'), [
    'id,name,email',
    's1,Ada One,ada@example.org',
    's2,"Bo Two, Jr.",bo@example.org',
    's3,Cy Three,cy@example.org',
    's4,Di Four,di@example.org',
  ].join('\n') + '\n');
  estlab('course', 'roster', COURSE, join(dir, 'roster.csv'), '--out', join(dir, 'codes.csv'), ...where);
  for (const row of parseCsv(readFileSync(join(dir, 'codes.csv'), 'utf8'))) students[row.id] = { ...row };
  assert.deepEqual(Object.keys(students), ['s1', 's2', 's3', 's4']);
  estlab('course', 'assign', COURSE, LAB, '--due', fromNow(7), '--cutoff', fromNow(9), '--late-penalty', '10%/day', ...where);

  // The instructor: from the link to /me, and from there to the class.
  staff = await openPage(browser, instructorLink);
  await staff.locator('#sign-in').click();
  await staff.waitForURL(`${server.url}/me`);
  await staff.locator(`#staff-assignments a[href="${CLASS_PAGE}"]`).click();
  await staff.waitForURL(server.url + CLASS_PAGE);
  await staff.waitForSelector('body[data-ready=true]');
  let rows = await classTable(staff);
  assert.deepEqual(Object.keys(rows).sort(), ['s1', 's2', 's3', 's4']);
  for (const row of Object.values(rows)) assert.equal(row.Submissions, '0');
  assert.equal(await staff.locator('#distribution-caption').textContent(),
    'Scores that count: no student has a graded submission yet; 4 of the roster have no graded submission.');

  // The students submit with their own sessions: s1 the reference solution, s2 the
  // starter file, s3 the starter file and then (once graded) a file with a mistake.
  for (const student of Object.values(students)) student.cookie = await signIn(server, student.code);
  sent.correct = { id: await submitAs(students.s1, correct), student: 's1' };
  sent.starter = { id: await submitAs(students.s2, starter), student: 's2' };
  sent.first = { id: await submitAs(students.s3, starter), student: 's3' };
  await graded(students.s3, sent.first.id);
  sent.mistake = { id: await submitAs(students.s3, slowOdometry), student: 's3' };
  assert.deepEqual(Object.values(sent).map((s) => s.id), [1, 2, 3, 4], 'the ids the mistake file was chosen for');
  const results = {};
  for (const [name, { id, student }] of Object.entries(sent)) results[name] = await graded(students[student], id);
  assert.equal(results.correct.score, 1);
  assert.equal(results.starter.score, 0);
  assert.ok(results.mistake.score > 0.5 && results.mistake.score < 1, `the mistake costs some points: ${results.mistake.score}`);

  // The table fills: Refresh until every submission is there with its score.
  const latest = { s1: results.correct.score, s2: results.starter.score, s3: results.mistake.score };
  rows = await waitFor('the class table to show every score', async () => {
    await staff.locator('#refresh-class').click();
    await staff.waitForFunction(() => /^As of /.test(document.querySelector('#refresh-status').textContent));
    await staff.evaluate(() => { document.querySelector('#refresh-status').textContent = ''; });
    return classTable(staff);
  }, (shown) => Object.entries(latest).every(([id, share]) => shown[id]?.['Latest score'] === percent(share)), { timeout: 60_000, interval: 500 });
  const answer = await staffGet(CLASS_API);
  for (const s of answer.students) {
    const row = rows[s.id];
    assert.equal(row.Name, s.name);
    assert.equal(row.Submissions, String(s.submissions));
    assert.equal(row['Score that counts'], percent(s.counting?.final_score));
    assert.equal(row['Latest score'], percent(s.latest?.final_score));
  }
  assert.equal(rows.s3.Submissions, '2');
  assert.equal(rows.s4['Score that counts'], '–');

  // Filtered: not submitted yet, below a score.
  await staff.locator('#filter').selectOption('not-submitted');
  assert.deepEqual(Object.keys(await classTable(staff)), ['s4']);
  await staff.locator('#filter').selectOption('below');
  assert.deepEqual(Object.keys(await classTable(staff)).sort(), ['s2', 's4']);
  await staff.locator('#filter').selectOption('all');
  // Found by name without its accents or case, by id, and by email.
  for (const [typed, found] of [['ADA ONE', ['s1']], ['jr.', ['s2']], ['s3', ['s3']], ['di@example', ['s4']]]) {
    await staff.locator('#find').fill(typed);
    assert.deepEqual(Object.keys(await classTable(staff)), found, typed);
  }
  await staff.locator('#find').fill('');

  // The distribution of the scores that count, as bars and in words.
  const scores = answer.students.map((s) => s.counting?.final_score).filter((v) => v !== null && v !== undefined).sort((a, b) => a - b);
  assert.equal(scores.length, 3);
  assert.equal(await staff.locator('#distribution-caption').textContent(),
    `Scores that count: 3 students, median ${percent(scores[1])}, 1 below 50 %; 1 of the roster has no graded submission.`);
  const drawn = await staff.evaluate(() => {
    const data = (id) => document.querySelector(`#${id} .chart`).plot.chart.getOption().series[0].data;
    return { distribution: data('distribution-figure'), tests: data('tests-figure') };
  });
  assert.deepEqual(drawn.distribution, answer.distribution);
  assert.equal(answer.distribution.reduce((a, b) => a + b), 3);
  assert.match(await staff.locator('#distribution-figure .plot-summary').textContent(), /^Students per band of the score that counts: 0–10 %: 1; /);

  // Each test's share of students passing it, as horizontal bars and in words.
  assert.equal(answer.tests.length, 11);
  assert.deepEqual(drawn.tests.map((v) => Math.round(v)), answer.tests.map((t) => Math.round((100 * t.passed) / t.of)));
  const odometry = answer.tests.find((t) => t.name.startsWith('calculate_odometry'));
  assert.equal(odometry.passed, 1, 'only the reference solution passes calculate_odometry');
  assert.match(await staff.locator('#tests-caption').textContent(),
    /^Students passing each test, of 3 with a graded submission that counts: \d+ of 11 tests passed by all; fewest pass \S.* \(\d of 3, \d+ %\)\.$/);
  const summary = await staff.locator('#tests-figure .plot-summary').textContent();
  for (const t of answer.tests) assert.ok(summary.includes(`${t.name}: ${t.passed} of ${t.of}`), `${t.name} in the summary`);

  // A column per test: each student's mark for the submission that counts.
  for (const s of answer.students) {
    for (const t of answer.tests) {
      const passed = s.tests[t.name];
      assert.equal(rows[s.id][t.name], passed === undefined ? '–' : passed ? '✓' : '✗', `${s.id}, ${t.name}`);
    }
  }

  // Every classic mistake names its tests and links to its students' pages by name.
  const names = Object.fromEntries(answer.students.map((s) => [s.id, s.name]));
  for (const mistake of answer.mistakes) {
    const item = staff.locator(`#mistakes li[data-kind="${mistake.kind}"]`);
    const count = mistake.students.length === 1 ? '1 student' : `${mistake.students.length} students`;
    assert.equal(await item.locator('strong').textContent(), `${count}, in ${mistake.functions.join(', ')}: `);
    assert.deepEqual(await item.locator('a').evaluateAll((links) => links.map((a) => [a.getAttribute('href'), a.textContent])),
      mistake.students.map((id) => [`${CLASS_PAGE}/students/${id}`, `${names[id]} (${id})`]));
  }
  assert.deepEqual(unexpected(staff), []);
});

test('a student\'s page: a submission beside its result, two compared line by line, and an extension the audit log records', bounded, async () => {
  await staff.locator('#class-table tr[data-student=s3] a').click();
  await staff.waitForURL(`${server.url}${CLASS_PAGE}/students/s3`);
  await staff.waitForSelector('body[data-ready=true]');
  // Headed by the student's name, not the id.
  await staff.waitForFunction(() => document.querySelector('#student-name').textContent === 'Cy Three');
  const ids = await staff.locator('#student-submissions tbody tr').evaluateAll((rows) => rows.map((row) => Number(row.dataset.id)));
  assert.deepEqual(ids, [sent.mistake.id, sent.first.id], 'newest first');

  // The newest, its source read-only and highlighted beside its full result.
  assert.equal(await staff.locator('#view-submission').inputValue(), String(sent.mistake.id));
  await staff.locator('#result[data-status=graded]').waitFor();
  const mistake = await staffGet(`/api/submissions/${sent.mistake.id}`);
  assert.match(await staff.locator('#result .verdict').textContent(),
    new RegExp(`^The server's grade for submission ${sent.mistake.id}: .* \\(${Math.round(100 * mistake.score)}%\\)\\.`));
  assert.equal(await staff.locator('#result .server-tests .test').count(), 11);
  const code = staff.locator('#source .cm-content');
  assert.equal(await staff.locator('#source').evaluate((box) => box.editor.state.doc.toString()), slowOdometry);
  assert.match(await code.textContent(), /^\/\/ EKF localization \(EL2320 lab\): a correct solution/);
  assert.equal(await code.getAttribute('contenteditable'), 'false', 'read-only');
  assert.ok(await staff.locator('#source .cm-line span[class]').count() > 0, 'highlighted');
  assert.equal(await staff.locator('#diff').isVisible(), false);

  // Compared with the earlier one: the lines added and removed, marked + and -.
  await staff.locator('#compare-submission').selectOption(String(sent.first.id));
  await staff.locator('#diff:not([hidden])').waitFor();
  assert.equal(await staff.locator('#source').isVisible(), false, 'the difference in place of the source');
  const diff = staff.locator('#diff');
  const [added, removed] = [Number(await diff.getAttribute('data-added')), Number(await diff.getAttribute('data-removed'))];
  assert.ok(added > 0 && removed > 0, `lines added (${added}) and removed (${removed})`);
  assert.equal(await diff.locator('.diff-summary').textContent(),
    `From submission ${sent.first.id} to submission ${sent.mistake.id}: ${added} line(s) added (+), ${removed} removed (-).`);
  assert.equal(await diff.locator('tr.added').count(), added);
  assert.equal(await diff.locator('tr.removed').count(), removed);
  assert.deepEqual([...new Set(await diff.locator('tr.added td.mark').allTextContents())], ['+']);
  assert.deepEqual([...new Set(await diff.locator('tr.removed td.mark').allTextContents())], ['-']);
  const line = diff.locator('tr.added', { hasText: 'v_R + v_L > 0.4' });
  assert.equal(await line.count(), 1, 'the mistake\'s line is added');
  assert.equal(await line.locator('td.code').textContent(), slowOdometry.split('\n').find((l) => l.includes('v_R + v_L > 0.4')));
  const newNumber = Number(await line.locator('td.number').nth(1).textContent());
  assert.ok(slowOdometry.split('\n')[newNumber - 1].includes('v_R + v_L > 0.4'), 'numbered as in the newer file');
  const backgrounds = await staff.evaluate(() => ['tr.added', 'tr.removed', 'tr.same'].map((selector) => {
    const row = document.querySelector(`#diff ${selector}`);
    return row ? getComputedStyle(row).backgroundColor : null;
  }));
  assert.equal(new Set(backgrounds).size, 3, `added, removed and unchanged lines in colours of their own: ${backgrounds}`);
  // Back to the source alone.
  await staff.locator('#compare-submission').selectOption('');
  await staff.locator('#source:not([hidden])').waitFor();
  assert.equal(await diff.isVisible(), false);

  // An extension, granted through the form: the page and the API show the new dates.
  const due = fromNow(14);
  const cutoff = fromNow(15);
  await staff.locator('#extension-form input[name=due]').fill(due);
  await staff.locator('#extension-form input[name=cutoff]').fill(cutoff);
  await staff.locator('#extension-form button[type=submit]').click();
  await waitFor('the extension to be granted', () => staff.locator('#extension-status').textContent(), (text) => text !== '', { timeout: 30_000 });
  assert.match(await staff.locator('#extension-status').textContent(),
    /^Extension granted: due .*, taken until .*\. No score of the submissions already made changed\.$/, 'on time already');
  assert.match(await staff.locator('#student-facts').textContent(), /, by an extension instructor granted on /);
  const student = await staffGet(`/api/courses/${COURSE}/labs/${LAB}/students/s3`);
  assert.equal(student.extension.granted_by, 'instructor');
  assert.equal(Date.parse(student.policy.due), Date.parse(due));
  assert.equal(Date.parse(student.policy.cutoff), Date.parse(cutoff));
  const local = (at) => staff.evaluate((moment) => new Date(moment).toLocaleString(undefined, {
    year: 'numeric', month: 'short', day: 'numeric', hour: '2-digit', minute: '2-digit', timeZoneName: 'short',
  }), at);
  assert.ok((await staff.locator('#student-facts').textContent()).includes(`Due ${await local(due)}, taken until ${await local(cutoff)}, by an extension`));

  // ... and the audit log on the class page.
  await staff.locator(`a[href="${CLASS_PAGE}"]`).first().click();
  await staff.waitForURL(server.url + CLASS_PAGE);
  await staff.waitForSelector('body[data-ready=true]');
  const audit = await staff.locator('#audit tbody tr').evaluateAll((rows) => rows.map((row) => [...row.cells].map((td) => td.textContent)));
  const granted = audit.find(([, who, what, detail]) => who === 'instructor' && what === 'extension' && detail.startsWith('s3, ekf-localization: due '));
  assert.ok(granted, `the extension in the audit table: ${JSON.stringify(audit)}`);
  assert.deepEqual(unexpected(staff), []);
});

test('after the grader changes, the whole assignment is regraded from the page with its progress, and the changed scores are those the API kept', bounded, async () => {
  graderBefore = (await staffGet(CLASS_API)).grader;
  // Another secret: other hidden cases, and a plan (with its hidden cases) of another hash.
  await server.stop();
  writeFileSync(join(dataDir, 'secret'), SECRET_AFTER);
  // Refused unless the secret is said to be new: the database keeps the first's fingerprint.
  await assert.rejects(startServer({ dataDir }), /secret \(fingerprint [0-9a-f]{16}\) is not the one this database's submissions are graded with/);
  server = await startServer({ dataDir, args: ['--new-secret'] });
  await visit(staff, CLASS_PAGE);
  const grader = await staff.locator('#grader').textContent();
  assert.match(grader, /^estlab \S+ plan [0-9a-f]{12}, JavaScript on (V8|QuickJS)$/);
  assert.notEqual(grader, graderBefore, 'the grader version changed');

  // Every text the regrade's box and status show, as they change.
  await staff.evaluate(() => {
    window.seen = [];
    const record = () => window.seen.push(`${document.querySelector('#regrade-status').textContent} | ${document.querySelector('#regrades').firstElementChild?.textContent ?? ''}`);
    new MutationObserver(record).observe(document.querySelector('#regrade-status'), { childList: true, characterData: true, subtree: true });
    new MutationObserver(record).observe(document.querySelector('#regrades'), { childList: true, characterData: true, subtree: true });
  });
  let asked = null;
  staff.once('dialog', (dialog) => { asked = dialog.message(); dialog.accept(); });
  await staff.locator('#regrade-all').click();
  await waitFor('the regrade to finish', () => staff.locator('#regrade-status').textContent(),
    (text) => text.startsWith('Regrade done') || text.startsWith('Not regraded'), { timeout: 180_000, interval: 300 });
  assert.match(asked, /^Regrade every submission of the assignment/);
  const seen = await staff.evaluate(() => window.seen);
  assert.ok(seen.some((text) => text.startsWith('Regrading 4 submission(s) in the background…')), `the progress: ${seen.join('\n')}`);
  assert.ok(seen.every((text) => !/regraded…|done:/.test(text) || /(\d+) of 4 regraded…|done: 4 submission\(s\) regraded/.test(text)), seen.join('\n'));

  // The list of changed scores, against each submission's results in the API.
  const box = staff.locator('#regrades .regrade').first();
  assert.match(await box.locator('p').first().textContent(),
    new RegExp(`^Regrade \\d+ of assignment, asked by instructor with ${grader.replace(/[.]/g, '\\.')}: done: 4 submission\\(s\\) regraded$`));
  const listed = await box.locator('table.changed tbody tr').evaluateAll((rows) => rows.map((row) => [...row.cells].map((td) => td.textContent)));
  const changed = [];
  for (const { id, student } of Object.values(sent)) {
    const submission = await staffGet(`/api/submissions/${id}`);
    assert.equal(submission.grader, grader, `submission ${id} regraded with the new grader`);
    assert.equal(submission.earlier.length, 1, `submission ${id}'s first result kept`);
    const [first] = submission.earlier;
    assert.equal(first.grader, graderBefore);
    if (Math.abs(first.score - submission.score) > 1e-9) changed.push({ id, student, before: first.score, after: submission.score });
  }
  assert.deepEqual(changed.map((c) => c.id), [sent.mistake.id], 'the secrets were chosen so that the mistake file\'s score changes');
  assert.equal(await staff.locator('#regrade-status').textContent(), `Regrade done: ${changed.length} score(s) changed.`);
  assert.deepEqual(listed, changed.map((c) => {
    const delta = c.after - c.before;
    return [c.student, String(c.id), percent(c.before), percent(c.after), `${delta >= 0 ? '+' : '−'}${percent(Math.abs(delta))}`];
  }));
  // The class table has the new score.
  const rows = await classTable(staff);
  assert.equal(rows.s3['Latest score'], percent(changed[0].after));
  assert.deepEqual(unexpected(staff), []);
});

test('the gradebook CSV downloaded from the export link matches the class', bounded, async () => {
  const [download] = await Promise.all([
    staff.waitForEvent('download'),
    staff.locator('a[href$="export?format=csv"]').click(),
  ]);
  assert.equal(download.suggestedFilename(), `${COURSE}-${LAB}-grades.csv`);
  const text = readFileSync(await download.path(), 'utf8');
  const rows = parseCsv(text);
  assert.deepEqual(Object.keys(rows[0]), ['id', 'name', 'email', 'status', 'submissions', 'score', 'late_penalty', 'final_score', 'submitted_at',
    'report_status', 'lab_passed']);
  const answer = await staffGet(CLASS_API);
  assert.deepEqual(rows.map((r) => r.id), answer.students.map((s) => s.id));
  const number = (field) => (field === '' ? null : Number(field));
  const close = (a, b) => (a === null || b === null || b === undefined ? a === (b ?? null) : Math.abs(a - b) < 5e-5);
  for (const row of rows) {
    const s = answer.students.find((x) => x.id === row.id);
    assert.equal(row.name, s.name);
    assert.equal(row.email, s.email);
    assert.equal(row.status, s.dropped ? 'dropped' : 'enrolled');
    assert.equal(Number(row.submissions), s.submissions);
    assert.ok(close(number(row.score), s.counting?.score), `${row.id}: score ${row.score} against ${s.counting?.score}`);
    assert.ok(close(number(row.final_score), s.counting?.final_score), `${row.id}: final_score ${row.final_score} against ${s.counting?.final_score}`);
    assert.ok(close(number(row.late_penalty), s.counting?.penalty), `${row.id}: late_penalty`);
    assert.equal(row.submitted_at, s.counting?.submitted_at ?? '');
  }
  assert.equal(rows.find((r) => r.id === 's2').name, 'Bo Two, Jr.', 'a quoted name with a comma');
  assert.equal(rows.find((r) => r.id === 's4').score, '', 'nothing for a student who has not submitted');
  assert.equal(Number(rows.find((r) => r.id === 's1').final_score), 1);
});

test('the student sees on /me and in the workbench that their submission was regraded, and what changed', bounded, async () => {
  const context = await browser.newContext({ viewport: { width: 1400, height: 1000 } });
  const [name, value] = students.s3.cookie.split('=');
  await context.addCookies([{ name, value, url: server.url }]);
  const page = await context.newPage();
  await visit(page, '/me');
  const submission = await as(students.s3, `/api/submissions/${sent.mistake.id}`);
  const { earlier: [before], result: after, grader } = submission.body;
  const note = page.locator('.latest .submission .regraded');
  await note.waitFor({ timeout: 30_000 });
  const text = await note.textContent();
  assert.match(text, /^This submission was regraded: the result below replaced the one it first had\./);
  assert.ok(text.includes(`with ${grader} (first graded with ${graderBefore})`), text);
  const score = (r) => `${Math.round(100 * r.score)} % (${Number(r.points.toPrecision(4))} of ${r.max_points} points)`;
  assert.ok(text.includes(`the score went from ${score(before.result)} to ${score(after)}.`), text);
  const tests = await note.locator('.changed-tests li').allTextContents();
  const expected = after.tests.flatMap((t) => {
    const old = before.result.tests.find((o) => o.name === t.name).points;
    return Math.abs(old - t.points) > 1e-9 ? [`${t.name}: ${Number(old.toPrecision(4))} → ${Number(t.points.toPrecision(4))} of ${t.max_points} points`] : [];
  });
  assert.ok(expected.length > 0);
  assert.deepEqual(tests, expected);
  // The other hidden cases change calculate_odometry's share; the whole data sets drawn
  // from the other secret may pass or fail a run of the mistake besides.
  assert.ok(tests.some((t) => t.startsWith('calculate_odometry')), tests.join('\n'));

  // The same in the workbench, where the submission opens read-only.
  await visit(page, `/ekf/code?submission=${sent.mistake.id}`);
  assert.match(await page.locator('#viewer-result .regraded').textContent(), /^This submission was regraded/);
  // A submission that was not regraded into another score still says it was regraded, with the score kept.
  await visit(page, `/ekf/code?submission=${sent.first.id}`);
  assert.match(await page.locator('#viewer-result .regraded').textContent(), /the score stayed 0 % \(0 of 110 points\)\./);

  // The workbench's deadline is the standing the server sends: with an extension whose
  // due date has passed a day and a half ago, a submission now is late, and loses two
  // days' penalty (a day begun counts).
  const granted = await staff.evaluate(async (body) => {
    const response = await fetch('/api/courses/el2320/extensions', {
      method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body),
    });
    return response.status;
  }, { lab: LAB, student: 's3', due: fromNow(-1.5), cutoff: fromNow(2) });
  assert.equal(granted, 200);
  await visit(page, '/ekf/code');
  const { body: me } = await as(students.s3, '/api/me');
  assert.equal(me.assignments[0].standing.state, 'late');
  assert.equal(me.assignments[0].standing.penalty, 0.2);
  assert.match(await page.locator('#deadline').textContent(),
    /^Due .*: a submission now is 1 day 1\d h late and loses 20 % of its score; the last are taken until .*, 1 day 23 h from now\.$/);
  await context.close();
});

test('a student cannot open the dashboard or call its API (404), and nobody signed in is sent to sign in', bounded, async () => {
  const paths = [
    CLASS_PAGE,
    `${CLASS_PAGE}/students/s1`,
    `${CLASS_PAGE}/students/s3`,
    CLASS_API,
    `/api/courses/${COURSE}/labs/${LAB}/students/s1`,
    `/api/courses/${COURSE}/labs/${LAB}/export?format=csv`,
    `/api/courses/${COURSE}/labs/${LAB}/export?format=sources`,
    `/api/courses/${COURSE}/audit`,
    `/api/courses/${COURSE}/regrades/1`,
  ];
  for (const student of [students.s1, students.s3]) {
    for (const path of paths) {
      const { status } = await as(student, path);
      assert.equal(status, 404, `${student.id}: GET ${path}`);
    }
    for (const [path, body] of [
      [`/api/courses/${COURSE}/regrades`, { lab: LAB, scope: { kind: 'assignment' } }],
      [`/api/courses/${COURSE}/extensions`, { lab: LAB, student: student.id, due: fromNow(30) }],
    ]) {
      const { status } = await as(student, path, { method: 'POST', body });
      assert.equal(status, 404, `${student.id}: POST ${path}`);
    }
  }
  // Nothing changed by those attempts.
  const student = await staffGet(`/api/courses/${COURSE}/labs/${LAB}/students/s1`);
  assert.equal(student.extension, null);
  assert.equal((await staffGet(CLASS_API)).regrades.length, 1);

  // In a browser too: the page is the site's 404.
  const context = await browser.newContext();
  const [name, value] = students.s1.cookie.split('=');
  await context.addCookies([{ name, value, url: server.url }]);
  const page = await context.newPage();
  const response = await page.goto(server.url + CLASS_PAGE);
  assert.equal(response.status(), 404);
  assert.equal(await page.locator('#dashboard').count(), 0);
  await context.close();

  // Nobody signed in: the pages send to /signin, the API answers 404.
  for (const path of paths) {
    const { status, location } = await as(null, path);
    if (path.startsWith('/api/')) assert.equal(status, 404, `anonymous: GET ${path}`);
    else assert.deepEqual([Math.floor(status / 100), location], [3, '/signin'], `anonymous: GET ${path}`);
  }
  const anonymous = await browser.newPage();
  await anonymous.goto(server.url + CLASS_PAGE);
  assert.equal(new URL(anonymous.url()).pathname, '/signin');
  await anonymous.close();
});
