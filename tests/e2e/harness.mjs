// What the end-to-end tests share: the real estlab binary, started on a free loopback
// port, the estlab command line, and headless Chromium (Debian's) driven by Playwright.
import assert from 'node:assert/strict';
import { spawn, execFileSync } from 'node:child_process';
import { chownSync, existsSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { after, before } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const estlabBinary = process.env.ESTLAB_BIN ?? join(root, 'target', 'debug', 'estlab');
/** The browser build (scripts/build-web): the wasm-bindgen package in pkg/, the site in dist/. */
export const webDir = process.env.ESTLAB_WEB ?? join(root, 'target', 'web');
export const staticDir = join(webDir, 'dist');
export const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';
/**
 * The real data sets (`ESTLAB_SHARED_DATA`, default `../shared/data` beside the repository;
 * a relative path is taken from the repository's root), as `estlab serve --datasets` reads
 * them; `ESTLAB_REQUIRE_SHARED_DATA=1` makes a test that needs them fail where they are missing.
 */
export const sharedDataDir = resolve(root, process.env.ESTLAB_SHARED_DATA ?? join('..', 'shared', 'data'));
export const requireSharedData = process.env.ESTLAB_REQUIRE_SHARED_DATA === '1';
/** The exercises' folders. */
export const exercisesDir = join(root, 'labs', 'src', 'exercises');

/** The reference solution of the EKF exercise, as a student would write it. */
export const correct = readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8');
/** The starter file: every function throws "not implemented", so it grades in milliseconds. */
export const starter = readFileSync(starterOf('ekf_localization'), 'utf8');

/** The starter file of the exercise in `folder` (`labs/src/exercises/<folder>/`). */
export function starterOf(folder) {
  return join(exercisesDir, folder, 'web', 'starter.js');
}

/**
 * `file` with the mistake called `name` of `mistakes` (a tests/student mistakes.json) made:
 * each of its replacements, which must each find their text.
 */
export function withMistake(file, mistakes, name) {
  const mistake = mistakes.find((m) => m.name === name);
  assert.ok(mistake, `no mistake ${name}`);
  return mistake.replace.reduce((text, { from, to }) => {
    assert.ok(text.includes(from), `${name}: ${from}`);
    return text.replace(from, to);
  }, file);
}

/** correct.js with an endless loop at the start of `predict`, which the sandboxes stop after 2 s. */
export const loopingInPredict = correct.replace(/function predict\(([^)]*)\) \{/, 'function predict($1) { while (true) {}');

/**
 * The estlab command line: its standard output, or a thrown error with its stderr. On
 * PostgreSQL, the database of the data directory that `--data` names.
 */
export function estlab(...args) {
  const data = args.indexOf('--data');
  const env = data >= 0 ? withDatabase(args[data + 1]) : process.env;
  return execFileSync(estlabBinary, args, { encoding: 'utf8', maxBuffer: 1 << 28, env });
}

/**
 * Whether the tests run on PostgreSQL (`ESTLAB_TEST_DATABASE=postgres`, as scripts/test
 * runs the load and regrade tests a second time), rather than each data directory's SQLite.
 */
export const onPostgres = process.env.ESTLAB_TEST_DATABASE === 'postgres';

/**
 * The environment of an estlab process over the data directory `dataDir`: on PostgreSQL,
 * with ESTLAB_DATABASE naming the directory's own database (made at the first ask, and
 * named in the directory's `test-database`, as the Rust tests' is).
 */
export function withDatabase(dataDir) {
  if (!onPostgres) {
    const env = { ...process.env };
    delete env.ESTLAB_DATABASE;
    return env;
  }
  const file = join(dataDir, 'test-database');
  if (!existsSync(file)) {
    mkdirSync(dataDir, { recursive: true });
    writeFileSync(file, newDatabase());
  }
  return { ...process.env, ESTLAB_DATABASE: readFileSync(file, 'utf8') };
}

/**
 * This test file's PostgreSQL server (as the Rust tests' pgtest starts theirs): Debian's
 * newest /usr/lib/postgresql/*\/bin, a cluster in a temporary folder, listening on a Unix
 * socket there only, run as the postgres user when the tests run as root; stopped when the
 * test file's process exits. Folders of earlier runs whose process is gone are removed.
 */
let cluster;
let databases = 0;
function newDatabase() {
  cluster ??= startCluster();
  const name = `e${databases++}`;
  execFileSync(join(cluster.bin, 'createdb'), ['-h', cluster.dir, '-p', '5432', '-U', 'estlab', name]);
  return `host=${cluster.dir} port=5432 user=estlab dbname=${name}`;
}

function startCluster() {
  const versions = existsSync('/usr/lib/postgresql') ? readdirSync('/usr/lib/postgresql').filter((v) => /^\d+$/.test(v)) : [];
  const newest = versions.map(Number).sort((a, b) => a - b).at(-1);
  if (newest === undefined) throw new Error('ESTLAB_TEST_DATABASE=postgres, but PostgreSQL is not installed (apt-get install postgresql, as scripts/test does)');
  const bin = process.env.ESTLAB_POSTGRES_BIN ?? `/usr/lib/postgresql/${newest}/bin`;
  for (const name of readdirSync(tmpdir())) {
    const pid = name.match(/^estlab-pg-(\d+)$/)?.[1];
    if (!pid || existsSync(`/proc/${pid}`)) continue;
    // A server its test process left running (killed before it could stop it) stops first.
    const postmaster = join(tmpdir(), name, 'data', 'postmaster.pid');
    const server = existsSync(postmaster) ? readFileSync(postmaster, 'utf8').split('\n')[0] : '';
    if (/^\d+$/.test(server) && existsSync(`/proc/${server}/cmdline`) && readFileSync(`/proc/${server}/cmdline`, 'utf8').includes('postgres')) {
      process.kill(Number(server), 'SIGQUIT');
    }
    rmSync(join(tmpdir(), name), { recursive: true, force: true });
  }
  const dir = join(tmpdir(), `estlab-pg-${process.pid}`);
  mkdirSync(dir);
  let user = {};
  if (process.getuid() === 0) {
    const line = readFileSync('/etc/passwd', 'utf8').split('\n').find((l) => l.startsWith('postgres:'));
    assert.ok(line, 'the tests run as root, which PostgreSQL refuses, and there is no user postgres');
    const [, , uid, gid] = line.split(':');
    user = { uid: Number(uid), gid: Number(gid) };
    chownSync(dir, user.uid, user.gid);
  }
  execFileSync(join(bin, 'initdb'), ['-D', join(dir, 'data'), '-U', 'estlab', '--auth=trust', '--no-locale', '-E', 'UTF8', '--no-sync'], { ...user, stdio: 'ignore' });
  const server = spawn(join(bin, 'postgres'), ['-D', join(dir, 'data'), '-k', dir, '-p', '5432', '-c', 'listen_addresses=',
    '-c', 'fsync=off', '-c', 'synchronous_commit=off', '-c', 'full_page_writes=off', '-c', 'max_connections=200'], { ...user, stdio: 'ignore' });
  // Not holding the test file's process open: it stops the server as it exits.
  server.unref();
  process.on('exit', () => server.kill('SIGINT'));
  for (let tries = 0; ; tries++) {
    try {
      execFileSync(join(bin, 'pg_isready'), ['-h', dir, '-p', '5432', '-q']);
      return { bin, dir };
    } catch (error) {
      if (tries > 600) throw new Error(`PostgreSQL did not accept connections: ${error.message}`);
      Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, 100);
    }
  }
}

