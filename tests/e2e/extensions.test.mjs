// Extensions and waivers in headless Chromium against the real server, at a phone's size
// and a laptop's: the exercise was due seconds before the students submitted, so each
// submission is a few seconds late ("12 s late", never "0 min") and loses 10 %. On the
// staff's student page the instructor reads what an extension covers, waives the penalty
// of one submission with a reason, and grants an extension: the page lists the score it
// re-judged (before and after), the submissions count in full, and the student's /me
// shows the waiver, their own dates and what they cover.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, correct, estlab, laptop, launchBrowser, openIn, parseCsv, phone, signIn, signedInContext, startServer, tempDir,
  waitFor,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
const REASON = 'ill on the due date';

let server;
let browser;
/** The students by id: { id, code, cookie, submissions: [first, second] }. */
const students = {};

const fromNow = (seconds) => new Date(Date.now() + seconds * 1000).toISOString().replace(/\.\d+Z$/, 'Z');

async function api(cookie, path, { method = 'GET', body } = {}) {
  const headers = { cookie };
  if (body !== undefined) headers['content-type'] = 'application/json';
  const response = await fetch(server.url + path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  return { status: response.status, body: await response.json() };
}

async function submitGraded(student) {
  const { status, body } = await api(student.cookie, '/api/submissions', { method: 'POST', body: { source: correct } });
  assert.equal(status, 202, JSON.stringify(body));
  await waitFor(`submission ${body.id} to be graded`, async () => (await api(student.cookie, `/api/submissions/${body.id}`)).body,
    (s) => s.status === 'graded', { timeout: 180_000, interval: 300 });
  return body.id;
}

before(async () => {
  server = await startServer();
  browser = await launchBrowser();
  const where = ['--data', server.dataDir, '--url', server.url];
  estlab('course', 'create', COURSE, '--title', 'Applied Estimation', ...where);
  const dir = tempDir();
  writeFileSync(join(dir, 'roster.csv'), 'id,name,email\nphone,Pat Phone,pat@example.org\nlaptop,Lee Laptop,lee@example.org\n');
  estlab('course', 'roster', COURSE, join(dir, 'roster.csv'), '--out', join(dir, 'codes.csv'), ...where);
  // Due a moment ago: what the students submit now is seconds late.
  estlab('course', 'assign', COURSE, LAB, '--due', fromNow(-3), '--cutoff', fromNow(86_400), '--late-penalty', '10%/day', ...where);
  for (const row of parseCsv(readFileSync(join(dir, 'codes.csv'), 'utf8'))) {
    students[row.id] = { ...row, cookie: await signIn(server, row.code), submissions: [] };
  }
  // Two correct submissions each, the students side by side, so that all are under a minute late.
  for (let round = 0; round < 2; round++) {
    const ids = await Promise.all(Object.values(students).map(submitGraded));
    Object.values(students).forEach((student, i) => student.submissions.push(ids[i]));
  }
}, bounded);
after(async () => {
  await browser?.close();
  await server?.stop();
}, bounded);

const contextWith = (cookie, size) => signedInContext(browser, server, cookie, size);
const open = (context, path) => openIn(context, server.url + path);

/** The student page's submissions table: { id: { Late, 'Counts as' } }. */
function submissionsTable(page) {
  return page.locator('#student-submissions').evaluate((table) => {
    const titles = [...table.querySelectorAll('thead th')].map((th) => th.textContent.trim());
    return Object.fromEntries([...table.querySelectorAll('tbody tr')].map((tr) => {
      const cells = [...tr.cells].map((td) => td.textContent.trim());
      return [tr.dataset.id, Object.fromEntries(titles.map((title, i) => [title, cells[i]]))];
    }));
  });
}

/** Nothing of the page is wider than the screen (the tables scroll inside their boxes). */
async function fitsTheScreen(page, size) {
  const width = await page.evaluate(() => document.documentElement.scrollWidth);
  assert.ok(width <= size.width, `the page is ${width} px wide on a ${size.width} px screen`);
}

for (const [name, size] of [['phone', phone], ['laptop', laptop]]) {
  test(`at a ${name}'s size: a waiver and an extension on the staff's student page re-judge the late submissions`, bounded, async () => {
    const student = students[name];
    const [first, second] = student.submissions;
    const link = estlab('course', 'staff', COURSE, `teacher-${name}@example.org`, '--role', 'instructor',
      '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
    const staffCookie = await signIn(server, link.split('#')[1]);
    const staff = await contextWith(staffCookie, size);
    const page = await open(staff, `/courses/${COURSE}/${LAB}/students/${name}`);

    // Seconds late, each charged a day begun.
    let rows = await submissionsTable(page);
    for (const id of [first, second]) {
      assert.match(rows[id].Late, /^\d{1,2} s late \(−10 %\)$/, `submission ${id}`);
      assert.equal(rows[id]['Counts as'], '90 %');
    }
    assert.match(await page.locator('#extension-covers').textContent(), /every submission of theirs, those already made included/);
    await fitsTheScreen(page, size);

    // The first's penalty waived, from its row's button.
    await page.locator(`#student-submissions tr[data-id="${first}"] button`, { hasText: 'Waive penalty' }).click();
    assert.equal(await page.locator('#waiver-submission').inputValue(), String(first));
    await page.locator('#waiver-reason').fill(REASON);
    await page.locator('#waiver-form button[type=submit]').click();
    await waitFor('the waiver', () => page.locator('#waiver-status').textContent(), (text) => text !== '', { timeout: 30_000 });
    assert.equal(await page.locator('#waiver-status').textContent(), `The late penalty of submission ${first} is waived.`);
    assert.deepEqual(await page.locator('#waiver-changes tbody td').allTextContents(), [String(first), '90 % (−10 %)', '100 % (−0 %)']);
    rows = await submissionsTable(page);
    assert.match(rows[first].Late, new RegExp(`^\\d{1,2} s late, penalty waived: ${REASON}$`));
    assert.equal(rows[first]['Counts as'], '100 %');
    // ... and the student sees it beside that submission.
    const own = await contextWith(student.cookie, size);
    let me = await open(own, '/me');
    const late = (id) => me.locator(`table.history tr[data-id="${id}"] td.late`).textContent();
    assert.match(await late(first), new RegExp(`^\\d{1,2} s late, penalty waived: ${REASON}$`));
    assert.match(await late(second), /^\d{1,2} s late \(−10 %\)$/);
    assert.equal(await me.locator('.facts .extension').count(), 0, 'no extension yet');
    await me.close();

    // An extension past both: the second, still penalised, is re-judged and listed.
    await page.locator('#extension-form input[name=due]').fill(fromNow(2 * 86_400));
    await page.locator('#extension-form button[type=submit]').click();
    await waitFor('the extension', () => page.locator('#extension-status').textContent(), (text) => text !== '', { timeout: 30_000 });
    assert.match(await page.locator('#extension-status').textContent(), /^Extension granted: due .*, taken until .*\. It changed 1 score\(s\):$/);
    assert.deepEqual(await page.locator('#extension-changes tbody td').allTextContents(), [String(second), '90 % (−10 %)', '100 % (−0 %)']);
    rows = await submissionsTable(page);
    assert.equal(rows[second].Late, 'on time');
    assert.equal(rows[second]['Counts as'], '100 %');
    assert.match(await page.locator('#student-facts').textContent(), /by an extension teacher-\w+@example\.org granted on/);
    assert.equal(await page.locator('#waiver-form').isHidden(), true, 'no penalty is left to waive');
    await fitsTheScreen(page, size);
    assert.deepEqual(page.problems, []);

    // The class view counts them in full, and the audit log lists both changes.
    const { body: view } = await api(staffCookie, `/api/courses/${COURSE}/labs/${LAB}/class`);
    assert.equal(view.students.find((s) => s.id === name).counting.final_score, 1);
    const { body: log } = await api(staffCookie, `/api/courses/${COURSE}/audit`);
    assert.ok(log.some((e) => e.action === 'waiver' && e.detail.endsWith(REASON)), JSON.stringify(log));
    assert.ok(log.some((e) => e.action === 'extension' && e.detail.includes(`re-judged submission ${second} 90 % → 100 %`)), JSON.stringify(log));
    await staff.close();

    // The student's /me: their dates, what they cover, both submissions on time by them.
    me = await open(own, '/me');
    assert.equal(await late(first), 'on time', 'the extension covers the waived one too');
    assert.equal(await late(second), 'on time');
    assert.match(await me.locator('.facts .extension').textContent(), /They cover every submission of yours to this exercise, those made before it included/);
    assert.equal(await me.locator('.counting .value').textContent(), '100 %');
    assert.match(await me.locator('.facts .standing').textContent(), /^due in 1 day 23 h$/);
    await fitsTheScreen(me, size);
    assert.deepEqual(me.problems, []);
    await own.close();
  });
}
