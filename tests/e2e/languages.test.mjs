// Writing an exercise in Python or MATLAB on the odometry workbench, in headless Chromium
// against the real server: the language's choice switches the editor to its starter and
// keeps each language's file; Run tests and Run paths run the file on the server and show
// the same views as in the browser; the starter fails every test as not implemented; the
// correct file scores full marks there and when submitted, graded in its language. A
// course's instructor takes an exercise's files in some languages only, on the class page;
// the student's workbench then offers those only.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, estlab, laptop, openIn, openPage, parseCsv, root, runAndWait, savedFile, signIn, signedInContext, starterOf, testStatus,
  tempDir, typeInEditor as type, waitForSubmission, withServerAndBrowser,
} from './harness.mjs';

const LAB = 'odometry';
const jsStarter = readFileSync(starterOf('odometry'), 'utf8');
const FUNCTIONS = ['odometry_step', 'pose_jacobian', 'increment_jacobian', 'wheel_noise', 'propagate'];
const PATHS = ['square', 'figure-eight'];

/** Each language the server runs: its folder of test files, its extension, and what its starter's functions throw. */
const LANGUAGES = [
  { name: 'python', title: 'Python', extension: 'py', thrown: 'NotImplementedError' },
  { name: 'matlab', title: 'MATLAB', extension: 'm', thrown: 'error' },
];
const correctIn = (language) => readFileSync(join(root, 'tests', 'student', language.name, `odometry.${language.extension}`), 'utf8');
const starterIn = (language) => readFileSync(starterOf('odometry').replace(/\.js$/, `.${language.extension}`), 'utf8');

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** The first line in the workbench's editor (CodeMirror draws the lines in view only). */
const firstLine = (page) => page.locator('#editor .cm-line').first().textContent();
const first = (text) => text.split('\n')[0];

