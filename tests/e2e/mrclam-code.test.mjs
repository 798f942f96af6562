// The workbench of the UKF and the particle filter (/mrclam/code) in headless Chromium
// against the real server: it fits a phone and a laptop; the starter file fails every
// test as not implemented; the correct file scores full marks in the browser and through
// the server, and each run is drawn, the student's path over the reference filter's; a
// classic mistake fails its function's test with its hint, and the particle filter's run
// shows where the student's belief departs from the reference's.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, browserPoints, checkStarterFails, checkWorkbenchFits, gradeOnCommandLine, openPage, plottedPoints, root, runAndWait,
  starterOf, testStatus, typeInEditor as type, waitForSubmission, withServerAndBrowser,
} from './harness.mjs';

const LAB = 'ukf-particle';
const correct = readFileSync(join(root, 'tests', 'student', 'ukf_particle', 'correct.js'), 'utf8');
const starter = readFileSync(starterOf('ukf_particle'), 'utf8');
const FUNCTIONS = [
  'motion', 'process_noise', 'sigma_points', 'ukf_predict', 'ukf_update', 'sample_motion', 'particle_weights',
  'needs_resampling', 'low_variance_resample', 'particle_estimate', 'measurement_noise', 'learn_alphas',
];
const RUNS = ['ukf', 'particle-filter'];
/** correct.js with each particle's two normal draws used the other way round in `sample_motion`. */
const swappedDraws = (() => {
  const from = 'const drawn = [u[0] + sdV * normals[i][0], u[1] + sdOmega * normals[i][1]];';
  assert.ok(correct.includes(from));
  return correct.replace(from, 'const drawn = [u[0] + sdV * normals[i][1], u[1] + sdOmega * normals[i][0]];');
})();

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** Shows the run `name` in the runs' section, once its view is drawn. */
async function showRun(page, name) {
  await page.locator('#run-choice').selectOption(name);
  await page.waitForFunction((n) => document.querySelector('figure[data-name="filter-path"] .plot-summary').textContent.startsWith(`The ${n} run`), name);
}