/** The temporary directories this test file made, removed when its process exits. */
const made = new Set();
process.on('exit', () => {
  for (const dir of made) rmSync(dir, { recursive: true, force: true });
});

/** A fresh temporary directory, removed with the test file's process. */
export function tempDir() {
  const dir = mkdtempSync(join(tmpdir(), 'estlab-e2e-'));
  made.add(dir);
  return dir;
}

/**
 * Starts `estlab COMMAND ...args` over `dataDir` (its secret and database); resolves once
 * its standard output matches `ready` to { match, process, log(), kill() }: log() is its
 * stderr so far, kill() sends SIGKILL and resolves once it has exited.
 */
function startEstlab(command, dataDir, args, ready) {
  if (!existsSync(estlabBinary)) throw new Error(`${estlabBinary} is not built (cargo build -p estlab)`);
  fixSecret(dataDir);
  const child = spawn(estlabBinary, [command, '--data', dataDir, ...args], {
    stdio: ['ignore', 'pipe', 'pipe'],
    // A grading's line in the log is what the tests count, whatever the shell's RUST_LOG.
    env: { ...withDatabase(dataDir), RUST_LOG: 'warn,estlab=info' },
  });
  child.closed = new Promise((done) => child.once('close', done));
  let stderr = '';
  child.stderr.on('data', (chunk) => { stderr += chunk; });
  return new Promise((resolve, reject) => {
    let stdout = '';
    child.stdout.on('data', (chunk) => {
      stdout += chunk;
      const match = stdout.match(ready);
      if (match) resolve({ match, process: child, log: () => stderr, kill: () => ended(child, 'SIGKILL') });
    });
    child.once('exit', (code) => reject(new Error(`estlab ${command} exited with ${code}: ${stderr}`)));
  });
}

