// A grade that means what it says, through the real server: a lookup table of every case a
// student can know earns nothing on the hidden cases, a second submission waits for the
// first, and the same file gets the same score alone and beside endless loops on a
// machine busy with other work (limits are CPU time of the student's own engine).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, readdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { bounded, estlab, root, startServer, submit, tempDir, waitFor, waitForSubmission } from './harness.mjs';

const correct = readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8');
const PUBLIC_SEED = 2320;

/** The key of a call's arguments in the table: every number to 12 digits. */
function keyOf(args) {
  const numbers = [];
  const walk = (value) => {
    if (Array.isArray(value)) value.forEach(walk);
    else numbers.push(value === 'Infinity' ? Infinity : value);
  };
  walk(args);
  return numbers.map((x) => (typeof x === 'number' ? x.toPrecision(12) : String(x))).join(',');
}

/**
 * A student file that is nothing but a table: every case of `seeds` (as `estlab cases`
 * prints them, which is all a student can know besides their results) answered from it.
 */
function lookupTable(seeds) {
  const table = {};
  for (const seed of seeds) {
    for (const c of JSON.parse(estlab('cases', '--seed', String(seed), '--per-function', '6'))) {
      (table[c.function] ??= {})[keyOf(Object.values(c.args))] = c.expected;
    }
  }
  const functions = Object.keys(table).map((name) =>
    `function ${name}(...args) { return TABLE[${JSON.stringify(name)}][keyOf(args)]; }`);
  return [`const TABLE = ${JSON.stringify(table)};`, `const keyOf = ${keyOf.toString()};`, ...functions].join('\n');
}

/** Every function's test of a result, by function name. */
function functionTests(result) {
  return result.tests.filter((t) => /^\w+: \d+ cases$/.test(t.name));
}

test('a lookup table of every shown case earns nothing on the hidden cases, and a second submission waits for the first', bounded, async () => {
  const server = await startServer();
  try {
    // The first submission tells the student their seed and shows their failures.
    const first = await (await submit(server, { student: 'table', source: '// nothing yet\n' })).json();
    const busy = await submit(server, { student: 'table', source: correct });
    assert.equal(busy.status, 409);
    assert.match((await busy.json()).error, new RegExp(`your submission ${first.id} is still waiting to be graded or being graded`));
    const graded = await waitForSubmission(server, first.url);
    assert.equal(graded.result.gradable, true);
    assert.equal(graded.result.hidden_cases, true);

    const table = lookupTable([PUBLIC_SEED, first.seed]);
    // On the command line, which knows no secret, the table passes every function.
    const file = join(tempDir(), 'table.js');
    writeFileSync(file, table);
    const local = JSON.parse(estlab('grade', file, '--seed', String(first.seed)));
    assert.equal(local.hidden_cases, false);
    for (const t of functionTests(local)) assert.equal(t.status, 'passed', `${t.name}: ${t.message}`);
    const response = await submit(server, { student: 'table', source: table });
    assert.equal(response.status, 202);
    const second = await waitForSubmission(server, (await response.json()).url);
    const result = second.result;
    assert.equal(result.gradable, true);
    for (const t of functionTests(result)) {
      assert.match(t.message, /^12 of 12 shown cases and \d+ of 6 hidden cases pass/, t.name);
      assert.doesNotMatch(t.message, /and 6 of 6 hidden/, t.name);
      for (const failure of t.failures.filter((f) => f.hidden)) {
        assert.equal(failure.args, null);
        assert.equal(failure.expected, null);
        assert.equal(failure.got, undefined);
      }
    }
    assert.ok(result.score < 0.1, `a lookup table scored ${result.score}`);
  } finally {
    await server.stop();
  }
});

/** correct.js made slow: `init`, called once per data-set run, first spends about half of
 * the run's CPU time limit on busy work (about 2 s on this machine's kind). */
const slow = correct.replace(/function init\(([^)]*)\) \{/,
  "function init($1) {\n  let s = 0; for (let i = 0; i < 70000000; i++) s += i & 7; if (s < 0) throw new Error('never');");
/** correct.js with an endless loop in `batch_update`: its test and the batch run run to
 * their limits. */
const looping = correct.replace(/function batch_update\(([^)]*)\) \{/, 'function batch_update($1) { for (;;) {}');

/** Processes that keep `n` cores busy until stopped. */
function burners(n) {
  const children = Array.from({ length: n }, () =>
    spawn(process.execPath, ['-e', 'for (;;) {}'], { stdio: 'ignore' }));
  return () => Promise.all(children.map((child) => new Promise((done) => {
    if (child.exitCode !== null || child.signalCode !== null) return done();
    child.once('exit', done);
    child.kill('SIGKILL');
  })));
}

/** What a result says, test by test, without the timings and seeds that differ. */
const verdicts = (result) => result.tests.map((t) => `${t.name}: ${t.status} ${t.points}`);

/**
 * How long the busy part may take: the slow file runs in the background lane at nice 10
 * beside two processes at nice 0 that keep both cores busy, so it gets a tenth of a core
 * or less; a bound against hanging, not a speed limit (the clean-clone CI run once took
 * over 120 s here).
 */
const BUSY = 10 * 60_000;