/** The rows of the table of the step shown: [label, yours, the reference's]. */
function tableRows(page) {
  return page.locator('#filter-table tbody tr').evaluateAll((trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
}

test('the workbench fits a phone and a laptop, without errors, and speaks of the UKF and the particle filter', bounded, () => checkWorkbenchFits(browser, server, {
  path: '/mrclam/code', heading: 'Your UKF and particle filter', runButton: 'Run filters', functions: FUNCTIONS, experiments: '/mrclam',
  nav: 'Your UKF and particle filter',
}));

test('the starter file fails every test with "not implemented", the runs too, and draws no run', bounded, async () => {
  const page = await openPage(browser, `${server.url}/mrclam/code`);
  await checkStarterFails(page, starter, FUNCTIONS, RUNS);
  assert.match(await page.locator('#score').textContent(),
    new RegExp(`^In your browser: 0 of 140 points \\(0%\\), 0 of 14 tests pass\\. 12 functions not implemented yet: ${FUNCTIONS.join(', ')}\\.$`));
  assert.equal(await page.locator('#runs').isHidden(), true, 'a run that reported no belief is not drawn');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the correct file scores full marks in the browser, draws each run over the reference\'s, and gets the same score from the server', bounded, async () => {
  const page = await openPage(browser, `${server.url}/mrclam/code`);
  await page.locator('#student').fill('mrclam-student');
  await page.locator('#student').dispatchEvent('change');
  await type(page, correct);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  assert.match(await page.locator('#score').textContent(), /^In your browser: 140 of 140 points \(100%\), 14 of 14 tests pass\.$/);
  for (const key of [...FUNCTIONS, ...RUNS]) assert.equal(await testStatus(page, key), 'passed', key);

  assert.equal(await page.locator('#runs').isVisible(), true, 'the runs are drawn');
  assert.equal(await page.locator('#runs h2').textContent(), 'Your filters along the generated robots');
  assert.deepEqual(await page.locator('#run-choice option').allTextContents(), RUNS);
  for (const [name, filter] of [['ukf', 'UKF'], ['particle-filter', 'particle filter']]) {
    await showRun(page, name);
    const counts = await plottedPoints(page, 'filter-path');
    for (const id of ['truth', 'posts', 'reference', 'yours', 'start']) {
      assert.ok(counts[id] > 0, `${name}: the series ${id} holds data: ${JSON.stringify(counts)}`);
    }
    assert.equal(counts.yours, counts.reference, `${name}: the student's path has every step`);
    assert.equal(counts.truth, counts.reference, `${name}: the truth has every step`);
    assert.equal(counts.departure, undefined, `${name}: nothing departs`);
    const steps = counts.reference;
    assert.match(await page.locator('#filter-summary').textContent(),
      new RegExp(`^Your ${filter} follows the reference ${filter}'s belief at all ${steps} steps; at the end it is [\\d.e-]+ m from the truth\\.$`));
    assert.equal(await page.locator('#filter-table caption').textContent(), `After step ${steps} of ${steps}, the last your run reported`);
    for (const [label, ...values] of await tableRows(page)) {
      const [mine, theirs] = values.map(Number);
      assert.ok(Math.abs(mine - theirs) <= 1e-6 * Math.abs(theirs), `${name}: ${label} ${mine} ${theirs}`);
    }
    assert.match(await page.locator('#prefix').textContent(), new RegExp(`^Grading strings your functions into an? ${filter === 'UKF' ? 'UKF' : 'particle filter'}`));
    assert.equal(await page.locator('#prefix a').getAttribute('href'), '/mrclam');
  }

  await page.locator('#submit').click();
  await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
  const verdict = await page.locator('#submission .verdict').textContent();
  assert.match(verdict, /^The server's grade for submission \d+: 140 of 140 points \(100%\)\. The same as in your browser\./);
  assert.match(await page.locator('#submission .hidden-cases').textContent(), /ran your filters along generated robots/);
  const id = verdict.match(/submission (\d+)/)[1];
  const graded = await waitForSubmission(server, `/api/submissions/${id}`);
  assert.equal(graded.lab, LAB, 'the workbench submits as the exercise on the UKF and the particle filter');
  assert.deepEqual(graded.result.tests.map((t) => t.subject.name), [...FUNCTIONS, ...RUNS]);
  assert.equal(graded.score, 1);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a particle\'s draws used the other way round fail sample_motion with the hint, and the particle filter\'s run shows where it departs', bounded, async () => {
  const page = await openPage(browser, `${server.url}/mrclam/code`);
  await type(page, swappedDraws);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const cli = gradeOnCommandLine(LAB, 'ukf_particle.js', swappedDraws, 1);
  for (const t of cli.tests) assert.equal(await testStatus(page, t.subject.name), t.status, t.subject.name);
  assert.equal(await testStatus(page, 'sample_motion'), 'failed');
  assert.equal(await testStatus(page, 'ukf'), 'passed');
  assert.equal(await testStatus(page, 'particle-filter'), 'failed');
  assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)));
  const hint = cli.tests.find((t) => t.subject.name === 'sample_motion').failures[0].hint;
  assert.equal(hint.kind, 'control_normals_swapped');
  assert.equal(await page.locator('#test-sample_motion .failure .hint').first().textContent(), `Hint: ${hint.text}`);

  const run = cli.tests.find((t) => t.subject.name === 'particle-filter');
  const [, step, steps] = run.message.match(/from step (\d+) of (\d+) on, the run departs/);
  await showRun(page, 'particle-filter');
  assert.match(await page.locator('#filter-summary').textContent(),
    new RegExp(`^Your particle filter departs from the reference particle filter's belief at step ${step} of ${steps} \\(t = [\\d.]+ s\\)`));
  assert.match(await page.locator('#filter-table caption').textContent(),
    new RegExp(`^At step ${step} of ${steps} \\(t = [\\d.]+ s\\), where your run first departs from the reference's$`));
  assert.equal((await plottedPoints(page, 'filter-path')).departure, 1, 'the point where it departs is marked');
  await page.locator('figure[data-name="filter-difference"]').scrollIntoViewIfNeeded();
  const marker = page.locator('figure[data-name="filter-difference"] .marker');
  await marker.waitFor({ state: 'visible' });
  assert.equal(await marker.getAttribute('title'), 'where your run departs');
  assert.deepEqual(page.problems, []);
  await page.close();
});