/**
 * Starts `estlab serve` on a free port, its submissions in `dataDir` (a fresh directory
 * unless given); resolves to { url, dataDir, process, stop(), kill() }: stop() as Ctrl-C
 * does, kill() at once (SIGKILL), each resolving once the server has exited.
 */
export async function startServer({ dataDir = tempDir(), args = [] } = {}) {
  const started = await startEstlab('serve', dataDir, ['--addr', '127.0.0.1:0', '--static', staticDir, ...args],
    /serving on (http:\/\/\S+)\//);
  return {
    url: started.match[1],
    dataDir,
    process: started.process,
    stop: () => ended(started.process, 'SIGINT'),
    kill: started.kill,
  };
}

/**
 * Starts `estlab grader` over `dataDir` (its secret, and its database: SQLite's file or,
 * on PostgreSQL, the directory's own); resolves once it grades to { holder, process,
 * log(), stop(), kill() }: log() is its stderr so far (a line per grading), stop() as
 * SIGTERM does, kill() at once (SIGKILL), each resolving once it has exited.
 */
export async function startGrader({ dataDir, args = [] }) {
  const started = await startEstlab('grader', dataDir, args, /estlab grader (\S+) is grading/);
  return {
    holder: started.match[1],
    process: started.process,
    log: started.log,
    stop: () => ended(started.process, 'SIGTERM'),
    kill: started.kill,
  };
}

/** CPU seconds a process and its waited-for children (the sandbox workers) have used. */
export function cpuOf(pid) {
  const stat = readFileSync(`/proc/${pid}/stat`, 'utf8');
  // "pid (comm) state ppid ...": utime, stime, cutime and cstime are fields 14 to 17, in 1/100 s.
  const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
  return fields.slice(11, 15).map(Number).reduce((a, b) => a + b, 0) / 100;
}

/** CPU seconds the whole machine has been busy (every core, every process), from /proc/stat. */
export function machineCpu() {
  // "cpu user nice system idle iowait irq softirq steal ...", in 1/100 s.
  const [user, nice, system, , , irq, softirq, steal] = readFileSync('/proc/stat', 'utf8').split('\n')[0].split(/\s+/).slice(1).map(Number);
  return (user + nice + system + irq + softirq + steal) / 100;
}

/** The value at quantile `q` of `values` (nearest rank). */
export function quantile(values, q) {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1))];
}

/**
 * Options for a test or a hook: the most it may take before it fails. A bound against
 * hanging (node:test has no timeout of its own), generous, not a speed limit.
 */
export const bounded = { timeout: 5 * 60_000 };

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/**
 * Calls `probe` every `interval` ms until `until` holds for what it returns, and returns
 * that. After `timeout` ms it fails with a message naming `what` and the value seen last:
 * a bound against hanging (a grading that never ends), generous, not a speed limit.
 */
export async function waitFor(what, probe, until, { timeout = 120_000, interval = 200 } = {}) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const value = await probe();
    if (until(value)) return value;
    if (Date.now() > deadline) {
      throw new Error(`gave up after ${timeout / 1000} s waiting for ${what}; seen last: ${JSON.stringify(value)?.slice(0, 500)}`);
    }
    await sleep(interval);
  }
}

/**
 * POSTs `body` (an object, or a string sent as it is) as a submission to `server`, as the
 * student signed in with `cookie` (`estlab_session=...`), or nobody.
 */
