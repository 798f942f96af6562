// The written questions in headless Chromium against the real server: a student finds
// them from /me, answers in words with math (typeset as they type), a choice, a number and
// a table, each saved a moment after they stop; the answers are there after a reload and
// nothing of the answer keys reaches the student's page; staff read the sets with the
// model answers and the keys, the fields read only; at a phone's size nothing spills over.
// A round of peer review: the teacher gives the assignment a set of their own from a file
// (a broken one is refused with its set, line, question and field), opens a round on the
// same page, each student marks the two sheets handed to them and hands the reviews in,
// the teacher closes it, each student reads their share of right marks and the gradebook
// has every student's share and bonus (axe-core finds no serious violation on a sheet,
// the rounds or the marks).
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import {
  bounded, estlab, launchBrowser, laptop, openIn, parseCsv, phone, setUpCourse, signedInContext, signIn, startServer, violations,
} from './harness.mjs';

const LAB = 'ekf-localization';

/** A question set of the teacher's own, for a review in class. */
const IN_CLASS = `title = "In class: the gain"

[[question]]
id = "roles"
kind = "text"
prompt = "What does the state $x_t$ hold?"
model = "The pose $(x, y, \\theta)$."

[[question]]
id = "weighing"
kind = "text"
prompt = "What decides how much a measurement moves the estimate?"
model = "The Kalman gain $K_t$."
`;
let server;
let browser;
before(async () => {
  server = await startServer();
  browser = await launchBrowser();
}, bounded);
after(async () => {
  await browser?.close();
  await server?.stop();
}, bounded);

/** Waits until the question `id` of set `part` says it is saved. */
async function saved(page, part, id) {
  await page.locator(`#q-${part}-${id} .saved`).filter({ hasText: /^Saved / }).waitFor({ timeout: 30_000 });
}

