// The course set up in the browser by its instructor, at a phone's size and a laptop's,
// in Stockholm's time zone: only the course is created on the command line. On the
// course's page the instructor opens an exercise with its dates (stored as the moment
// meant in their zone, shown with the zone), previews a roster (a duplicate id is named
// by its line; a good file changes nothing until imported), imports it and downloads the
// codes file (its codes sign in), gives one student a new code (the old one stops
// working), adds an assistant (their one-time link signs in, and they read the page
// without its forms), makes an API token and revokes it; the staff's actions list each.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import {
  bounded, estlab, getJson, laptop, openIn, parseCsv, phone, signedInContext, withServerAndBrowser,
} from './harness.mjs';

let server;
let browser;
withServerAndBrowser((s, b) => { server = s; browser = b; });

const ZONE = 'Europe/Stockholm';

/** Signs in with `code` as the sign-in form does; true when it let the person in. */
async function signsIn(code) {
  const response = await fetch(`${server.url}/signin`, {
    method: 'POST',
    headers: { 'content-type': 'application/x-www-form-urlencoded' },
    body: new URLSearchParams({ code }),
    redirect: 'manual',
  });
  return response.status === 303 ? response.headers.getSetCookie().find((c) => c.startsWith('estlab_session=')).split(';')[0] : null;
}

/** A browser context of `size` in Stockholm, signed in with `cookie`. */
const contextWith = (cookie, size) => signedInContext(browser, server, cookie, size, { timezoneId: ZONE, locale: 'en-GB' });
const open = (context, path) => openIn(context, server.url + path);

/** Waits for a status line to say something other than "Working…", and returns it. */
async function statusOf(page, id) {
  const line = page.locator(`#${id}`);
  await page.waitForFunction((el) => el.textContent !== '' && el.textContent !== 'Working…', await line.elementHandle(), { timeout: 60_000 });
  return line.textContent();
}

/** Clicks `button` and reads the codes file the page downloads. */
async function codesFrom(page, button) {
  const [download] = await Promise.all([page.waitForEvent('download', { timeout: 60_000 }), button.click()]);
  return { name: download.suggestedFilename(), rows: parseCsv(readFileSync(await download.path(), 'utf8')) };
}

async function fitsTheScreen(page, size) {
  const width = await page.evaluate(() => document.documentElement.scrollWidth);
  assert.ok(width <= size.width, `the page is ${width} px wide on a ${size.width} px screen`);
}