export function submit(server, body, cookie) {
  return fetch(`${server.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json', ...(cookie ? { cookie } : {}) },
    body: typeof body === 'string' ? body : JSON.stringify(body),
  });
}

/** The submission at `url` (its API path) as `server` has it now. */
export async function submission(server, url) {
  const response = await fetch(server.url + url);
  if (!response.ok) throw new Error(`GET ${url}: ${response.status} ${await response.text()}`);
  return response.json();
}

/**
 * The submission at `url` once `until` holds for it (by default: once it is graded);
 * `what` names what is awaited in the message of a timeout.
 */
export function waitForSubmission(server, url, { until = (s) => s.status === 'graded', what = 'graded', ...options } = {}) {
  return waitFor(`submission ${url} to be ${what}`, () => submission(server, url), until, options);
}

/**
 * Sends `signal` to `child`, unless it has exited; resolves once it has and its output
 * is read to the end (what it wrote before it ended is in its log).
 */
function ended(child, signal) {
  child.closed ??= new Promise((done) => child.once('close', done));
  if (child.exitCode === null && child.signalCode === null) child.kill(signal);
  return child.closed;
}

/** Headless Chromium with the flags this machine needs. */
export function launchBrowser() {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: [
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
  });
}

/**
 * A new page of `browser` (or of a browser context, at the context's size) at the size
 * `viewport`, that records every console error and uncaught exception into
 * `page.problems`, and has opened `url` and waited until its script says it is ready.
 */
export async function openPage(browser, url, viewport = laptop) {
  const page = await browser.newPage({ viewport, acceptDownloads: true });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  // A request the page's own navigation cancelled (ERR_ABORTED: a fetch still under way
  // when a link or a test opens the next page) is not a failure of the page.
  page.on('requestfailed', (request) => {
    if (request.failure()?.errorText !== 'net::ERR_ABORTED') page.problems.push(`request failed: ${request.url()}`);
  });
  await page.goto(url);
  try {
    await page.waitForSelector('body[data-ready=true]', { timeout: 20000 });
  } catch (error) {
    throw new Error(`${url} never got ready: ${error.message}\nwhat went wrong on the page: ${page.problems.join('\n')}`);
  }
  return page;
}

/** Runs `task` on every item with at most `limit` at once; resolves to the results in order. */
export async function mapLimit(items, limit, task) {
  const results = new Array(items.length);
  let next = 0;
  const worker = async () => {
    while (next < items.length) {
      const i = next++;
      results[i] = await task(items[i], i);
    }
  };
  await Promise.all(Array.from({ length: Math.min(limit, items.length) }, worker));
  return results;
}

/** A CSV without embedded quotes or line breaks (what `estlab course roster --out` writes in the tests). */
export function parseCsv(text) {
  const [header, ...rows] = text.trim().split('\n').map((line) => line.split(','));
  return rows.map((row) => Object.fromEntries(header.map((name, i) => [name, row[i]])));
}

/** Replaces the workbench editor's whole text by typing it, as a paste would. */
export async function typeInEditor(page, text) {
  await page.locator('#editor .cm-content').click();
  await page.keyboard.press('Control+A');
  await page.keyboard.press('Delete');
  await page.keyboard.insertText(text);
}

/** Clicks a workbench's `button` and waits until the run it starts has finished. */
export async function runAndWait(page, button, timeout = 120_000) {
  await page.locator(button).click();
  await page.waitForFunction(() => document.getElementById('stop').disabled, null, { timeout });
}

/** What a workbench shows of the test of `key` (a function, a run): passed, failed or not-run. */
export function testStatus(page, key) {
  return page.locator(`#test-${key}`).getAttribute('data-status');
}

/** The points a workbench shows for the browser's verdict. */
export async function browserPoints(page) {
  const text = await page.locator('#score').textContent();
  return Number(text.match(/In your browser: ([\d.]+) of/)[1]);
}

/** `estlab grade --lab LAB` of `text`, saved as `fileName`, for the variant `seed`, as JSON. */
export function gradeOnCommandLine(lab, fileName, text, seed) {
  const file = join(tempDir(), fileName);
  writeFileSync(file, text);
  return JSON.parse(estlab('grade', '--lab', lab, file, '--seed', String(seed)));
}

/** How many points each series of the plot `name` on `page` holds, by the series' id. */
export function plottedPoints(page, name) {
  return page.evaluate((n) => {
    const plot = document.querySelector(`figure[data-name="${n}"] .chart`).plot;
    const count = (data) => data.reduce((sum, item) => sum + (item.coords ? item.coords.length : 1), 0);
    return Object.fromEntries(plot.series().map((s) => [s.id, count(s.data ?? [])]));
  }, name);
}

/** A workbench's file as the page saved it in this browser: the EKF's, or another exercise's (`lab`). */
export function savedFile(page, lab = 'ekf-localization') {
  return page.evaluate((key) => localStorage.getItem(key), `estlab:${lab}:source`);
}

/**
 * The workbench at `path` at a phone's and a laptop's size: no sideways scrolling, its
 * `heading` (the page's title too) and `runButton`, an intro that names every one of
 * `functions` and links the `experiments` page, its `nav` link the current one, the
 * editor and the toolbar on the screen, and no errors.
 */
export async function checkWorkbenchFits(browser, server, { path, heading, runButton, functions, experiments, nav }) {
  for (const size of [phone, laptop]) {
    const page = await openPage(browser, server.url + path, size);
    const what = `${size.width} px`;
    assert.equal(await page.evaluate(() => document.documentElement.scrollWidth), size.width, `${what}: no sideways scrolling`);
    assert.equal(await page.title(), `${heading} · estlab`);
    assert.equal(await page.locator('h1').textContent(), heading);
    assert.equal(await page.locator('#run-datasets').textContent(), runButton);
    for (const name of functions) assert.ok((await page.locator('main p').first().textContent()).includes(name), name);
    assert.equal(await page.locator(`main p a[href="${experiments}"]`).count(), 1, 'the intro links the experiment page');
    assert.equal(await page.locator('nav a[aria-current=page]').textContent(), nav);
    for (const selector of ['.editor', '#run-tests', '#run-datasets', '#submit']) {
      const box = await page.locator(selector).boundingBox();
      assert.ok(box.x >= 0 && box.x + box.width <= size.width, `${what}: ${selector} is on the screen`);
    }
    assert.deepEqual(page.problems, [], what);
    await page.close();
  }
}

/**
 * Runs the tests and the runs of a workbench `page` holding the `starter` file: the test of
 * each of `functions` fails with the "not implemented" it throws, at its line, and the test
 * of each of `runs` fails saying so.
 */
export async function checkStarterFails(page, starter, functions, runs) {
  await runAndWait(page, '#run-tests');
  await runAndWait(page, '#run-datasets');
  const lines = starter.split('\n');
  for (const key of functions) {
    assert.equal(await testStatus(page, key), 'failed', key);
    const line = lines.findIndex((text) => text.includes(`${key}: not implemented`)) + 1;
    assert.match(await page.locator(`#test-${key} .failure .thrown`).first().textContent(),
      new RegExp(`threw Error: ${key}: not implemented \\(line ${line}\\)`), key);
  }
  for (const key of runs) {
    assert.equal(await testStatus(page, key), 'failed', key);
    assert.match(await page.locator(`#test-${key} .message`).textContent(), /not implemented/, key);
  }
}

/** Signs in with a code through the sign-in form's POST; resolves to the session cookie (`estlab_session=...`). */
export async function signIn(server, code) {
  const response = await fetch(`${server.url}/signin`, {
    method: 'POST',
    headers: { 'content-type': 'application/x-www-form-urlencoded' },
    body: new URLSearchParams({ code }),
    redirect: 'manual',
  });
  assert.equal(response.status, 303, `sign-in answered ${response.status}: ${(await response.text()).slice(0, 300)}`);
  const cookie = response.headers.getSetCookie().find((c) => c.startsWith('estlab_session='));
  assert.ok(cookie, 'no session cookie');
  return cookie.split(';')[0];
}

/** GETs an API path with some headers (a cookie, a bearer token); resolves to status and body. */
export async function getJson(server, path, headers) {
  const response = await fetch(server.url + path, { headers });
  return { status: response.status, body: await response.json() };
}

/**
 * A course on `server`'s data directory, set up through the command line: `count`
 * students with ids `prefix` and a number (r001, r002, ...), the exercises `labs` (the
 * EKF's unless named) open until 2030, and an API token of a staff `role`. Resolves to
 * the students with their codes (from the codes file the roster import writes) and the
 * token.
 */
export function setUpCourse(server, { course = 'el2320', title, prefix, count, role, labs = ['ekf-localization'] }) {
  const dir = tempDir();
  const on = ['--data', server.dataDir, '--url', server.url];
  estlab('course', 'create', course, '--title', title, ...on);
  const ids = Array.from({ length: count }, (_, i) => `${prefix}${String(i + 1).padStart(3, '0')}`);
  const roster = join(dir, 'roster.csv');
  writeFileSync(roster, ['id,name,email', ...ids.map((id) => `${id},Student ${id},${id}@example.org`)].join('\n') + '\n');
  const codes = join(dir, 'codes.csv');
  estlab('course', 'roster', course, roster, '--out', codes, ...on);
  for (const lab of labs) estlab('course', 'assign', course, lab, '--due', '2030-01-01T00:00Z', '--data', server.dataDir);
  const token = estlab('course', 'token', course, '--role', role, '--data', server.dataDir).trim().split('\n').at(-1);
  const students = parseCsv(readFileSync(codes, 'utf8'));
  assert.deepEqual(students.map((s) => s.id), ids);
  for (const s of students) assert.ok(s.code, `no code for ${s.id}`);
  return { students, token };
}

/**
 * A new context of `browser` at the size `viewport`, signed in to `server` with `cookie`
 * (`estlab_session=...`; none for nobody), with further context `options` (a time zone).
 */
export async function signedInContext(browser, server, cookie, viewport, options = {}) {
  const context = await browser.newContext({ viewport, ...options });
  if (cookie) {
    const [name, value] = cookie.split('=');
    await context.addCookies([{ name, value, url: server.url }]);
  }
  return context;
}

/**
 * Opens `url` in a new page of `context` and waits until its script says it is ready; the
 * page records its console errors and uncaught exceptions in `page.problems`.
 */
export async function openIn(context, url) {
  const page = await context.newPage();
  page.problems = [];
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  page.on('console', (message) => { if (message.type() === 'error') page.problems.push(`console: ${message.text()}`); });
  await page.goto(url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 60_000 });
  return page;
}

