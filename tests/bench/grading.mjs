// Measures grading on the real server (scripts/bench-grading): a correct submission from
// stored to graded, hidden cases included; the hostile files of the integrity tests side by
// side, with the server's peak memory and the size of every stored result. Prints a
// Markdown report for BENCHMARKS.md. Measurements only: nothing here is asserted.
import { readFileSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { root, startServer, submit, waitForSubmission } from '../e2e/harness.mjs';

const correct = readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8');
/** Each exercise's correct file, by the exercise's name. */
const correctFiles = {
  'ekf-localization': correct,
  odometry: readFileSync(join(root, 'tests', 'student', 'odometry', 'correct.js'), 'utf8'),
};
const ROUNDS = 10;

const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
};

/** Peak resident memory of a process, in MB (VmHWM). */
function peakMemory(pid) {
  const status = readFileSync(`/proc/${pid}/status`, 'utf8');
  return Number(status.match(/^VmHWM:\s+(\d+) kB/m)[1]) / 1024;
}

const looping = correct.replace(/function batch_update\(([^)]*)\) \{/, 'function batch_update($1) { for (;;) {}');
const hostile = {
  'setters on Object.prototype': "Object.defineProperty(Object.prototype, 'error', { set(v) {}, configurable: true });\n",
  'a heading of 1e300': correct.replace('wrap(mu[2] + u[2])];', 'wrap(mu[2] + u[2]) + 1e300];'),
  'every function returns 15,000 numbers': ['calculate_odometry', 'predict', 'observation_model',
    'jacobian_observation_model', 'associate', 'batch_associate', 'update', 'batch_update']
    .map((name) => `function ${name}() { return new Array(15000).fill(1.5); }`).join('\n'),
  'for (;;) {} at the top level': 'for (;;) {}',
  'an allocation bomb in predict': `${correct}\nfunction predict() { const a = []; for (;;) a.push(new Float64Array(1 << 20)); }\n`,
  'an endless loop in batch_update': looping,
  'the right shapes with wrong numbers everywhere': wrongEverywhere(),
};

/** correct.js with every function's answer nudged: every case fails, in detail. */
function wrongEverywhere() {
  const names = ['calculate_odometry', 'predict', 'observation_model', 'jacobian_observation_model',
    'associate', 'batch_associate', 'update', 'batch_update'];
  let source = correct;
  for (const name of names) source = source.replace(`function ${name}(`, `function original_${name}(`);
  return `${source}
function nudge(v) {
  if (typeof v === 'number') return v * 1.01 + 1e-3;
  if (typeof v === 'boolean') return !v;
  if (Array.isArray(v)) return v.map(nudge);
  return Object.fromEntries(Object.entries(v).map(([k, x]) => [k, nudge(x)]));
}
${names.map((name) => `function ${name}(...args) { return nudge(original_${name}(...args)); }`).join('\n')}
`;
}

async function main() {
  const server = await startServer();
  const lines = [];
  try {
    for (const [lab, source] of Object.entries(correctFiles)) {
      const seconds = [];
      for (let i = 0; i < ROUNDS; i++) {
        const { url } = await (await submit(server, { student: `bench-${i}`, source, lab })).json();
        const graded = await waitForSubmission(server, url, { interval: 20 });
        if (graded.result.score !== 1) throw new Error(`the correct ${lab} file scored ${graded.result.score}`);
        seconds.push((Date.parse(graded.graded_at) - Date.parse(graded.submitted_at)) / 1000);
      }
      lines.push(`| a correct ${lab} submission, stored to graded, hidden cases included (median of ${ROUNDS}) | ${median(seconds).toFixed(2)} s (${Math.min(...seconds).toFixed(2)} to ${Math.max(...seconds).toFixed(2)}) |`);
    }

    const urls = [];
    for (const [name, source] of Object.entries(hostile)) {
      const { url } = await (await submit(server, { student: name, source })).json();
      urls.push([name, url]);
    }
    for (const [name, url] of urls) {
      const graded = await waitForSubmission(server, url, { timeout: 600_000 });
      const seconds = (Date.parse(graded.graded_at) - Date.parse(graded.submitted_at)) / 1000;
      lines.push(`| ${name}: ${graded.result.points} points, stored result ${JSON.stringify(graded.result).length} bytes | ${seconds.toFixed(1)} s from stored to graded (queued behind the others) |`);
    }
    lines.push(`| the server's peak memory (VmHWM) after all of them | ${peakMemory(server.process.pid).toFixed(0)} MB |`);
    lines.push(`| the database after all of them | ${(statSync(join(server.dataDir, 'estlab.sqlite3')).size / 1024).toFixed(0)} KB (+ WAL) |`);
  } finally {
    await server.stop();
  }
  console.log(['| what | measured |', '| --- | ---: |', ...lines].join('\n'));
}

await main();
