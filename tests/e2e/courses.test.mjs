// A course in headless Chromium against the real server: the instructor's command line
// makes the course, imports a roster and opens the exercise; two students sign in with
// their links (each in a browser context of their own), submit from the workbench as
// themselves and see their own submissions only; an earlier submission opens read-only
// and loads into the editor; nobody signed in is told to sign in; after the cutoff a
// submission is refused and the file stays in the editor.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, correct, estlab, launchBrowser, openPage, savedFile as saved, starter, startServer, tempDir, typeInEditor as type,
  waitFor,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
/** The starter file: every function throws at once, so that it is graded quickly. */

let server;
let browser;
/** The course's options for the command line, once the server's address is known. */
let where;
/** The students of the roster, by id: { id, name, email, code, link }, and once signed in their page. */
const students = {};
/** The instructor's one-time sign-in link, as `estlab course create` prints it. */
let instructorLink;

before(async () => {
  server = await startServer();
  browser = await launchBrowser();
  where = ['--data', server.dataDir, '--url', server.url];
}, bounded);
after(async () => {
  for (const student of Object.values(students)) await student.page?.context().close();
  await browser.close();
  await server.stop();
}, bounded);

/** A moment `days` from now (negative: in the past), as the command line takes it. */
function fromNow(days) {
  return new Date(Date.now() + days * 86_400_000).toISOString().replace(/\.\d+Z$/, 'Z');
}

/** Goes to `path` on the server in `page` (keeping its context's cookies) and waits until the page is ready. */
async function visit(page, path) {
  await page.goto(server.url + path);
  await page.waitForSelector('body[data-ready=true]', { timeout: 60_000 });
}

/** The problems a page had, less the refusals the test asked for (Chromium logs every answer that is not 2xx). */
function unexpected(page, ...statuses) {
  const expected = statuses.map((status) => `console: Failed to load resource: the server responded with a status of ${status}`);
  return page.problems.filter((problem) => {
    const i = expected.findIndex((e) => problem.startsWith(e));
    if (i < 0) return true;
    expected.splice(i, 1);
    return false;
  });
}