/** The staff's class table as shown: a row per student, by id, of the cells' text by column title. */
export function classTable(page) {
  return page.locator('#class-table').evaluate((table) => {
    const titles = [...table.querySelectorAll('thead th')].map((th) => th.textContent.trim());
    return Object.fromEntries([...table.querySelectorAll('tbody tr')].map((tr) => {
      const cells = [...tr.cells].map((td) => td.textContent.trim());
      return [tr.dataset.student, Object.fromEntries(titles.map((title, i) => [title, cells[i]]))];
    }));
  });
}

/** The screen sizes the layout tests take: a phone held upright, and a laptop. */
export const phone = { width: 390, height: 844 };
export const laptop = { width: 1400, height: 1000 };

/**
 * The secret every server and grader a test starts grades with, unless the test put
 * another in its data directory: what a server draws from it (a submission's hidden
 * cases, a class's held-out trials) is then the same at every run, and so is what a test
 * asserts of it. `scripts/test` checks that no test starts one otherwise.
 */
export const TEST_SECRET = Buffer.alloc(32, 7);

/** Puts TEST_SECRET in `dataDir` unless it holds a secret already. */
function fixSecret(dataDir) {
  const file = join(dataDir, 'secret');
  if (!existsSync(file)) writeFileSync(file, TEST_SECRET, { mode: 0o600 });
}


/**
 * A server and a browser for a whole test file: started before its first test and handed
 * to `use(server, browser)`, stopped after its last; `serverOptions` as startServer takes.
 */
export function withServerAndBrowser(use, serverOptions = {}) {
  let server;
  let browser;
  before(async () => {
    server = await startServer(serverOptions);
    browser = await launchBrowser();
    use(server, browser);
  }, bounded);
  after(async () => {
    await browser?.close();
    await server?.stop();
  }, bounded);
}

const axeSource = readFileSync(createRequire(import.meta.url).resolve('axe-core/axe.min.js'), 'utf8');

/** The serious and critical violations axe finds on `page` as it is now, as readable lines. */
export async function violations(page) {
  await page.evaluate(axeSource);
  const found = await page.evaluate(() => window.axe.run(document, { resultTypes: ['violations'] }).then((r) => r.violations
    .filter((v) => v.impact === 'serious' || v.impact === 'critical')
    .map((v) => `${v.id} (${v.impact}): ${v.help}; ${v.nodes.slice(0, 5).map((n) => n.target.join(' ')).join(' | ')}` +
      (v.nodes.length > 5 ? ` and ${v.nodes.length - 5} more` : ''))));
  return found;
}
