// The sensor-fusion workbench (/fusion/code) in headless Chromium against the real
// server: it fits a phone and a laptop; the starter file fails every test as not
// implemented; the correct file scores full marks in the browser and through the server,
// and each trial is drawn, the student's path over the reference filter's; a classic
// mistake fails its function's test with its hint, and the trial it spoils shows where
// the student's belief departs from the reference's.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, browserPoints, checkStarterFails, checkWorkbenchFits, gradeOnCommandLine, openPage, plottedPoints, root, runAndWait,
  savedFile, starterOf, testStatus, typeInEditor as type, waitForSubmission, withServerAndBrowser,
} from './harness.mjs';

const LAB = 'sensor-fusion';
const correct = readFileSync(join(root, 'tests', 'student', 'sensor_fusion', 'correct.js'), 'utf8');
const starter = readFileSync(starterOf('sensor_fusion'), 'utf8');
const FUNCTIONS = ['combine_platforms', 'heading_sigma', 'measurement_noise', 'in_field_of_view', 'predict', 'mahalanobis', 'update'];
const TRIALS = ['busy-room', 'wide-tour'];
/** correct.js with the heading's innovation not wrapped in `update` (`mahalanobis` still wraps it). */
const unwrappedUpdate = (() => {
  const from = 'function update(mu_bar, sigma_bar, z, Q) {\n  const nu = innovation(mu_bar, z);';
  assert.ok(correct.includes(from));
  return correct.replace(from, 'function update(mu_bar, sigma_bar, z, Q) {\n  const nu = z.map((v, i) => v - mu_bar[i]);');
})();

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** `estlab grade --lab sensor-fusion` of `text` for the variant `seed`, as JSON. */
const cliGrade = (text, seed) => gradeOnCommandLine(LAB, 'sensor_fusion.js', text, seed);
/** How many points each series of the trial plot holds, by the series' id. */
const plotted = (page) => plottedPoints(page, 'trial');

/** Shows the trial `name` in the runs' section, once its view is drawn. */
async function showTrial(page, name) {
  await page.locator('#run-choice').selectOption(name);
  await page.waitForFunction((n) => document.querySelector('figure[data-name="trial"] .plot-summary').textContent.startsWith(`The ${n} trial`), name);
}