for (const [name, size] of [['phone', phone], ['laptop', laptop]]) {
  test(`at a ${name}'s size: an instructor sets the course up on its page`, bounded, async () => {
    const course = `c-${name}`;
    const created = estlab('course', 'create', course, '--title', `Applied Estimation (${name})`,
      '--instructor', `teacher-${name}@example.org`, '--data', server.dataDir, '--url', server.url);
    const teacher = await signsIn(created.trim().split('\n').pop().split('#')[1]);
    assert.ok(teacher, 'the instructor signs in');
    const context = await contextWith(teacher, size);
    const page = await open(context, `/courses/${course}`);
    assert.equal(await page.locator('#course-title').textContent(), `Applied Estimation (${name}) (${course})`);
    assert.ok(await page.locator('#assign-form').isVisible());

    // An exercise opened with its dates, in the instructor's zone.
    assert.match(await page.locator('#assign-zone').textContent(), /Europe\/Stockholm/);
    await page.locator('#assign-lab').selectOption('odometry');
    await page.locator('#assign-due').fill('2030-01-15T23:59');
    await page.locator('#assign-cutoff').fill('2030-01-18T23:59');
    await page.locator('#assign-penalty').fill('101');
    await page.locator('#assign-form button[type=submit]').click();
    assert.match(await statusOf(page, 'assign-status'), /Late penalty: a share between 0 and 100 % per day/);
    await page.locator('#assign-penalty').fill('10');
    await page.evaluate(() => { document.getElementById('assign-status').textContent = ''; });
    await page.locator('#assign-form button[type=submit]').click();
    assert.match(await statusOf(page, 'assign-status'), /^Odometry and its error propagation is open: due 15 Jan 2030, 23:59 CET/);
    const stored = (await getJson(server, `/api/courses/${course}`, { cookie: teacher })).body;
    assert.deepEqual(stored.assignments.map((a) => [a.lab, a.due, a.cutoff, a.penalty_per_day]),
      [['odometry', '2030-01-15T22:59:00Z', '2030-01-18T22:59:00Z', 0.1]]);
    assert.match(await page.locator('#assignments tbody').textContent(), /15 Jan 2030, 23:59 CET/);

    // The roster: a bad file named by its line, a good one previewed, then imported.
    const roster = (text) => ({ name: 'roster.csv', mimeType: 'text/csv', buffer: Buffer.from(text) });
    await page.locator('#roster-file').setInputFiles(roster('id,name,email\ns1,Sam,s1@example.org\ns1,Sam again,s1b@example.org\n'));
    await page.locator('#roster-form button[type=submit]').click();
    assert.match(await statusOf(page, 'roster-status'), /^roster\.csv: line 3: the id "s1" appears a second time/);
    await page.locator('#roster-file').setInputFiles(roster('id,name,email\ns1,Sam Ström,s1@example.org\ns2,Björn Berg,s2@example.org\n'));
    await page.evaluate(() => { document.getElementById('roster-status').textContent = ''; });
    await page.locator('#roster-form button[type=submit]').click();
    assert.equal(await statusOf(page, 'roster-status'), 'Check the changes below, then import them.');
    assert.match(await page.locator('#roster-plan').textContent(), /New: 2.*s1: Sam Ström.*s2: Björn Berg/s);
    assert.match(await page.locator('#roster-facts').textContent(), /No student yet/, 'the preview changed nothing');
    const imported = await codesFrom(page, page.locator('#roster-apply'));
    assert.match(imported.name, new RegExp(`^${course}-codes-\\d{8}T\\d{6}Z\\.csv$`));
    assert.deepEqual(imported.rows.map((r) => [r.id, r.name]), [['s1', 'Sam Ström'], ['s2', 'Björn Berg']]);
    assert.match(await statusOf(page, 'roster-status'), /^Imported roster\.csv: 2 students; 2 new/);
    assert.match(await page.locator('#roster-facts').textContent(), /^2 on the roster/);
    assert.ok(await signsIn(imported.rows[1].code), "s2's code signs in");

    // A new code for s1: the old one stops working.
    await page.locator('#students input[value=s1]').check();
    const reissued = await codesFrom(page, page.locator('#reissue-button'));
    assert.deepEqual(reissued.rows.map((r) => r.id), ['s1']);
    assert.equal(await signsIn(imported.rows[0].code), null, 'the old code is over');
    assert.ok(await signsIn(reissued.rows[0].code), 'the new code signs in');

    // An assistant, whose one-time link signs in; they read the page without its forms.
    await page.locator('#staff-email').fill(`ta-${name}@example.org`);
    await page.locator('#staff-name').fill('Tove Assistant');
    await page.locator('#staff-role').selectOption('assistant');
    await page.locator('#staff-form button[type=submit]').click();
    assert.equal(await statusOf(page, 'staff-status'), `ta-${name}@example.org is assistant of ${course}.`);
    const staffLink = await page.locator('#staff-link-text').inputValue();
    assert.ok(staffLink.startsWith(`${server.url}/signin#`), staffLink);
    const assistant = await signsIn(staffLink.split('#')[1]);
    assert.ok(assistant, 'the link signs the assistant in');
    assert.match(await page.locator('#staff tbody').textContent(), /Tove Assistant/);
    const theirs = await open(await contextWith(assistant, size), `/courses/${course}`);
    assert.ok(await theirs.locator('#read-only').isVisible());
    for (const form of ['#assign-form', '#roster-form', '#staff-form', '#token-form']) {
      assert.equal(await theirs.locator(form).isVisible(), false, `${form} is hidden from an assistant`);
    }
    assert.match(await theirs.locator('#students tbody').textContent(), /Björn Berg/);
    assert.deepEqual(theirs.problems, []);

    // A token, which works until revoked.
    await page.locator('#token-role').selectOption('assistant');
    await page.locator('#token-form button[type=submit]').click();
    assert.match(await statusOf(page, 'token-status'), /^Token \d+ is made\.$/);
    const token = await page.locator('#token-text').inputValue();
    const asToken = () => getJson(server, `/api/courses/${course}`, { authorization: `Bearer ${token}` });
    assert.equal((await asToken()).status, 200);
    await page.evaluate(() => { document.getElementById('token-status').textContent = ''; });
    await page.locator('#tokens button', { hasText: 'Revoke' }).click();
    assert.match(await statusOf(page, 'token-status'), /is revoked/);
    assert.equal((await asToken()).status, 401);

    // Every change in the staff's actions, by the instructor.
    const log = await page.locator('#course-audit tbody').textContent();
    for (const action of ['assign', 'roster', 'staff', 'token']) assert.match(log, new RegExp(action));
    assert.match(log, new RegExp(`teacher-${name}@example\\.org`));
    await fitsTheScreen(page, size);
    // The bad roster's 400 is logged by Chromium as a resource that failed; nothing else.
    assert.deepEqual(page.problems.filter((p) => !p.includes('status of 400 (Bad Request)')), []);
    await context.close();
  });
}
