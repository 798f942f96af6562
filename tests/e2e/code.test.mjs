// The student's workbench in headless Chromium against the real server: a fix typed into
// the editor turns a failing test green, the file survives a reload, the browser's verdict
// is the command line's, a submission gets the server's score, and an endless loop is
// stopped in the browser while the server keeps answering.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, browserPoints, correct, estlab, loopingInPredict, openPage, root, runAndWait, savedFile as saved, submission,
  starterOf, submit, tempDir, testStatus, typeInEditor as type, waitForSubmission, withMistake as mistaken, withServerAndBrowser,
} from './harness.mjs';

const mistakes = JSON.parse(readFileSync(join(root, 'tests', 'student', 'mistakes.json'), 'utf8'));

/** correct.js with the mistake called `name` made. */
const withMistake = (name) => mistaken(correct, mistakes, name);

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

test('the starter file: every test fails with "not implemented", and reset asks first', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  assert.deepEqual(page.problems, []);
  await runAndWait(page, '#run-tests');
  const starter = readFileSync(starterOf('ekf_localization'), 'utf8').split('\n');
  for (const key of ['calculate_odometry', 'predict', 'batch_update']) {
    assert.equal(await testStatus(page, key), 'failed', key);
    const line = starter.findIndex((text) => text.includes(`${key}: not implemented`)) + 1;
    assert.match(await page.locator(`#test-${key} .failure .thrown`).first().textContent(),
      new RegExp(`threw Error: ${key}: not implemented \\(line ${line}\\)`), key);
  }
  assert.equal(await testStatus(page, 'o3'), 'not-run');
  // Grouped, not 32 failures spelt out: one line on the score, each function folded.
  assert.match(await page.locator('#score').textContent(),
    /8 functions not implemented yet: calculate_odometry, predict, observation_model, jacobian_observation_model, associate, batch_associate, update, batch_update\./);
  for (const key of ['predict', 'associate']) {
    assert.equal(await page.locator(`#test-${key} > details`).getAttribute('open'), null, key);
    assert.equal(await page.locator(`#test-${key} .failure`).count(), 1, key);
  }
  await type(page, '// my start\n');
  let asked = null;
  page.once('dialog', (dialog) => { asked = dialog.message(); dialog.dismiss(); });
  await page.locator('#reset').click();
  assert.match(asked, /Replace your code with the starter file/);
  assert.equal(await saved(page), '// my start\n', 'dismissing keeps the code');
  page.once('dialog', (dialog) => dialog.accept());
  await page.locator('#reset').click();
  assert.match(await saved(page), /not implemented/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a fix typed into the editor turns a failing test green, and the file survives a reload', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  await type(page, withMistake('bearing-not-wrapped'));
  await runAndWait(page, '#run-tests');
  assert.equal(await testStatus(page, 'observation_model'), 'failed');
  assert.equal(await testStatus(page, 'predict'), 'passed');
  const failure = page.locator('#test-observation_model .failure').first();
  assert.match(await failure.locator('.hint').textContent(), /wrap/i);
  assert.match(await failure.locator('table.mismatches').textContent(), /expected.*got/s);

  await type(page, correct);
  assert.equal(await page.locator('#tests').getAttribute('class'), 'tests stale', 'old results are marked stale');
  await runAndWait(page, '#test-observation_model button.run');
  assert.equal(await testStatus(page, 'observation_model'), 'passed');

  await page.reload();
  await page.waitForSelector('body[data-ready=true]');
  assert.equal(await saved(page), correct);
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#download').click()]);
  assert.equal(readFileSync(await download.path(), 'utf8'), correct, 'the downloaded file is the edited one');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the correct file scores 1 in the browser and through the server, and the verdicts agree', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  await page.locator('#student').fill('e2e-student');
  await page.locator('#student').dispatchEvent('change');
  await type(page, correct);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  assert.match(await page.locator('#score').textContent(), /110 of 110 points \(100%\), 11 of 11 tests pass\./);
  assert.equal(await page.locator('#runs').isVisible(), true, 'the runs are plotted');
  assert.match(await page.locator('#summary').textContent(), /mean absolute error/);
  // Where the run is shown: that it is a prefix, and a link to the whole data set.
  assert.match(await page.locator('#prefix').textContent(),
    /^Grading runs the first \d+ readings of this data set \([\d.]+ s of \d+ time steps\)/);
  const whole = await page.locator('#prefix a').getAttribute('href');
  assert.match(whole, /^\/ekf\?kind=o3&seed=\d+&mode=sequential$/);
  const experiment = await openPage(browser, server.url + whole);
  const seed = whole.match(/seed=(\d+)/)[1];
  assert.equal(await experiment.locator('#dataset-kind').inputValue(), 'o3');
  assert.equal(await experiment.locator('#dataset-seed').inputValue(), seed);
  assert.equal(await experiment.locator('input[name=mode][value=sequential]').isChecked(), true);
  const dir = tempDir();
  estlab('simulate', '--kind', 'o3', '--seed', seed, '--out', dir);
  const native = estlab('run', join(dir, `so_o3_${seed}.txt`), join(dir, `map_o3_${seed}.txt`));
  const errors = native.split('\n').find((line) => line.startsWith('mean absolute error'));
  assert.ok((await experiment.locator('#summary').textContent()).includes(errors),
    `the experiment page runs the whole data set: ${errors}`);
  assert.deepEqual(experiment.problems, []);
  await experiment.close();

  await page.locator('#submit').click();
  await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
  const text = await page.locator('#submission').textContent();
  assert.match(text, /The server's grade for submission \d+: 110 of 110 points \(100%\)\. The same as in your browser\./);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('typing a student id says which variant it gives at once, and keeps the results of the last run, saying whose they are', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  await page.locator('#student').fill('');
  await page.locator('#student').dispatchEvent('change');
  await type(page, correct);
  await runAndWait(page, '#test-predict button.run');
  assert.equal(await testStatus(page, 'predict'), 'passed');
  await page.locator('#student').pressSequentially('variant-reader');
  assert.match(await page.locator('#seed').textContent(),
    /^your own variant: seed \d+\. The results below are for seed 1: run again for this variant\.$/);
  assert.equal(await testStatus(page, 'predict'), 'passed', 'the results stay');
  await runAndWait(page, '#test-predict button.run');
  assert.match(await page.locator('#seed').textContent(), /^your own variant: seed \d+$/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a link with ?seed=N (from a Gradescope or PrairieLearn result) opens that variant, graded as the command line grades it', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code?seed=4242`);
  assert.equal(await page.locator('#seed').textContent(),
    'the variant of your link: seed 4242 (Submit sends your file to this server, which grades the variant of your student id)');
  const text = withMistake('threshold-strict');
  await type(page, text);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const file = join(tempDir(), 'linked.js');
  writeFileSync(file, text);
  // The browser checks the first readings of each data set, as QuickJS grades them.
  const cli = JSON.parse(estlab('grade', file, '--seed', '4242', '--javascript', 'quickjs'));
  assert.equal(cli.seed, 4242);
  assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)));
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('for broken files the browser gives the command line\'s points, test by test', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  const dir = tempDir();
  for (const name of ['odometry-wheels-swapped', 'jacobian-transposed', 'threshold-strict', 'batch-q-bar-range-variance']) {
    const text = withMistake(name);
    await type(page, text);
    await runAndWait(page, '#run-tests');
    await runAndWait(page, '#run-datasets');
    const file = join(dir, `${name}.js`);
    writeFileSync(file, text);
    // The browser checks the first readings of each data set, as QuickJS grades them
    // (on V8 the command line goes through whole data sets, where a mistake may show
    // in another run).
    const cli = JSON.parse(estlab('grade', file, '--seed', '1', '--javascript', 'quickjs'));
    assert.ok(cli.score < 1, name);
    assert.equal(await browserPoints(page), Number(cli.points.toPrecision(4)), name);
    for (const t of cli.tests) {
      const key = t.subject.name;
      assert.equal(await testStatus(page, key), t.status, `${name}: ${t.name}`);
    }
  }
  await page.close();
});