test('a student answers, the answers stay, staff read the keys', bounded, async () => {
  const { students } = setUpCourse(server, { title: 'Written', prefix: 'w', count: 1, role: 'assistant' });
  const student = await signIn(server, students[0].code);
  const link = estlab('course', 'staff', 'el2320', 'teacher@example.org', '--role', 'instructor',
    '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
  const teacher = await signIn(server, link.split('#')[1]);

  const context = await signedInContext(browser, server, student, laptop);
  const me = await openIn(context, `${server.url}/me`);
  await me.getByRole('link', { name: 'answer the written questions' }).click();
  await me.waitForSelector('body[data-ready=true]');
  assert.equal(new URL(me.url()).pathname, `/courses/el2320/${LAB}/questions`);
  const page = me;
  assert.equal(await page.locator('.question-set h2').count(), 2);
  assert.equal(await page.locator('#set-0 ~ .question').count(), 15);

  // Words with math, typeset beside the field as they are typed.
  const roles = page.getByLabel('Your answer to question 1 (Markdown, $…$ for math)').first();
  await roles.fill('The state $x_t = (x, y, \\theta)$ is what the filter estimates.');
  await page.locator('#q-0-roles .preview .katex').first().waitFor();
  await saved(page, 0, 'roles');
  // A choice, a number with its unit field, a table.
  await page.locator('#q-0-map-mle input[type=radio]').first().check();
  await saved(page, 0, 'map-mle');
  await page.locator('#q-1-gate-value input').fill('13.82');
  await saved(page, 1, 'gate-value');
  await page.locator('#q-1-batch-dimensions input').first().fill('2n x 1');
  await saved(page, 1, 'batch-dimensions');
  // Nothing of what answers are checked against, nor a model answer.
  const text = await page.locator('#question-sets').textContent();
  assert.ok(!text.includes('Model answer') && !text.includes('Checked against'), 'a key on the student\'s page');
  assert.equal(await page.locator('.key').count(), 0);

  // After a reload, every answer is there.
  await page.reload();
  await page.waitForSelector('body[data-ready=true]');
  assert.equal(await page.locator('#q-0-roles textarea').inputValue(), 'The state $x_t = (x, y, \\theta)$ is what the filter estimates.');
  assert.ok(await page.locator('#q-0-map-mle input[type=radio]').first().isChecked());
  assert.equal(await page.locator('#q-1-gate-value input').inputValue(), '13.82');
  assert.equal(await page.locator('#q-1-batch-dimensions input').first().inputValue(), '2n x 1');
  assert.deepEqual(page.problems, []);

  // A wrong number is saved as typed (it is checked later, not refused).
  await page.locator('#q-1-gate-value input').fill('about 14');
  await saved(page, 1, 'gate-value');

  // At a phone's size, nothing is wider than the screen.
  const phoneContext = await signedInContext(browser, server, student, phone);
  const small = await openIn(phoneContext, `${server.url}/courses/el2320/${LAB}/questions`);
  const overflow = await small.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  assert.ok(overflow <= 0, `the page is ${overflow} px wider than a phone`);
  await phoneContext.close();

  // Staff read the keys and the model answers, and answer nothing.
  const staffContext = await signedInContext(browser, server, teacher, laptop);
  const staff = await openIn(staffContext, `${server.url}/courses/el2320/${LAB}/questions`);
  assert.match(await staff.locator('#q-1-gate-value .key').textContent(), /Checked against 13\.8155 ± 0\.01/);
  assert.match(await staff.locator('#q-0-map-mle .key').textContent(), /Checked against option 1/);
  assert.ok(await staff.locator('#q-0-roles .key .model .katex').count() > 0, 'the model answer typeset');
  const fields = staff.locator('#question-sets textarea, #question-sets input');
  assert.ok(await fields.count() > 0);
  assert.deepEqual(new Set(await fields.evaluateAll((all) => all.map((f) => f.disabled))), new Set([true]));
  assert.deepEqual(staff.problems, []);
  await staffContext.close();
  await context.close();
});

test('a review round in class: opened, reviewed, closed, marks read', bounded, async () => {
  const course = 'review-class';
  const { students } = setUpCourse(server, { course, title: 'Review', prefix: 'r', count: 3, role: 'assistant' });
  const link = estlab('course', 'staff', course, 'teacher@review.example', '--role', 'instructor',
    '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
  const teacher = await signIn(server, link.split('#')[1]);
  const api = `${server.url}/api/courses/${course}/labs/${LAB}`;

  // The teacher gives the assignment a set of their own from a file; one that does not
  // read is refused with its line, and nothing changes.
  const staffContext = await signedInContext(browser, server, teacher, laptop);
  const staff = await openIn(staffContext, `${server.url}/courses/${course}/${LAB}/questions`);
  const files = staff.getByLabel('Load .toml files');
  await files.setInputFiles({ name: 'broken.toml', mimeType: 'text/plain', buffer: Buffer.from('title = "x"\n[[question]]\nkind = "essay"\nprompt = "?"\n') });
  await staff.getByRole('button', { name: 'Save the sets' }).click();
  await staff.getByRole('status').filter({ hasText: /^Not saved: .*set 1: line 2: question 1: kind "essay"/ }).waitFor();
  staff.problems.length = 0; // the browser logs the refusal (400) it was meant to get
  await files.setInputFiles({ name: 'in-class.toml', mimeType: 'text/plain', buffer: Buffer.from(IN_CLASS) });
  await staff.getByRole('button', { name: 'Save the sets' }).click();
  await staff.getByRole('status').filter({ hasText: 'Saved: 1 set.' }).waitFor();
  assert.deepEqual(await staff.locator('.question-set h2').allTextContents(), ['In class: the gain']);
  const cookies = [];
  for (const [i, student] of students.entries()) {
    const cookie = await signIn(server, student.code);
    cookies.push(cookie);
    for (const question of ['roles', 'weighing']) {
      const response = await fetch(`${api}/answers`, {
        method: 'POST',
        headers: { cookie, 'content-type': 'application/json', origin: server.url },
        body: JSON.stringify({ part: 0, question, answer: { kind: 'text', value: `Answer ${i} to ${question}: $K_t$` } }),
      });
      assert.equal(response.status, 200, await response.text());
    }
  }

  // The teacher opens a round of the set, two reviews a sheet.
  await staff.reload();
  await staff.waitForSelector('body[data-ready=true]');
  await staff.getByLabel('Reviews of each sheet').fill('2');
  await staff.getByRole('button', { name: 'Open a round' }).click();
  await staff.getByRole('status').filter({ hasText: /Round \d+ is open: 3 sheets/ }).waitFor();
  // The status is said once the round's table is drawn: its rows are there.
  assert.equal(await staff.locator('.round-table tr[data-student]').count(), 3);

  // Each student reviews their two sheets: the first answer right, the second wrong.
  for (const cookie of cookies) {
    const context = await signedInContext(browser, server, cookie, laptop);
    const page = await openIn(context, `${server.url}/courses/${course}/${LAB}/questions`);
    assert.ok(!(await page.locator('#peer-review').isHidden()));
    for (const number of [1, 2]) {
      await page.getByRole('button', { name: `Review sheet ${number}` }).click();
      const sheet = page.locator('.review-sheet');
      await sheet.locator('.given .katex').first().waitFor();
      await sheet.getByLabel('Right').first().check();
      await sheet.getByLabel('Wrong').nth(1).check();
      await sheet.getByLabel(/^Your comment on question/).nth(1).fill('the gain decides');
      if (number === 1) assert.deepEqual(await violations(page), [], 'a sheet to mark');
      await sheet.getByRole('button', { name: 'Hand in the review' }).click();
      await page.getByRole('button', { name: `Read sheet ${number}` }).waitFor();
    }
    assert.deepEqual(page.problems, []);
    await context.close();
  }

  // The teacher sees every review handed in and closes the round.
  await staff.reload();
  await staff.waitForSelector('body[data-ready=true]');
  await staff.locator('.round p').filter({ hasText: '6 of 6 reviews handed in' }).waitFor();
  await staff.getByRole('button', { name: /^Close round/ }).click();
  await staff.locator('.round h3').filter({ hasText: '(closed)' }).waitFor();
  const shares = await staff.locator('.round-table tr[data-student] td:nth-child(4)').allTextContents();
  assert.deepEqual(shares, ['50 %', '50 %', '50 %']);
  assert.deepEqual(await violations(staff), [], 'the staff\'s rounds');
  assert.deepEqual(staff.problems, []);
  await staffContext.close();

  // The gradebook has each student's share and bonus of the set's review.
  const csv = await fetch(`${api}/export?format=csv`, { headers: { cookie: teacher } });
  assert.equal(csv.status, 200);
  const rows = parseCsv(await csv.text());
  assert.deepEqual(rows.map((r) => [r.review_share_1, r.review_bonus_1]), [['0.5000', 'yes'], ['0.5000', 'yes'], ['0.5000', 'yes']]);

  // A student reads what their sheet received.
  const context = await signedInContext(browser, server, cookies[0], laptop);
  const page = await openIn(context, `${server.url}/courses/${course}/${LAB}/questions`);
  assert.match(await page.locator('.received .tally').textContent(), /2 of 4 marks right, 50 %: the bonus is yours/);
  assert.match(await page.locator('.received .marks').textContent(), /the gain decides/);
  assert.deepEqual(await violations(page), [], 'the marks received');
  await context.close();
});