test('without a course the workbench asks for a student id and says that anyone may submit', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  assert.equal(await page.locator('#student').isVisible(), true);
  assert.match(await page.locator('#who').textContent(), /This server runs no course: anyone may submit under any student id/);
  assert.match(await page.locator('#seed').textContent(), /^no id yet: the public variant, seed 1$/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the instructor makes the course; two students sign in with their links, submit as themselves and see only their own', bounded, async () => {
  const created = estlab('course', 'create', COURSE, '--title', 'Applied Estimation', ...where);
  instructorLink = created.trim().split('\n').pop();
  assert.match(instructorLink, new RegExp(`^${server.url}/signin#\\S+$`));
  const dir = tempDir();
  writeFileSync(join(dir, 'roster.csv'), 'id,name,email\ns1,Ada One,ada@example.org\ns2,Bo Two,bo@example.org\n');
  estlab('course', 'roster', COURSE, join(dir, 'roster.csv'), '--out', join(dir, 'codes.csv'), ...where);
  const [header, ...rows] = readFileSync(join(dir, 'codes.csv'), 'utf8').trim().split('\n').map((line) => line.split(','));
  assert.deepEqual(header, ['id', 'name', 'email', 'code', 'link']);
  for (const [id, name, email, code, link] of rows) students[id] = { id, name, email, code, link };
  estlab('course', 'assign', COURSE, LAB, '--due', fromNow(2), '--cutoff', fromNow(3), '--late-penalty', '10%/day', ...where);

  // Each signs in in a browser context of their own, from the link: the code is filled in.
  for (const student of Object.values(students)) {
    assert.ok(student.link.startsWith(`${server.url}/signin#`), student.link);
    const page = await openPage(browser, student.link);
    student.page = page;
    assert.equal(await page.locator('#code').inputValue(), student.code);
    assert.ok(!page.url().includes('#'), `the code is taken out of the address: ${page.url()}`);
    await page.locator('#sign-in').click();
    await page.waitForURL(`${server.url}/me`);
    await page.waitForSelector('body[data-ready=true]');
    assert.match(await page.locator('main').textContent(), new RegExp(`Signed in as ${student.name}`));
    assert.equal(await page.locator('.latest').getAttribute('data-submission'), null, 'nothing submitted yet');
  }

  // The workbench knows who they are: no id field, their name, course and deadline, their variant.
  const files = { s1: starter, s2: correct };
  for (const student of Object.values(students)) {
    const { page } = student;
    await visit(page, '/ekf/code');
    assert.equal(await page.locator('#student').isVisible(), false, 'no student id field');
    const who = await page.locator('#who').textContent();
    assert.match(who, new RegExp(`^Signed in as ${student.name} \\(${student.id}\\), ${COURSE}`));
    assert.match(who, /Due .*: \d+ days? \d+ h left\./);
    const me = await page.evaluate(() => fetch('/api/me').then((r) => r.json()));
    assert.equal(me.member.login, student.id);
    assert.equal(await page.locator('#seed').textContent(), `your own variant: seed ${me.seed}`);
    await type(page, files[student.id]);
  }

  // Both submit at once; each gets the server's score.
  await Promise.all(Object.values(students).map(async (student) => {
    await student.page.locator('#submit').click();
    await student.page.waitForSelector('#submission[data-status=graded]', { timeout: 180_000 });
  }));
  const s1 = await students.s1.page.locator('#submission .verdict').first().textContent();
  const s2 = await students.s2.page.locator('#submission .verdict').first().textContent();
  assert.match(s1, /^The server's grade for submission \d+: 0 of 110 points \(0%\)\./);
  assert.match(s2, /^The server's grade for submission \d+: 110 of 110 points \(100%\)\./);
  students.s1.submission = Number(s1.match(/submission (\d+)/)[1]);
  students.s2.submission = Number(s2.match(/submission (\d+)/)[1]);
  assert.notEqual(students.s1.submission, students.s2.submission);

  // Each one's page shows their own submission, with its result in full, and not the other's.
  for (const [student, other] of [[students.s1, students.s2], [students.s2, students.s1]]) {
    const { page } = student;
    await visit(page, '/me');
    const ids = await page.locator('table.history tbody tr').evaluateAll((rows) => rows.map((row) => Number(row.dataset.id)));
    assert.deepEqual(ids, [student.submission], `${student.id}'s history`);
    assert.equal(await page.locator(`[data-id="${other.submission}"], [data-submission="${other.submission}"]`).count(), 0);
    assert.equal(Number(await page.locator('.latest').getAttribute('data-submission')), student.submission);
    const latest = page.locator('.latest .submission[data-status=graded]');
    await latest.waitFor({ timeout: 60_000 });
    assert.match(await latest.locator('.verdict').textContent(), new RegExp(`^The server's grade for submission ${student.submission}: `));
    assert.equal(await latest.locator('.server-tests .test').count(), 11, 'every test of the server\'s result');
    const answers = await page.evaluate(async ([own, theirs]) => {
      const mine = await fetch(`/api/submissions/${own}`);
      const other = await fetch(`/api/submissions/${theirs}`);
      return { mine: mine.status, source: (await mine.json()).source, other: other.status };
    }, [student.submission, other.submission]);
    assert.equal(answers.mine, 200);
    assert.equal(answers.source, files[student.id]);
    assert.equal(answers.other, 404, `${student.id} cannot read ${other.id}'s submission`);
  }
});

test('an earlier submission opens read-only from the student\'s page, and loads into the editor after asking', bounded, async () => {
  const { page, submission } = students.s1;
  await visit(page, '/ekf/code');
  await type(page, '// a fresh start\n');
  assert.equal(await saved(page), '// a fresh start\n');

  await visit(page, '/me');
  await page.locator(`table.history tr[data-id="${submission}"] a.open`).click();
  await page.waitForURL(`${server.url}/ekf/code?submission=${submission}`);
  await page.waitForSelector('body[data-ready=true]');
  assert.equal(await page.locator('#viewer').isVisible(), true);
  assert.equal(await page.locator('#workbench').isVisible(), false);
  assert.equal(await page.locator('#viewer-title').textContent(), `Submission ${submission}`);
  const code = page.locator('#viewer-source .cm-content');
  assert.match(await code.textContent(), /EKF localization \(EL2320 Lab 1\): your implementation\./);
  assert.equal(await code.getAttribute('contenteditable'), 'false', 'read-only');
  assert.ok(await page.locator('#viewer-source .cm-line span[class]').count() > 0, 'highlighted');
  assert.match(await page.locator('#viewer-result .verdict').textContent(),
    new RegExp(`^The server's grade for submission ${submission}: 0 of 110 points`));

  let asked = null;
  page.once('dialog', (dialog) => { asked = dialog.message(); dialog.dismiss(); });
  await page.locator('#load-submission').click();
  assert.match(asked, new RegExp(`Replace the file in your editor with submission ${submission}\\?`));
  assert.equal(await saved(page), '// a fresh start\n', 'dismissing keeps the file');
  assert.equal(await page.locator('#viewer').isVisible(), true);

  page.once('dialog', (dialog) => dialog.accept());
  await page.locator('#load-submission').click();
  await page.waitForSelector('#workbench:not([hidden])');
  assert.equal(await page.locator('#viewer').isVisible(), false);
  assert.equal(new URL(page.url()).search, '', 'back at the editor\'s address');
  assert.equal(await saved(page), starter, 'the submission is in the editor, saved');
  assert.match(await page.locator('#saved').textContent(), new RegExp(`Submission ${submission} is in the editor`));

  // A submission that is not theirs, or that does not exist: none of theirs.
  await visit(page, `/ekf/code?submission=${students.s2.submission}`);
  assert.equal(await page.locator('#viewer-error').textContent(), `There is no such submission of yours (${students.s2.submission}).`);
  assert.equal(await page.locator('#viewer-panes').isVisible(), false);
  await page.locator('#back-to-editor').click();
  await page.waitForSelector('#workbench:not([hidden])');
  assert.equal(await saved(page), starter);
  assert.deepEqual(unexpected(page, 404, 404), []);
});

test('nobody signed in: the workbench says to sign in, and Submit refuses with a link to sign in, the file untouched', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  assert.equal(await page.locator('#student').isVisible(), false);
  assert.equal(await page.locator('#who a').getAttribute('href'), '/signin');
  assert.match(await page.locator('#seed').textContent(), /^the public variant, seed 1$/);
  await type(page, '// not signed in\n');
  await page.locator('#submit').click();
  const refusal = page.locator('#submission[data-status=refused]');
  await refusal.waitFor();
  assert.match(await refusal.textContent(), /^Not submitted: sign in to submit/);
  assert.equal(await refusal.locator('a').getAttribute('href'), '/signin');
  assert.equal(await saved(page), '// not signed in\n');
  assert.deepEqual(unexpected(page, 401), []);
  await page.close();
});

test('staff: the workbench says staff do not submit, Submit is refused with the server\'s reason, and a student\'s submission opens', bounded, async () => {
  const page = await openPage(browser, instructorLink);
  await page.locator('#sign-in').click();
  await page.waitForURL(`${server.url}/me`);
  await visit(page, `/ekf/code?submission=${students.s2.submission}`);
  assert.match(await page.locator('#viewer-facts').textContent(), /^Submitted by s2 /);
  assert.equal(await page.locator('#load-submission').isVisible(), true);
  await page.locator('#back-to-editor').click();
  await page.waitForSelector('#workbench:not([hidden])');
  assert.match(await page.locator('#who').textContent(), /\(instructor of el2320\): staff do not submit\./);
  assert.equal(await page.locator('#student').isVisible(), false);
  await type(page, '// staff\n');
  await page.locator('#submit').click();
  const refusal = page.locator('#submission[data-status=refused]');
  await refusal.waitFor();
  assert.match(await refusal.textContent(), /^Not submitted: you are signed in as instructor of el2320: staff do not submit/);
  assert.equal(await saved(page), '// staff\n');
  assert.deepEqual(unexpected(page, 403), []);
  await page.context().close();
});

test('after the cutoff a submission is refused with the server\'s reason, and the file stays in the editor', bounded, async () => {
  const { page } = students.s2;
  await visit(page, '/ekf/code');
  assert.equal(await saved(page), correct);
  assert.match(await page.locator('#who').textContent(), /left\./);
  estlab('course', 'assign', COURSE, LAB, '--due', '2020-01-01T00:00Z', '--cutoff', '2020-01-01T00:00Z', ...where);
  await page.locator('#submit').click();
  const refusal = page.locator('#submission[data-status=refused]');
  await refusal.waitFor();
  assert.match(await refusal.textContent(), /^Not submitted: .*cutoff/);
  assert.equal(await saved(page), correct, 'the file is untouched');
  // The page asks the server again: the exercise is closed.
  await waitFor('the deadline to read closed', () => page.locator('#who').textContent(), (text) => /closed/.test(text), { timeout: 10_000 });
  assert.deepEqual(unexpected(page, 404, 403), []);
  assert.deepEqual(unexpected(students.s1.page, 404, 404), []);
});
