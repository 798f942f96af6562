// Measures how much flooding students delay everyone else's grading (scripts/bench-fair):
// the real server with its defaults, a course with both exercises open; each flooding
// student keeps a file in every exercise waiting whose every function is an endless loop
// (every phase runs to its limit), submitting again as soon as one is graded; honest
// students meanwhile submit the correct EKF file, one at a time each, a few seconds apart.
// The honest students' times from stored to graded (the server's `submitted_at` to
// `graded_at`) are reported for 0, 1 and 5 flooding students. Measurements only: nothing
// is asserted.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { correct, root, setUpCourse, signIn, startServer } from '../e2e/harness.mjs';

const SECONDS = Number(process.env.ESTLAB_FAIR_SECONDS ?? 60);
const HONEST = Number(process.env.ESTLAB_FAIR_HONEST ?? 6);
const FLOODERS = (process.env.ESTLAB_FAIR_FLOODERS ?? '0,1,5').split(',').map(Number);
/** An honest student's pause between a result and their next submission. */
const PAUSE_MS = 4000;
const LABS = ['ekf-localization', 'odometry'];

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
/** Every function of a file made an endless loop. */
const looping = (source) => source.replace(/^function (\w+)\(([^)]*)\) \{/gm, 'function $1($2) { for (;;) {}');
const floods = {
  'ekf-localization': looping(correct),
  odometry: looping(readFileSync(join(root, 'tests', 'student', 'odometry', 'correct.js'), 'utf8')),
};

function quantile(values, q) {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1))];
}

async function post(server, cookie, lab, source) {
  const response = await fetch(`${server.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json', cookie },
    body: JSON.stringify({ source, lab }),
  });
  return { status: response.status, body: await response.json() };
}

/** Polls a submission until it is graded; resolves to it (to nothing once the scenario stops). */
async function graded(server, cookie, id, stopped = () => false) {
  while (!stopped()) {
    const response = await fetch(`${server.url}/api/submissions/${id}`, { headers: { cookie } });
    const body = await response.json();
    if (body.status === 'graded') return body;
    await sleep(100);
  }
}

async function scenario(flooders) {
  const server = await startServer();
  try {
    const { students } = setUpCourse(server, { title: 'Fair under load', prefix: 'f', count: flooders + HONEST, role: 'assistant', labs: LABS });
    for (const s of students) s.cookie = await signIn(server, s.code);
    const [floodingStudents, honestStudents] = [students.slice(0, flooders), students.slice(flooders)];
    const end = performance.now() + SECONDS * 1000;
    let floodGradings = 0;
    let stopping = false;
    const flooding = floodingStudents.flatMap((s) => LABS.map(async (lab) => {
      while (performance.now() < end) {
        const answer = await post(server, s.cookie, lab, `// ${s.id} ${floodGradings}\n${floods[lab]}`);
        if (answer.status !== 202) throw new Error(`${s.id}'s flood: ${answer.status} ${JSON.stringify(answer.body)}`);
        if (await graded(server, s.cookie, answer.body.id, () => stopping)) floodGradings++;
      }
    }));
    // The honest students start a moment after the flood: a flooder's first files are
    // not yet known to run long.
    await sleep(1000);
    const times = [];
    const honest = honestStudents.map(async (s, i) => {
      await sleep(i * (PAUSE_MS / HONEST));
      let n = 0;
      while (performance.now() < end) {
        const answer = await post(server, s.cookie, 'ekf-localization', `// ${s.id} ${n++}\n${correct}`);
        if (answer.status === 429) break;
        if (answer.status !== 202) throw new Error(`${s.id}: ${answer.status} ${JSON.stringify(answer.body)}`);
        const done = await graded(server, s.cookie, answer.body.id);
        if (!done.result.gradable || done.result.score !== 1) throw new Error(`${s.id}'s correct file: ${JSON.stringify(done.result).slice(0, 300)}`);
        times.push((Date.parse(done.graded_at) - Date.parse(done.submitted_at)) / 1000);
        await sleep(PAUSE_MS);
      }
    });
    await Promise.all(honest);
    // The flooders' last files are left to the server's stop.
    stopping = true;
    await Promise.all(flooding);
    return { flooders, times, floodGradings };
  } finally {
    await server.stop();
  }
}

const machine = `${execFileSync('nproc', { encoding: 'utf8' }).trim()} cores (${execFileSync('lscpu', { encoding: 'utf8' }).match(/^Model name:\s*(.*)$/m)[1]}), ` +
  `Linux ${execFileSync('uname', ['-r'], { encoding: 'utf8' }).trim()}, load average before ${readFileSync('/proc/loadavg', 'utf8').split(' ').slice(0, 3).join(' ')}`;
const results = [];
for (const flooders of FLOODERS) {
  const result = await scenario(flooders);
  console.error(`${flooders} flooding: ${result.times.length} honest gradings, median ${quantile(result.times, 0.5).toFixed(2)} s`);
  results.push(result);
}
console.log(`${new Date().toISOString().slice(0, 10)}, ${machine}; ${SECONDS} s a scenario, ${HONEST} honest students a ${PAUSE_MS / 1000} s pause apart\n`);
console.log('| flooding students | honest gradings | stored to graded, median | p90 | max | flood gradings ended |');
console.log('| ---: | ---: | ---: | ---: | ---: | ---: |');
const quiet = quantile(results[0].times, 0.5);
for (const { flooders, times, floodGradings } of results) {
  const median = quantile(times, 0.5);
  console.log(`| ${flooders} | ${times.length} | ${median.toFixed(2)} s (${(median / quiet).toFixed(1)} × quiet) | ${quantile(times, 0.9).toFixed(2)} s | ${Math.max(...times).toFixed(2)} s | ${floodGradings} |`);
}