test('an endless loop is stopped at the time limit in the browser, and the server keeps serving meanwhile', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  const looping = loopingInPredict;
  assert.notEqual(looping, correct);
  await type(page, looping);
  await runAndWait(page, '#run-tests');
  assert.equal(await testStatus(page, 'predict'), 'failed');
  assert.match(await page.locator('#test-predict .message').textContent(), /Stopped after 2 s, the time limit, while running predict\/p1/);
  assert.equal(await testStatus(page, 'update'), 'passed', 'the tests after it run in a fresh worker');

  const response = await submit(server, { student: 'loop', source: looping });
  assert.equal(response.status, 202);
  const { url } = await response.json();
  const health = await fetch(`${server.url}/healthz`);
  assert.equal(await health.text(), 'ok');
  const during = await submission(server, url);
  assert.notEqual(during.status, 'graded', 'the health check was answered while the loop was being graded');
  const graded = await waitForSubmission(server, url);
  assert.equal(graded.result.gradable, true);
  const predict = graded.result.tests.find((t) => t.name.startsWith('predict'));
  assert.match(predict.message, /Stopped after 2 s, the time limit/);
  await page.close();
});

test('student code in the browser reaches no network, even through globalThis', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  const snooping = correct.replace(/function predict\(([^)]*)\) \{/, `function predict($1) {
  const request = new globalThis.XMLHttpRequest();
  request.open('GET', '/healthz', false);
  request.send();`);
  await type(page, snooping);
  await runAndWait(page, '#test-predict button.run');
  assert.equal(await testStatus(page, 'predict'), 'failed');
  assert.match(await page.locator('#test-predict .failure .thrown').first().textContent(), /NetworkError|Failed to execute 'send'/);
  await page.close();
});

