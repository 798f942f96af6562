// The odometry workbench (/odometry/code) in headless Chromium against the real server:
// it fits a phone and a laptop; the starter file fails every test as not implemented; the
// correct file scores full marks in the browser and through the server, and each path is
// drawn over the reference's; a classic mistake fails its function's test with its hint;
// each exercise keeps its own file; a variant link and a submission link work, and a
// submission opened on the other exercise's workbench moves to its own; and in a course,
// one server grades both exercises, each with its own tests, listing each on /me with its
// own workbench.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, browserPoints, checkStarterFails, checkWorkbenchFits, correct as ekfCorrect, gradeOnCommandLine, laptop, openPage,
  plottedPoints, root, runAndWait, savedFile, setUpCourse, signIn, starterOf, submit, testStatus, typeInEditor as type,
  waitForSubmission, withMistake, withServerAndBrowser,
} from './harness.mjs';

const LAB = 'odometry';
const student = (file) => readFileSync(join(root, 'tests', 'student', 'odometry', file), 'utf8');
const correct = student('correct.js');
const mistakes = JSON.parse(student('mistakes.json'));
const starter = readFileSync(starterOf('odometry'), 'utf8');
const FUNCTIONS = ['odometry_step', 'pose_jacobian', 'increment_jacobian', 'wheel_noise', 'propagate'];
const PATHS = ['square', 'figure-eight'];

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** `estlab grade --lab odometry` of `text` for the variant `seed`, as JSON. */
const cliGrade = (text, seed) => gradeOnCommandLine(LAB, 'odometry.js', text, seed);
/** How many points each series of the path plot holds, by the series' id. */
const plotted = (page) => plottedPoints(page, 'path');

test('the workbench fits a phone and a laptop, without errors, and speaks of odometry', bounded, () => checkWorkbenchFits(browser, server, {
  path: '/odometry/code', heading: 'Your odometry', runButton: 'Run paths', functions: FUNCTIONS, experiments: '/odometry', nav: 'Your odometry code',
}));