for (const language of LANGUAGES) test(`${language.title} on the workbench: its starter, its tests and paths run on the server, its submission`, bounded, async () => {
  const correct = correctIn(language);
  const starter = starterIn(language);
  const page = await openPage(browser, `${server.url}/odometry/code`);
  assert.deepEqual(await page.locator('#language option').allTextContents(), ['JavaScript', 'Python', 'MATLAB']);
  assert.equal(await firstLine(page), first(jsStarter), 'JavaScript first');
  await page.locator('#language').selectOption(language.name);
  assert.equal(await firstLine(page), first(starter), `the ${language.title} starter`);

  // The starter: every test fails, each function not implemented, as the language says it.
  await runAndWait(page, '#run-tests');
  assert.match(await page.locator('#score').textContent(),
    /^On the server: 0 of 70 points \(0%\), 0 of 7 tests pass, 2 not run yet\. 5 functions not implemented yet: /);
  assert.match(await page.locator('#test-wheel_noise').textContent(),
    new RegExp(`threw ${language.thrown}: wheel_noise: not implemented`));

  // The correct file: full marks, the paths drawn.
  await type(page, correct);
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  for (const key of [...FUNCTIONS, ...PATHS]) assert.equal(await testStatus(page, key), 'passed', `${key}: ${await page.locator(`#test-${key}`).textContent()}`);
  assert.match(await page.locator('#score').textContent(), /^On the server: 70 of 70 points \(100%\), 7 of 7 tests pass\.$/);
  assert.equal(await page.locator('#runs').isVisible(), true, 'the paths are drawn');
  assert.deepEqual(await page.locator('#run-choice option').allTextContents(), PATHS);

  // Each language keeps its own file.
  assert.equal(await page.evaluate((name) => localStorage.getItem(`estlab:odometry:${name}`), language.name), correct);
  await page.locator('#language').selectOption('javascript');
  assert.equal(await firstLine(page), first(jsStarter));
  assert.equal(await savedFile(page, LAB), null, 'no JavaScript file saved');
  await page.reload();
  await page.waitForSelector('body[data-ready=true]');
  assert.equal(await page.locator('#language').inputValue(), 'javascript', 'the choice is kept');
  await page.locator('#language').selectOption(language.name);
  assert.equal(await firstLine(page), first(correct));

  // Submitted, graded in its language with hidden cases, the same as run on the server.
  await page.locator('#student').fill(`${language.name}-student`);
  await page.locator('#student').dispatchEvent('change');
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  await page.locator('#submit').click();
  await page.waitForSelector('#submission[data-status=graded]', { timeout: 120_000 });
  const verdict = await page.locator('#submission .verdict').textContent();
  assert.match(verdict, /^The server's grade for submission \d+: 70 of 70 points \(100%\)\. The same as in your run on the server\./);
  const id = verdict.match(/submission (\d+)/)[1];
  const graded = await waitForSubmission(server, `/api/submissions/${id}`);
  assert.equal(graded.language, language.name);
  assert.equal(graded.result.hidden_cases, true);
  assert.deepEqual(page.problems, []);
  await page.close();
});

// Before any course exists (the next test makes one), anyone runs files on the server.
test('the lab\'s MATLAB files, a function in each, upload together as one file', bounded, async () => {
  const [matlab] = LANGUAGES.filter((language) => language.name === 'matlab');
  // The correct file cut into a file a function, as the lab's skeleton has them.
  const dir = tempDir();
  const chunks = correctIn(matlab).split(/\n(?=function )/).filter((chunk) => chunk.startsWith('function '));
  const files = chunks.map((chunk) => {
    const name = chunk.match(/^function [^=]*= *(\w+)/)[1];
    const path = join(dir, `${name}.m`);
    writeFileSync(path, chunk);
    return path;
  });
  assert.ok(files.length >= 5, 'a file a function');
  const page = await openPage(browser, `${server.url}/odometry/code`);
  await page.locator('#upload').setInputFiles(files);
  await page.waitForFunction(() => document.getElementById('language').value === 'matlab');
  assert.equal(await page.locator('#error').isVisible(), false);
  await runAndWait(page, '#run-tests');
  for (const key of FUNCTIONS) assert.equal(await testStatus(page, key), 'passed', `${key}: ${await page.locator(`#test-${key}`).textContent()}`);

  // Several files of another language are refused, and the file stays as it was.
  const scripts = ['a.js', 'b.js'].map((name) => join(dir, name));
  for (const path of scripts) writeFileSync(path, jsStarter);
  await page.locator('#upload').setInputFiles(scripts);
  await page.waitForSelector('#error:not([hidden])');
  assert.match(await page.locator('#error').textContent(), /^2 files were chosen: choose one file, or several MATLAB files \(\.m\), which become one\.$/);
  assert.equal(await page.locator('#language').inputValue(), 'matlab');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('an instructor takes the files in Python only, and the workbench offers Python only', bounded, async () => {
  const starter = starterIn(LANGUAGES[0]);
  const created = estlab('course', 'create', 'langs', '--title', 'Languages', '--data', server.dataDir, '--url', server.url);
  const instructorLink = created.trim().split('\n').pop();
  estlab('course', 'assign', 'langs', LAB, '--due', '2030-01-01T00:00Z', '--data', server.dataDir);
  const staff = await openPage(browser, instructorLink);
  await staff.locator('#sign-in').click();
  await staff.waitForURL(`${server.url}/me`);
  await staff.goto(`${server.url}/courses/langs/${LAB}`);
  await staff.waitForSelector('body[data-ready=true]');
  const box = (language) => staff.locator(`#languages input[value=${language}]`);
  assert.equal(await box('javascript').isChecked(), true, 'every language at first');
  assert.equal(await box('python').isChecked(), true);
  assert.equal(await box('matlab').isChecked(), true);
  await box('javascript').uncheck();
  await staff.waitForFunction(() => document.querySelector('#languages-status').textContent !== '');
  assert.equal(await staff.locator('#languages-status').textContent(), 'Files are taken in Python and MATLAB.');
  await box('matlab').uncheck();
  await staff.waitForFunction(() => document.querySelector('#languages-status').textContent === 'Files are taken in Python.');
  await staff.reload();
  await staff.waitForSelector('body[data-ready=true]');
  assert.equal(await box('javascript').isChecked(), false, 'as stored');
  assert.equal(await box('matlab').isChecked(), false, 'as stored');
  assert.deepEqual(staff.problems, []);
  await staff.close();

  // A student of the course: Python only, and the editor in Python.
  const dir = tempDir();
  const roster = join(dir, 'roster.csv');
  const codes = join(dir, 'codes.csv');
  writeFileSync(roster, 'id,name,email\nl001,Lu One,lu@example.org\n');
  estlab('course', 'roster', 'langs', roster, '--out', codes, '--data', server.dataDir, '--url', server.url);
  const [{ code }] = parseCsv(readFileSync(codes, 'utf8'));
  const context = await signedInContext(browser, server, await signIn(server, code), laptop);
  const page = await openIn(context, `${server.url}/odometry/code`);
  assert.equal(await page.locator('#language').inputValue(), 'python');
  assert.equal(await page.locator('#language option[value=javascript]').isDisabled(), true);
  assert.equal(await page.locator('#language option[value=matlab]').isDisabled(), true);
  assert.equal(await firstLine(page), first(starter));
  assert.deepEqual(page.problems, []);
  await context.close();
});