/** The rows of the table of the step shown: [label, yours, the reference's]. */
function tableRows(page) {
  return page.locator('#trial-table tbody tr').evaluateAll((trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
}

test('the workbench fits a phone and a laptop, without errors, and speaks of sensor fusion', bounded, () => checkWorkbenchFits(browser, server, {
  path: '/fusion/code', heading: 'Your sensor fusion', runButton: 'Run trials', functions: FUNCTIONS, experiments: '/fusion', nav: 'Your fusion code',
}));

test('the starter file fails every test with "not implemented", the trials too, and draws no trial', bounded, async () => {
  const page = await openPage(browser, `${server.url}/fusion/code`);
  assert.equal(await savedFile(page, LAB), null, 'nothing saved yet: the editor holds the starter');
  await checkStarterFails(page, starter, FUNCTIONS, TRIALS);
  assert.match(await page.locator('#score').textContent(),
    new RegExp(`^In your browser: 0 of 90 points \\(0%\\), 0 of 9 tests pass\\. 7 functions not implemented yet: ${FUNCTIONS.join(', ')}\\.$`));
  assert.equal(await page.locator('#runs').isHidden(), true, 'a run that reported no belief is not drawn');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the correct file scores full marks in the browser, draws each trial over the reference\'s, and gets the same score from the server', bounded, async () => {
  const page = await openPage(browser, `${server.url}/fusion/code`);
  await page.locator('#student').fill('fusion-student');
  await page.locator('#student').dispatchEvent('change');
  await type(page, correct);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  assert.match(await page.locator('#score').textContent(), /^In your browser: 90 of 90 points \(100%\), 9 of 9 tests pass\.$/);
  for (const key of [...FUNCTIONS, ...TRIALS]) assert.equal(await testStatus(page, key), 'passed', key);

  assert.equal(await page.locator('#runs').isVisible(), true, 'the trials are drawn');
  assert.equal(await page.locator('#runs h2').textContent(), 'Your filter over the trials');
  assert.deepEqual(await page.locator('#run-choice option').allTextContents(), TRIALS);
  for (const name of TRIALS) {
    await showTrial(page, name);
    const counts = await plotted(page);
    for (const id of ['truth', 'field of view', 'used', 'reference', 'reference ellipses', 'yours', 'your ellipses', 'start']) {
      assert.ok(counts[id] > 0, `${name}: the series ${id} holds data: ${JSON.stringify(counts)}`);
    }
    assert.equal(counts.yours, counts.reference, `${name}: the student's path has every step`);
    assert.equal(counts.truth, counts.reference, `${name}: the truth has every step`);
    assert.equal(counts.departure, undefined, `${name}: nothing departs`);
    const steps = counts.reference;
    assert.match(await page.locator('#trial-summary').textContent(),
      new RegExp(`^Your filter follows the reference filter's belief at all ${steps} steps: its mean distance from the truth is ([\\d.e-]+) m \\(the reference's \\1 m\\)`));
    assert.equal(await page.locator('#trial-table caption').textContent(), `After step ${steps} of ${steps}, the last your run reported`);
    const rows = await tableRows(page);
    assert.deepEqual(rows.map(([label]) => label), ['x (m)', 'y (m)', 'θ (°)', 'σx (m)', 'σy (m)', 'σθ (°)']);
    for (const [label, ...values] of rows) {
      const [mine, theirs] = values.map(Number);
      assert.ok(Math.abs(mine - theirs) <= 1e-6 * Math.abs(theirs), `${name}: ${label} ${mine} ${theirs}`);
    }
    assert.match(await page.locator('figure[data-name="trial-difference"] .plot-summary').textContent(),
      new RegExp(`^How far your belief is from the reference filter's at each of the ${steps} steps`));
    assert.equal(await page.locator('figure[data-name="trial-difference"] .marker').isHidden(), true, `${name}: no step is marked`);
    assert.match(await page.locator('#prefix').textContent(), new RegExp(`^Grading runs your functions as a filter over this trial: ${steps} steps`));
    assert.equal(await page.locator('#prefix a').getAttribute('href'), '/fusion');
  }

  await page.locator('#submit').click();
  await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
  const verdict = await page.locator('#submission .verdict').textContent();
  assert.match(verdict, /^The server's grade for submission \d+: 90 of 90 points \(100%\)\. The same as in your browser\./);
  assert.match(await page.locator('#submission .hidden-cases').textContent(), /ran your filter over trials you have not seen/);
  const id = verdict.match(/submission (\d+)/)[1];
  const graded = await waitForSubmission(server, `/api/submissions/${id}`);
  assert.equal(graded.lab, LAB, 'the workbench submits as the sensor-fusion exercise');
  assert.deepEqual(graded.result.tests.map((t) => t.subject.name), [...FUNCTIONS, ...TRIALS]);
  assert.equal(graded.score, 1);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the heading\'s innovation not wrapped in update fails its test with the hint, and the trial shows where it departs', bounded, async () => {
  const page = await openPage(browser, `${server.url}/fusion/code`);
  await type(page, unwrappedUpdate);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const cli = cliGrade(unwrappedUpdate, 1);
  for (const t of cli.tests) assert.equal(await testStatus(page, t.subject.name), t.status, t.subject.name);
  assert.equal(await testStatus(page, 'update'), 'failed');
  for (const key of FUNCTIONS.filter((name) => name !== 'update')) assert.equal(await testStatus(page, key), 'passed', key);
  assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)));
  const hint = cli.tests.find((t) => t.subject.name === 'update').failures[0].hint;
  assert.equal(hint.kind, 'fusion_innovation_not_wrapped');
  assert.equal(await page.locator('#test-update .failure .hint').first().textContent(), `Hint: ${hint.text}`);

  // Each trial the mistake spoils shows the step the grader names.
  const spoiled = cli.tests.filter((t) => t.subject.kind === 'run' && t.status === 'failed');
  assert.ok(spoiled.length > 0, 'a trial crosses the heading\'s wrap at an update');
  for (const t of spoiled) {
    const name = t.subject.name;
    const [, step, steps] = t.message.match(/from step (\d+) of (\d+) on, the run departs/);
    await showTrial(page, name);
    assert.match(await page.locator('#trial-summary').textContent(),
      new RegExp(`^Your filter departs from the reference filter's belief at step ${step} of ${steps} \\(t = [\\d.]+ s\\), whose reading the reference used`));
    assert.match(await page.locator('#trial-table caption').textContent(),
      new RegExp(`^At step ${step} of ${steps} \\(t = [\\d.]+ s\\), where your run first departs from the reference's$`));
    const [x, , theta] = await tableRows(page);
    assert.ok(x[1] !== x[2] || theta[1] !== theta[2], `${name}: the table shows the belief apart: ${JSON.stringify([x, theta])}`);
    assert.equal((await plotted(page)).departure, 1, `${name}: the point where it departs is marked`);
    // The plot over time draws (and marks the step) once it is in view.
    await page.locator('figure[data-name="trial-difference"]').scrollIntoViewIfNeeded();
    const marker = page.locator('figure[data-name="trial-difference"] .marker');
    await marker.waitFor({ state: 'visible' });
    assert.equal(await marker.getAttribute('title'), 'where your run departs');
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});