test('the starter file fails every test with "not implemented", the paths too', bounded, async () => {
  const page = await openPage(browser, `${server.url}/odometry/code`);
  assert.equal(await savedFile(page, LAB), null, 'nothing saved yet: the editor holds the starter');
  await checkStarterFails(page, starter, FUNCTIONS, PATHS);
  assert.match(await page.locator('#score').textContent(),
    /^In your browser: 0 of 70 points \(0%\), 0 of 7 tests pass\. 5 functions not implemented yet: odometry_step, pose_jacobian, increment_jacobian, wheel_noise, propagate\.$/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the correct file scores full marks in the browser, draws each path over the reference\'s, and gets the same score from the server', bounded, async () => {
  const page = await openPage(browser, `${server.url}/odometry/code`);
  await page.locator('#student').fill('odometry-student');
  await page.locator('#student').dispatchEvent('change');
  await type(page, correct);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  assert.match(await page.locator('#score').textContent(), /^In your browser: 70 of 70 points \(100%\), 7 of 7 tests pass\.$/);
  for (const key of [...FUNCTIONS, ...PATHS]) assert.equal(await testStatus(page, key), 'passed', key);

  assert.equal(await page.locator('#runs').isVisible(), true, 'the paths are drawn');
  assert.equal(await page.locator('#runs h2').textContent(), 'Your odometry along the paths');
  assert.deepEqual(await page.locator('#run-choice option').allTextContents(), PATHS);
  for (const name of PATHS) {
    await page.locator('#run-choice').selectOption(name);
    await page.waitForFunction((n) => document.querySelector('figure[data-name="path"] .plot-summary').textContent.startsWith(`The ${n} path`), name);
    const counts = await plotted(page);
    for (const id of ['reference', 'reference ellipses', 'yours', 'your ellipses', 'start', 'your end']) {
      assert.ok(counts[id] > 0, `${name}: the series ${id} holds data: ${JSON.stringify(counts)}`);
    }
    assert.equal(counts.yours, counts.reference, `${name}: the student's path has every step`);
    const steps = counts.reference - 1;
    assert.match(await page.locator('figure[data-name="path"] .plot-summary').textContent(),
      new RegExp(`The reference ends at .*; yours is 0 m from it, its heading 0° off\\. 3σ ellipses every \\d+ steps; after step ${steps} `));
    assert.equal(await page.locator('#path-table caption').textContent(), `After step ${steps} of ${steps}, the last your run reported`);
    const rows = await page.locator('#path-table tbody tr').evaluateAll((trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    assert.equal(rows.length, 9, 'the pose and the six entries of its covariance');
    for (const [label, ...values] of rows) {
      const [mine, theirs] = values.map(Number);
      assert.ok(Math.abs(mine - theirs) <= 1e-6 * Math.abs(theirs), `${name}: ${label} ${mine} ${theirs}`);
    }
    assert.match(await page.locator('#prefix').textContent(), new RegExp(`^Grading drives your functions along this path: ${steps} steps`));
    assert.equal(await page.locator('#prefix a').getAttribute('href'), '/odometry');
  }

  await page.locator('#submit').click();
  await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
  const verdict = await page.locator('#submission .verdict').textContent();
  assert.match(verdict, /^The server's grade for submission \d+: 70 of 70 points \(100%\)\. The same as in your browser\./);
  assert.match(await page.locator('#submission .hidden-cases').textContent(), /drove your functions along paths you have not seen/);
  const id = verdict.match(/submission (\d+)/)[1];
  const graded = await waitForSubmission(server, `/api/submissions/${id}`);
  assert.equal(graded.lab, LAB, 'the workbench submits as the odometry exercise');
  assert.deepEqual(graded.result.tests.map((t) => t.subject.name), [...FUNCTIONS, ...PATHS]);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a classic mistake fails the test of the function it names, with its hint, and its path strays from the reference\'s', bounded, async () => {
  const name = 'step-half-axle';
  const mistake = mistakes.find((m) => m.name === name);
  const text = withMistake(correct, mistakes, name);
  const page = await openPage(browser, `${server.url}/odometry/code`);
  await type(page, text);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const cli = cliGrade(text, 1);
  for (const t of cli.tests) {
    const key = t.subject.name;
    assert.equal(await testStatus(page, key), key === mistake.breaks || PATHS.includes(key) ? 'failed' : 'passed', key);
  }
  assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)));
  const hint = cli.tests.find((t) => t.name.startsWith(mistake.breaks)).failures[0].hint;
  assert.equal(hint.kind, mistake.hint);
  assert.equal(await page.locator(`#test-${mistake.breaks} .failure .hint`).first().textContent(), `Hint: ${hint.text}`);

  // The path the mistake drives is drawn, off the reference's.
  const summary = await page.locator('figure[data-name="path"] .plot-summary').textContent();
  const off = Number(summary.match(/yours is ([\d.e+-]+) m from it/)[1]);
  assert.ok(off > 0.01, `the half-turning path ends away from the reference's: ${summary}`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('each exercise keeps its own file in the browser', bounded, async () => {
  // One browser context: one localStorage for both workbenches.
  const context = await browser.newContext();
  const odometry = await openPage(context, `${server.url}/odometry/code`);
  await type(odometry, '// my odometry\n');
  const ekf = await openPage(context, `${server.url}/ekf/code`);
  await type(ekf, '// my EKF\n');
  for (const page of [odometry, ekf]) {
    await page.reload();
    await page.waitForSelector('body[data-ready=true]');
  }
  assert.equal(await savedFile(odometry, LAB), '// my odometry\n');
  assert.equal(await savedFile(ekf), '// my EKF\n');
  assert.equal(await odometry.locator('#editor .cm-content').textContent(), '// my odometry');
  assert.equal(await ekf.locator('#editor .cm-content').textContent(), '// my EKF');
  const [download] = await Promise.all([odometry.waitForEvent('download'), odometry.locator('#download').click()]);
  assert.equal(download.suggestedFilename(), 'odometry.js');
  assert.deepEqual([...odometry.problems, ...ekf.problems], []);
  await context.close();
});

test('?seed=N opens that variant as the command line grades it; ?submission=ID opens a submission, on its own exercise\'s workbench', bounded, async () => {
  const page = await openPage(browser, `${server.url}/odometry/code?seed=4242`);
  assert.match(await page.locator('#seed').textContent(), /^the variant of your link: seed 4242/);
  const text = withMistake(correct, mistakes, 'wheel-noise-no-absolute-value');
  await type(page, text);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const cli = cliGrade(text, 4242);
  assert.ok(cli.score < 1);
  assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)));
  await page.close();

  // On a server without courses, anyone reads a submission's result (not its code).
  const sent = async (body) => (await (await submit(server, body)).json()).url.split('/').at(-1);
  const odometryId = await sent({ student: 'linker', lab: LAB, source: starter });
  const ekfId = await sent({ student: 'linker', source: '// nothing\n' });
  await waitForSubmission(server, `/api/submissions/${odometryId}`);
  const viewer = await openPage(browser, `${server.url}/odometry/code?submission=${odometryId}`);
  await viewer.waitForSelector('#viewer-result[data-status=graded]', { timeout: 60_000 });
  assert.equal(await viewer.locator('#viewer-title').textContent(), `Submission ${odometryId}`);
  assert.match(await viewer.locator('#viewer-result .verdict').textContent(), new RegExp(`submission ${odometryId}: 0 of 70 points`));
  assert.equal(await viewer.locator('#back-to-editor').getAttribute('href'), '/odometry/code');
  await viewer.locator('#back-to-editor').click();
  await viewer.waitForSelector('#workbench:not([hidden])');
  assert.equal(new URL(viewer.url()).pathname, '/odometry/code', 'back at this workbench');

  // The EKF submission's link on the odometry workbench: it opens on the EKF's.
  await viewer.goto(`${server.url}/odometry/code?submission=${ekfId}`);
  await viewer.waitForURL(`${server.url}/ekf/code?submission=${ekfId}`, { timeout: 60_000 });
  await viewer.waitForSelector('body[data-ready=true]');
  assert.equal(await viewer.locator('#viewer-title').textContent(), `Submission ${ekfId}`);
  assert.equal(await viewer.locator('h1').textContent(), 'Your EKF localization');
  assert.deepEqual(viewer.problems, []);
  await viewer.close();
});

// Last: it turns the server into a course server, where submitting needs signing in.
test('in a course, one server grades an EKF and an odometry submission, each with its own tests, and /me opens each in its own workbench', bounded, async () => {
  const { students: [pupil] } = setUpCourse(server, {
    title: 'Two exercises', prefix: 'two', count: 1, role: 'assistant', labs: ['ekf-localization', LAB],
  });
  const context = await browser.newContext({ viewport: laptop });
  const [name, value] = (await signIn(server, pupil.code)).split('=');
  await context.addCookies([{ name, value, url: server.url }]);
  const page = await openPage(context, `${server.url}/me`);
  const visit = async (path) => {
    await page.goto(server.url + path);
    await page.waitForSelector('body[data-ready=true]', { timeout: 60_000 });
  };

  const graded = {};
  for (const [lab, path, file, points] of [['ekf-localization', '/ekf/code', ekfCorrect, 110], [LAB, '/odometry/code', correct, 70]]) {
    await visit(path);
    assert.match(await page.locator('#deadline').textContent(), /^Due /, `${lab}: the course opened it`);
    await type(page, file);
    await page.locator('#submit').click();
    await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
    const verdict = await page.locator('#submission .verdict').textContent();
    assert.match(verdict, new RegExp(`^The server's grade for submission \\d+: ${points} of ${points} points \\(100%\\)`), lab);
    const id = verdict.match(/submission (\d+)/)[1];
    assert.equal(await page.locator('#submission .links a').first().getAttribute('href'), `${path}?submission=${id}`, lab);
    graded[lab] = { id, path, result: await page.evaluate(async (url) => (await (await fetch(url)).json()), `/api/submissions/${id}`) };
  }
  assert.equal(graded['ekf-localization'].result.lab, 'ekf-localization');
  assert.equal(graded[LAB].result.lab, LAB);
  const names = (lab) => graded[lab].result.result.tests.map((t) => t.subject.name);
  assert.deepEqual(names(LAB), [...FUNCTIONS, ...PATHS]);
  assert.ok(names('ekf-localization').includes('predict') && !names('ekf-localization').includes('propagate'), names('ekf-localization').join());
  for (const lab of Object.keys(graded)) assert.equal(graded[lab].result.score, 1, lab);

  await visit('/me');
  for (const [lab, { id, path }] of Object.entries(graded)) {
    const section = page.locator(`section.assignment[data-lab="${lab}"]`);
    assert.equal(await section.locator('a.workbench').getAttribute('href'), path, `${lab}: Open the workbench`);
    assert.equal(await section.locator(`table.history tr[data-id="${id}"] a.open`).getAttribute('href'), `${path}?submission=${id}`, lab);
  }
  assert.equal(await page.locator('section.assignment[data-lab="odometry"] h3').textContent(), 'Odometry and its error propagation (odometry)');
  const about = await page.evaluate(async () => (await fetch('/api/me')).json());
  assert.deepEqual(Object.fromEntries(about.assignments.map((a) => [a.lab, a.workbench])),
    { 'ekf-localization': '/ekf/code', odometry: '/odometry/code' });

  await page.locator(`section.assignment[data-lab="odometry"] a.open`).click();
  await page.waitForURL(`${server.url}/odometry/code?submission=${graded[LAB].id}`);
  await page.waitForSelector('#viewer-result[data-status=graded]', { timeout: 60_000 });
  assert.match(await page.locator('#viewer-source .cm-content').textContent(), /^\/\/ Odometry and how its error grows: a correct solution/);
  assert.deepEqual(page.problems, []);
  await context.close();
});