test('the same file gets the same score alone and beside four endless loops on a busy machine', { timeout: 2 * BUSY }, async () => {
  assert.notEqual(slow, correct);
  assert.notEqual(looping, correct);
  const server = await startServer({ args: ['--parallel', '2'] });
  let stopBurners = null;
  try {
    const alone = await (await submit(server, { student: 'slow', source: slow })).json();
    const aloneResult = (await waitForSubmission(server, alone.url)).result;
    assert.equal(aloneResult.score, 1, verdicts(aloneResult).join('\n'));

    stopBurners = burners(2);
    const busy = await (await submit(server, { student: 'slow', source: slow })).json();
    const loops = [];
    for (let i = 1; i <= 4; i++) {
      const response = await submit(server, { student: `loop${i}`, source: looping });
      assert.equal(response.status, 202);
      loops.push(await response.json());
    }
    const busyResult = (await waitForSubmission(server, busy.url, { timeout: BUSY })).result;
    const loopResults = [];
    for (const loop of loops) loopResults.push((await waitForSubmission(server, loop.url, { timeout: BUSY })).result);
    await stopBurners();
    stopBurners = null;

    assert.deepEqual(verdicts(busyResult), verdicts(aloneResult));
    assert.equal(busyResult.score, aloneResult.score);
    for (const result of loopResults) {
      assert.equal(result.gradable, true);
      const batch = result.tests.find((t) => t.name.startsWith('batch_update:'));
      assert.match(batch.message, /Stopped after 2 s, the time limit/);
      assert.equal(result.tests.filter((t) => t.status === 'failed').length, 2, verdicts(result).join('\n'));
    }
  } finally {
    await stopBurners?.();
    await server.stop();
  }
});

/** A field of /proc/PID/status in kB (VmRSS, VmHWM), or null when the process is gone. */
function memoryOf(pid, field) {
  try {
    const status = readFileSync(`/proc/${pid}/status`, 'utf8');
    return Number(status.match(new RegExp(`^${field}:\\s+(\\d+) kB`, 'm'))[1]);
  } catch {
    return null;
  }
}

/** The processes whose parent is `pid`. */
function childrenOf(pid) {
  return readdirSync('/proc').filter((name) => /^\d+$/.test(name)).filter((name) => {
    try {
      // /proc/PID/stat: "pid (comm) state ppid ...", comm may hold spaces.
      const stat = readFileSync(`/proc/${name}/stat`, 'utf8');
      return Number(stat.slice(stat.lastIndexOf(')') + 2).split(' ')[1]) === pid;
    } catch {
      return false;
    }
  }).map(Number);
}

const HOSTILE = {
  'tampering setters': "Object.defineProperty(Object.prototype, 'error', { set(v) {}, configurable: true });\n",
  'a 1e300 heading': correct.replace('wrap(mu[2] + u[2])];', 'wrap(mu[2] + u[2]) + 1e300];'),
  'huge outputs': ['calculate_odometry', 'predict', 'observation_model', 'jacobian_observation_model',
    'associate', 'batch_associate', 'update', 'batch_update']
    .map((name) => `function ${name}() { return new Array(15000).fill(1.5); }`).join('\n'),
  'a top-level loop': 'for (;;) {}',
  'an allocation bomb': correct + '\nfunction predict() { const a = []; for (;;) a.push(new Float64Array(1 << 20)); }\n',
  'an endless loop': looping,
};

test('hostile files graded side by side: the server answers meanwhile, its memory and its results stay small', bounded, async () => {
  const server = await startServer({ args: ['--parallel', '2'] });
  try {
    const urls = [];
    for (const [name, source] of Object.entries(HOSTILE)) {
      const response = await submit(server, { student: name, source });
      assert.equal(response.status, 202, name);
      urls.push([name, (await response.json()).url]);
    }
    // While they are graded, every request is answered.
    let answered = 0;
    const done = () => Promise.all(urls.map(([, url]) => fetch(server.url + url).then((r) => r.json())))
      .then((all) => all.every((s) => s.status === 'graded'));
    while (!(await done())) {
      const page = await fetch(`${server.url}/ekf/code`);
      assert.equal(page.status, 200);
      answered++;
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
    assert.ok(answered > 0);
    for (const [name, url] of urls) {
      const { result } = await waitForSubmission(server, url);
      assert.equal(result.gradable, true, `${name}: ${result.reason}`);
      assert.ok(result.score < 1, name);
      const size = JSON.stringify(result).length;
      assert.ok(size < 16 << 10, `${name}: a stored result of ${size} bytes`);
    }
    const peak = memoryOf(server.process.pid, 'VmHWM');
    assert.ok(peak !== null && peak < 200 << 10, `the server's memory peaked at ${peak} kB`);
    const database = statSync(join(server.dataDir, 'estlab.sqlite3')).size +
      (existsSync(join(server.dataDir, 'estlab.sqlite3-wal')) ? statSync(join(server.dataDir, 'estlab.sqlite3-wal')).size : 0);
    assert.ok(database < 4 << 20, `the database holds ${database} bytes`);
  } finally {
    await server.stop();
  }
});

/** correct.js with an endless loop in every function: its worker would run for about
 * 18 s after the load check (every phase to its limit, on two engines). */
const loopingEverywhere = correct.replace(/function (\w+)\(([^)]*)\) \{/g, 'function $1($2) { for (;;) {}');

test('sandbox workers die with the server, even when it is killed', bounded, async () => {
  assert.notEqual(loopingEverywhere, correct);
  const server = await startServer();
  const { url } = await (await submit(server, { student: 'orphan', source: loopingEverywhere })).json();
  let workers = [];
  try {
    await waitForSubmission(server, url, { until: (s) => s.status === 'grading', what: 'being graded' });
    workers = await waitFor('a sandbox worker', () => childrenOf(server.process.pid), (pids) => pids.length > 0);
  } finally {
    await server.kill();
  }
  // At once, by the kernel (PR_SET_PDEATHSIG); without it the worker would go on for
  // many seconds more, its phases running to their limits before its write fails.
  await waitFor('the workers to end with the server', () => workers.filter((pid) => memoryOf(pid, 'VmRSS') !== null),
    (alive) => alive.length === 0, { timeout: 8_000 });
});
