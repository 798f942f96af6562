// The report in headless Chromium against the real server: a student who submitted the
// reference solution opens their report, whose four runs the server made with their own
// code on the whole data sets (each drawn with its map, errors and covariance and its
// printout), writes an analysis (typeset as it is typed, kept across a reload), prints
// it to an A4 PDF (whose pages pdftoppm renders and the test reads) and hands it in; a
// teacher finds it in the class's list, reads it with its runs, sends one part back; the
// student revises and hands in again; the teacher accepts it, and the gradebook says the
// report is accepted and the lab passed.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, correct, estlab, getJson, launchBrowser, laptop, openIn, parseCsv, phone, setUpCourse, signedInContext,
  signIn, startServer, submit, tempDir, violations, waitFor,
} from './harness.mjs';

const LAB = 'ekf-localization';
const RUNS = ['o3/sequential', 'outliers/sequential', 'no-odometry/sequential', 'no-odometry/batch'];
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

/** Waits until the page has drawn the report's runs. */
async function runsDrawn(page) {
  await page.getByRole('status').filter({ hasText: /^The runs of submission \d+ on the whole data sets\.$/ }).waitFor({ timeout: 120_000 });
}

test('a report: four runs of the student\'s code, printed, handed in, judged', bounded, async () => {
  const course = 'report-class';
  const { students } = setUpCourse(server, { course, title: 'Report', prefix: 'p', count: 1, role: 'assistant' });
  const link = estlab('course', 'staff', course, 'teacher@report.example', '--role', 'instructor',
    '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
  const teacher = await signIn(server, link.split('#')[1]);
  const cookie = await signIn(server, students[0].code);
  const response = await submit(server, { lab: LAB, source: correct }, cookie);
  const accepted = await response.json();
  assert.equal(response.status, 202, JSON.stringify(accepted));
  const graded = await waitFor(`submission ${accepted.id}`,
    async () => (await getJson(server, `/api/submissions/${accepted.id}`, { cookie })).body,
    (s) => s.status === 'graded', { timeout: 120_000 });
  assert.equal(graded.score, 1);

  // The student's report: the four runs, each with its five figures and its printout.
  const context = await signedInContext(browser, server, cookie, laptop);
  const page = await openIn(context, `${server.url}/courses/${course}/${LAB}/report`);
  await runsDrawn(page);
  const runs = page.locator('.report-run');
  assert.equal(await runs.count(), 4);
  for (const [i, name] of RUNS.entries()) {
    const run = runs.nth(i);
    assert.equal(await run.locator('figure.plot').count(), 5, name);
    const printout = await run.locator('.printout').textContent();
    assert.match(printout, /mean absolute error/i, `${name}: ${printout}`);
    // The whole data set: the map's summary counts every step of the run.
    assert.match(await run.locator('figure[data-name=map] .plot-summary').textContent(), /over \d{3,} steps/);
  }
  assert.equal(await page.locator('.report-set').count(), 2);
  assert.deepEqual(await violations(page), [], 'the student\'s report');
  // At a phone's size, nothing is wider than the screen.
  const phoneContext = await signedInContext(browser, server, cookie, phone);
  const small = await openIn(phoneContext, `${server.url}/courses/${course}/${LAB}/report`);
  await runsDrawn(small);
  const overflow = await small.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  assert.ok(overflow <= 0, `the report is ${overflow} px wider than a phone`);
  await phoneContext.close();

  // An analysis, typeset as it is typed, saved, there after a reload.
  const analysis = 'The ellipses stay small: $\\Sigma_t$ shrinks with every reading of the 17 landmarks.';
  await page.getByLabel('Your analysis of “o3, sequential update”').fill(analysis);
  await runs.nth(0).locator('.analysis-text .katex').first().waitFor();
  await runs.nth(0).locator('.saved').filter({ hasText: /^Saved / }).waitFor();
  await page.reload();
  await page.waitForSelector('body[data-ready=true]');
  await runsDrawn(page);
  assert.equal(await page.getByLabel('Your analysis of “o3, sequential update”').inputValue(), analysis);

  // Printed to an A4 PDF: the cover with the facts, then a page or more per run; no
  // buttons or fields, the analysis typeset.
  const dir = tempDir();
  const pdf = join(dir, 'report.pdf');
  writeFileSync(pdf, await page.pdf({ format: 'A4', printBackground: true }));
  // ESTLAB_KEEP_REPORT_PDF=FILE keeps a copy to look at.
  if (process.env.ESTLAB_KEEP_REPORT_PDF) writeFileSync(process.env.ESTLAB_KEEP_REPORT_PDF, readFileSync(pdf));
  execFileSync('pdftoppm', ['-r', '50', '-png', pdf, join(dir, 'page')]);
  const pages = readdirSync(dir).filter((f) => f.startsWith('page') && f.endsWith('.png')).sort();
  assert.ok(pages.length >= 5 && pages.length <= 16, `${pages.length} pages`);
  for (const file of pages) {
    // A4 at 50 dpi: 8.27 inches wide (about 414 pixels), 297/210 as tall as wide (the
    // PNG's width and height are in its header).
    const png = readFileSync(join(dir, file));
    const [width, height] = [png.readUInt32BE(16), png.readUInt32BE(20)];
    assert.ok(Math.abs(width - 414) <= 1 && Math.abs(height / width - 297 / 210) < 0.01, `${file}: ${width} x ${height}`);
  }
  const text = execFileSync('pdftotext', ['-layout', pdf, '-'], { encoding: 'utf8' });
  assert.match(text, /Report of Student p001/);
  for (const title of ['o3, sequential update', 'Outliers, sequential update', 'No odometry, batch update']) assert.match(text, new RegExp(title));
  assert.match(text, /shrinks with every reading/);
  assert.ok(!/Print or save as PDF|Hand in the report|Your analysis of/.test(text), 'controls in the PDF');

  // Handed in: the fields are gone until staff send it back.
  page.once('dialog', (dialog) => dialog.accept());
  await page.getByRole('button', { name: 'Hand in the report' }).click();
  await page.getByRole('status').filter({ hasText: 'Your report is handed in.' }).waitFor();
  assert.equal(await page.locator('.analysis textarea').count(), 0);
  assert.deepEqual(page.problems, []);

  // The teacher: the class's list, the report with its runs, one part sent back.
  const staffContext = await signedInContext(browser, server, teacher, laptop);
  const staff = await openIn(staffContext, `${server.url}/courses/${course}/${LAB}/report`);
  assert.match(await staff.locator('.report-class').textContent(), /handed in, waiting for staff/);
  await staff.getByRole('link', { name: 'Student p001 (p001)' }).click();
  await staff.waitForSelector('body[data-ready=true]');
  await runsDrawn(staff);
  assert.equal(await staff.locator('.report-run figure.plot').count(), 20);
  const rubrics = staff.locator('fieldset.rubric');
  assert.equal(await rubrics.count(), 6);
  for (let i = 0; i < 6; i++) await rubrics.nth(i).getByLabel(i === 2 ? 'to be revised' : 'passes').check();
  await rubrics.nth(2).getByLabel(/^Comment/).fill('Say why the sequential update *diverges* here.');
  assert.deepEqual(await violations(staff), [], 'the teacher\'s report');
  await staff.getByRole('button', { name: 'Save the judgement' }).click();
  await staff.getByRole('status').filter({ hasText: /judgement is saved/ }).waitFor();
  assert.match(await staff.locator('.report-facts').textContent(), /to be revised/);

  // The student reads it, revises, hands in again; the teacher accepts.
  await page.reload();
  await page.waitForSelector('body[data-ready=true]');
  assert.match(await page.locator('.report-run').nth(2).locator('.part-mark.revise').textContent(), /diverges/);
  await page.getByLabel('Your analysis of “No odometry, sequential update”').fill('It linearises at a wrong heading and never recovers.');
  await page.locator('.report-run').nth(2).locator('.saved').filter({ hasText: /^Saved / }).waitFor();
  page.once('dialog', (dialog) => dialog.accept());
  await page.getByRole('button', { name: 'Hand in the revised report' }).click();
  await page.getByRole('status').filter({ hasText: 'Your report is handed in.' }).waitFor();
  await staff.reload();
  await staff.waitForSelector('body[data-ready=true]');
  await rubrics.nth(2).getByLabel('passes').check();
  await staff.getByRole('button', { name: 'Save the judgement' }).click();
  await staff.getByRole('status').filter({ hasText: /judgement is saved/ }).waitFor();
  assert.match(await staff.locator('.report-facts').textContent(), /Labpassed/);
  assert.deepEqual(staff.problems, []);
  await staffContext.close();
  await context.close();

  // The gradebook: the report accepted, the lab passed.
  const csv = await fetch(`${server.url}/api/courses/${course}/labs/${LAB}/export?format=csv`, { headers: { cookie: teacher } });
  assert.equal(csv.status, 200);
  const [row] = parseCsv(await csv.text());
  assert.equal(row.report_status, 'accepted');
  assert.equal(row.lab_passed, 'yes');
});
