// The class view acting on a selection, in headless Chromium at a phone's size and a
// laptop's: the table follows a grading that finishes while it is open (no click on
// Refresh), the instructor selects two students by their boxes, grants them an
// extension at once (only they get it, at the moment meant in the instructor's zone)
// and regrades their submissions only; the selection survives the table's redrawing.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import {
  bounded, classTable, estlab, getJson, laptop, openIn, phone, setUpCourse, signIn, signedInContext, starter, submit,
  waitFor, withServerAndBrowser,
} from './harness.mjs';

let server;
let browser;
withServerAndBrowser((s, b) => { server = s; browser = b; });

const LAB = 'ekf-localization';

/** Submits `source` as the student signed in with `cookie`; the submission's id. */
async function submitAs(cookie, source) {
  const response = await submit(server, { source }, cookie);
  const body = await response.json();
  assert.equal(response.status, 202, JSON.stringify(body));
  return body.id;
}

for (const [name, size] of [['phone', phone], ['laptop', laptop]]) {
  test(`at a ${name}'s size: the class table follows gradings, and a selection is extended and regraded at once`, bounded, async () => {
    const course = `bulk-${name}`;
    const { students } = setUpCourse(server, { course, title: `Bulk (${name})`, prefix: `${name[0]}`, count: 3, role: 'assistant' });
    const link = estlab('course', 'staff', course, `teacher@${name}.example`, '--role', 'instructor',
      '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
    const teacher = await signIn(server, link.split('#')[1]);
    const cookies = await Promise.all(students.map((s) => signIn(server, s.code)));
    // Two students have a graded submission before the page opens.
    for (const i of [0, 1]) {
      const id = await submitAs(cookies[i], starter);
      await waitFor(`submission ${id}`, async () => (await getJson(server, `/api/submissions/${id}`, { cookie: cookies[i] })).body,
        (s) => s.status === 'graded', { timeout: 120_000 });
    }

    const context = await signedInContext(browser, server, teacher, size, { timezoneId: 'Europe/Stockholm', locale: 'en-GB' });
    const page = await openIn(context, `${server.url}/courses/${course}/${LAB}`);
    const [a, b, c] = students.map((s) => s.id);
    let rows = await classTable(page);
    assert.equal(rows[c].Submissions, '0');

    // The selection: a and c, kept while the table redraws.
    await page.locator(`#class-table tr[data-student="${a}"] input.pick`).check();
    await page.locator(`#class-table tr[data-student="${c}"] input.pick`).check();
    assert.equal(await page.locator('#bulk-count').textContent(), `2 students selected: ${a}, ${c}.`);

    // c submits while the page is open: the table shows it without a click on Refresh.
    const late = await submitAs(cookies[2], starter);
    rows = await waitFor('the class table to show c\'s submission', () => classTable(page),
      (shown) => shown[c]?.Submissions === '1' && shown[c]?.['Latest score'] !== '–', { timeout: 90_000, interval: 500 });
    assert.ok(late > 0);
    assert.ok(await page.locator(`#class-table tr[data-student="${c}"] input.pick`).isChecked(), 'still selected');

    // An extension for the two selected, in the instructor's zone.
    await page.locator('#bulk-due').fill('2031-02-01T12:00');
    await page.locator('#bulk-cutoff').fill('2031-02-03T12:00');
    await page.locator('#bulk-extension button[type=submit]').click();
    await page.waitForFunction(() => /^Extended /.test(document.querySelector('#bulk-status').textContent), null, { timeout: 60_000 });
    assert.match(await page.locator('#bulk-status').textContent(), /^Extended 2 of 2: due 1 Feb 2031, 12:00 CET, taken until 3 Feb 2031, 12:00 CET; 0 score\(s\)/);
    const extended = async (id) => (await getJson(server, `/api/courses/${course}/labs/${LAB}/students/${id}`, { cookie: teacher })).body.extension;
    assert.equal((await extended(a)).due, '2031-02-01T11:00:00Z');
    assert.equal((await extended(c)).cutoff, '2031-02-03T11:00:00Z');
    assert.equal(await extended(b), null, 'b was not selected');

    // A regrade of the selected only.
    await page.locator('#bulk-regrade').click();
    await page.waitForFunction(() => /^Regrade done/.test(document.querySelector('#bulk-status').textContent), null, { timeout: 120_000 });
    const audit = (await getJson(server, `/api/courses/${course}/audit`, { cookie: teacher })).body;
    const regrade = audit.find((entry) => entry.action === 'regrade');
    assert.match(regrade.detail, new RegExp(`^every submission of ${a}, ${c} of ${LAB}: 2 submission\\(s\\)`));
    assert.equal(audit.filter((entry) => entry.action === 'extension').length, 2);

    const width = await page.evaluate(() => document.documentElement.scrollWidth);
    assert.ok(width <= size.width, `the page is ${width} px wide on a ${size.width} px screen`);
    assert.deepEqual(page.problems, []);
    await context.close();
  });
}