test('student code in the browser cannot post a verdict of its own, nor rewrite the harness\'s', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  // A file with no predict of its own that tries every way to make the page believe
  // predict passed: posting on the worker, and rewriting what the harness posts.
  const forged = JSON.stringify({ function: 'predict', results: [], repeats: [] });
  const forging = correct.replace(/function predict\(/, 'function not_predict(') + `
self.postMessage({ output: ${JSON.stringify(forged)} });
globalThis.postMessage({ ready: true });
const realPost = MessagePort.prototype.postMessage;
MessagePort.prototype.postMessage = function (message) {
  return realPost.call(this, { output: ${JSON.stringify(forged)} });
};
Object.defineProperty(Object.prototype, 'error', { set(v) {}, configurable: true });
`;
  await type(page, forging);
  await runAndWait(page, '#test-predict button.run');
  assert.equal(await testStatus(page, 'predict'), 'failed');
  assert.match(await page.locator('#test-predict .message').first().textContent(), /predict is not defined/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the keyboard reaches every control of the workbench, and each names what it does', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf/code`);
  await type(page, correct);
  await runAndWait(page, '#test-predict button.run');
  // Tab from the student id through the toolbar: every button is reached.
  await page.locator('#student').focus();
  const reached = new Set();
  for (let i = 0; i < 12; i++) {
    await page.keyboard.press('Tab');
    reached.add(await page.evaluate(() => document.activeElement.id || document.activeElement.className));
  }
  for (const id of ['run-tests', 'run-datasets', 'submit', 'download', 'upload-button', 'reset']) {
    assert.ok(reached.has(id), `${id} is reached with Tab: ${[...reached].join(', ')}`);
  }
  assert.equal(await page.locator('#test-predict button.run').getAttribute('aria-label'), 'Run the tests of predict only');
  // Upload from the keyboard: the button opens the file chooser.
  const chooser = page.waitForEvent('filechooser');
  await page.locator('#upload-button').focus();
  await page.keyboard.press('Enter');
  await (await chooser).setFiles({ name: 'mine.js', mimeType: 'text/javascript', buffer: Buffer.from('// uploaded\n') });
  await page.waitForFunction(() => document.querySelector('.cm-content').textContent.includes('// uploaded'));
  assert.deepEqual(page.problems, []);
  await page.close();
});
