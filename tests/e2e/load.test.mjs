// A course under load, on loopback: its signed-in students (30 here, 200 in
// scripts/bench-load; ESTLAB_LOAD_STUDENTS sets it) submit at about the same time, each
// submits again as soon as their first is graded, and every submission ends graded, with
// its own student, source and seed, in that student's history and nobody else's. Then
// grading cut off by a SIGKILL: every submission made before the kill is there after the
// restart, graded once, and the sessions survived. Times are measured and printed (and
// written to $ESTLAB_LOAD_REPORT for scripts/bench-load), never asserted.
//
// Not 200 students by default: this checks that nothing is lost or mixed up, which a
// small class shows as well as a large one; scripts/bench-load measures the large one.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { test } from 'node:test';
import {
  bounded, correct, cpuOf, getJson, mapLimit, quantile, setUpCourse, signIn, starter, startServer, waitFor,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
/** Gradings at once: one per core of this 2-core machine (the default is one per two). */
const PARALLEL = Number(process.env.ESTLAB_LOAD_PARALLEL ?? 2);
const SERVER_ARGS = ['--parallel', String(PARALLEL)];

/** The starter file: every function throws "not implemented", so it grades quickly. */

/** `source` made unique to a student and a submission by its first line. */
const unique = (student, n, source) => `// student ${student} submission ${n}\n${source}`;

/** Signs every student in, 8 at a time; sets `student.cookie`. */
async function signInAll(server, students) {
  await mapLimit(students, 8, async (student) => { student.cookie = await signIn(server, student.code); });
}

/** POSTs a submission as the student of `cookie`; resolves to its status, body and latency (ms, until the body is read). */
async function post(server, cookie, source) {
  const started = performance.now();
  const response = await fetch(`${server.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json', cookie },
    body: JSON.stringify({ source }),
  });
  const body = await response.json();
  return { status: response.status, body, latency: performance.now() - started };
}

/** Every submission of the course, as its staff sees them (summaries, no sources). */
async function courseSubmissions(server, token) {
  const { status, body } = await getJson(server, `/api/courses/${COURSE}/submissions?lab=${LAB}`, { authorization: `Bearer ${token}` });
  assert.equal(status, 200, JSON.stringify(body));
  return body;
}

/** How many submissions of a list are in each status, for progress and for the message of a timeout. */
function countStatuses(list, started) {
  const counts = { total: list.length, queued: 0, grading: 0, graded: 0, seconds: (performance.now() - started) / 1000 };
  for (const s of list) counts[s.status]++;
  if (process.env.ESTLAB_LOAD_PROGRESS) console.error(JSON.stringify(counts));
  return counts;
}

/** A field of /proc/PID/status in kB (VmRSS, VmHWM). */
function memoryOf(pid, field) {
  return Number(readFileSync(`/proc/${pid}/status`, 'utf8').match(new RegExp(`^${field}:\\s+(\\d+) kB`, 'm'))[1]);
}

/** What a student's submission must be when read back with their own cookie. */
function checkOwn(read, student, id, source, seed) {
  assert.equal(read.status, 200, `${student.id} reading ${id}: ${JSON.stringify(read.body)}`);
  const s = read.body;
  assert.equal(s.id, id);
  assert.equal(s.student, student.id, `submission ${id}`);
  assert.equal(s.course, COURSE);
  assert.equal(s.source, source, `submission ${id} of ${student.id}: another source`);
  assert.equal(s.status, 'graded', `submission ${id}`);
  assert.equal(s.seed, seed, `submission ${id}`);
  assert.ok(s.result, `submission ${id} has no result`);
  assert.equal(s.result.seed, seed, `submission ${id}: graded with another seed`);
  assert.equal(s.result.gradable, true, `submission ${id}: ${s.result.reason}`);
  return s;
}

test('every student of a course submits at once, then again as each first is graded: all graded, none lost or mixed up', bounded, async () => {
  const STUDENTS = Number(process.env.ESTLAB_LOAD_STUDENTS ?? 30);
  const setupStarted = performance.now();
  const server = await startServer({ args: SERVER_ARGS });
  try {
    const { students, token } = setUpCourse(server, { course: COURSE, title: 'Estimation under load', prefix: 'u', count: STUDENTS, role: 'assistant' });
    await signInAll(server, students);
    const setupSeconds = (performance.now() - setupStarted) / 1000;

    const cpuBefore = cpuOf(server.process.pid);
    const started = performance.now();
    const firsts = await Promise.all(students.map((s) => post(server, s.cookie, unique(s.id, 1, starter))));
    const posts = [...firsts];
    firsts.forEach((answer, i) => {
      assert.equal(answer.status, 202, `${students[i].id}'s first submission: ${JSON.stringify(answer.body)}`);
      students[i].submissions = [{ id: answer.body.id, source: unique(students[i].id, 1, starter) }];
      students[i].seed = answer.body.seed;
    });

    // One watcher for the whole course (an assistant's token): as a student's first
    // submission is seen graded, that student submits their second.
    const byId = new Map(students.map((s) => [s.submissions[0].id, s]));
    const seconds = [];
    const refused = [];
    let allGradedAt = null;
    let list = [];
    await waitFor(`all ${2 * STUDENTS} submissions to be graded`, async () => {
      const all = await courseSubmissions(server, token);
      list = all;
      for (const summary of all) {
        const student = byId.get(summary.id);
        if (summary.status === 'graded' && student && !student.second) {
          const source = unique(student.id, 2, starter);
          student.second = post(server, student.cookie, source).then((answer) => {
            posts.push(answer);
            if (answer.status === 202) student.submissions.push({ id: answer.body.id, source });
            else refused.push(`${student.id}'s second submission: ${answer.status} ${JSON.stringify(answer.body)}`);
          }, (error) => refused.push(`${student.id}'s second submission: ${error.message}`));
          seconds.push(student.second);
        }
      }
      assert.deepEqual(refused, [], 'second submissions refused');
      return countStatuses(all, started);
    }, (counts) => counts.total === 2 * STUDENTS && counts.graded === counts.total, { timeout: 270_000, interval: 100 });
    allGradedAt = performance.now();
    const cpuSeconds = cpuOf(server.process.pid) - cpuBefore;
    await Promise.all(seconds);

    // Two submissions a student, each listed once, all graded.
    assert.equal(posts.length, 2 * STUDENTS);
    assert.equal(list.length, 2 * STUDENTS);
    assert.equal(new Set(list.map((s) => s.id)).size, 2 * STUDENTS, 'a submission listed twice');
    const made = students.flatMap((s) => s.submissions.map((x) => x.id)).sort((a, b) => a - b);
    assert.deepEqual(list.map((s) => s.id).sort((a, b) => a - b), made);

    // Every student's own view: their two submissions, their source, their seed; and
    // someone else's submission answers 404.
    const stored = await mapLimit(students, 8, async (student, i) => {
      const me = await getJson(server, '/api/me', { cookie: student.cookie });
      assert.equal(me.status, 200);
      assert.equal(me.body.member.login, student.id);
      assert.equal(me.body.seed, student.seed, `${student.id}: the seed of /api/me and of the submission differ`);
      assert.deepEqual(me.body.assignments[0].history.map((h) => h.id), student.submissions.map((x) => x.id),
        `${student.id}'s history`);
      const reads = [];
      for (const { id, source } of student.submissions) {
        reads.push(checkOwn(await getJson(server, `/api/submissions/${id}`, { cookie: student.cookie }), student, id, source, student.seed));
      }
      const other = students[(i + 1) % students.length];
      const foreign = await getJson(server, `/api/submissions/${other.submissions[0].id}`, { cookie: student.cookie });
      assert.equal(foreign.status, 404, `${student.id} read ${other.id}'s submission: ${JSON.stringify(foreign.body).slice(0, 200)}`);
      return reads;
    });
    const anonymous = await getJson(server, `/api/submissions/${students[0].submissions[0].id}`);
    assert.equal(anonymous.status, 404);

    const latencies = posts.map((p) => p.latency);
    const moments = stored.flat();
    const serverSpan = (Math.max(...moments.map((s) => Date.parse(s.graded_at))) -
      Math.min(...moments.map((s) => Date.parse(s.submitted_at)))) / 1000;
    const report = {
      students: STUDENTS,
      submissions: posts.length,
      parallel: PARALLEL,
      binary: process.env.ESTLAB_BIN ?? 'target/debug/estlab',
      submit_latency_ms: {
        median: quantile(latencies, 0.5), p99: quantile(latencies, 0.99), max: Math.max(...latencies),
        firsts: { median: quantile(latencies.slice(0, STUDENTS), 0.5), p99: quantile(latencies.slice(0, STUDENTS), 0.99) },
        seconds: { median: quantile(latencies.slice(STUDENTS), 0.5), p99: quantile(latencies.slice(STUDENTS), 0.99) },
      },
      first_submit_to_all_graded_s: (allGradedAt - started) / 1000,
      server_first_stored_to_last_graded_s: serverSpan,
      server_cpu_s_per_submission: cpuSeconds / posts.length,
      setup_and_sign_in_s: setupSeconds,
      server_memory_mb: { rss: memoryOf(server.process.pid, 'VmRSS') / 1024, peak: memoryOf(server.process.pid, 'VmHWM') / 1024 },
    };
    console.log(`load: ${report.submissions} submissions of ${STUDENTS} students, --parallel ${PARALLEL}: ` +
      `submit latency median ${report.submit_latency_ms.median.toFixed(1)} ms, p99 ${report.submit_latency_ms.p99.toFixed(1)} ms ` +
      `(max ${report.submit_latency_ms.max.toFixed(1)}; the ${STUDENTS} at once: median ${report.submit_latency_ms.firsts.median.toFixed(1)}, ` +
      `the ${STUDENTS} as firsts are graded: median ${report.submit_latency_ms.seconds.median.toFixed(1)}); all graded ${report.first_submit_to_all_graded_s.toFixed(1)} s after the first submit ` +
      `(server: first stored to last graded ${serverSpan.toFixed(1)} s; ${report.server_cpu_s_per_submission.toFixed(2)} s of CPU per submission, workers included); course set-up and ${STUDENTS} sign-ins ${setupSeconds.toFixed(1)} s; ` +
      `server memory ${report.server_memory_mb.rss.toFixed(0)} MB (peak ${report.server_memory_mb.peak.toFixed(0)} MB)`);
    if (process.env.ESTLAB_LOAD_REPORT) writeFileSync(process.env.ESTLAB_LOAD_REPORT, JSON.stringify(report, null, 2) + '\n');
  } finally {
    await server.stop();
  }
});

test('grading cut off by SIGKILL under load: after the restart every submission is there, graded once, and sessions survive', bounded, async () => {
  const STUDENTS = Number(process.env.ESTLAB_KILL_STUDENTS ?? 12);
  const first = await startServer({ args: SERVER_ARGS });
  let students, token, before;
  try {
    ({ students, token } = setUpCourse(first, { course: COURSE, title: 'Estimation under load', prefix: 'u', count: STUDENTS, role: 'assistant' }));
    await signInAll(first, students);
    const answers = await Promise.all(students.map((s) => post(first, s.cookie, unique(s.id, 1, correct))));
    answers.forEach((answer, i) => {
      assert.equal(answer.status, 202, `${students[i].id}: ${JSON.stringify(answer.body)}`);
      Object.assign(students[i], { id1: answer.body.id, seed: answer.body.seed, source: unique(students[i].id, 1, correct) });
    });
    // Killed while some are graded and the rest wait or are being graded.
    before = await waitFor('some but not all submissions to be graded', () => courseSubmissions(first, token),
      (all) => all.some((s) => s.status === 'graded'), { interval: 50 });
  } finally {
    await first.kill();
  }
  const gradedBefore = before.filter((s) => s.status === 'graded');
  const gradingAtKill = before.filter((s) => s.status === 'grading').length;
  assert.equal(before.length, STUDENTS);
  assert.ok(gradedBefore.length < STUDENTS, 'every submission was graded before the kill: nothing was cut off');

  const second = await startServer({ dataDir: first.dataDir, args: SERVER_ARGS });
  try {
    // The sessions are in the database: the cookies of before the kill still sign in.
    await mapLimit(students, 8, async (student) => {
      const me = await getJson(second, '/api/me', { cookie: student.cookie });
      assert.equal(me.status, 200);
      assert.equal(me.body.member?.login, student.id, `${student.id}'s session did not survive the restart`);
      assert.equal(me.body.seed, student.seed);
    });
    const after = await waitFor('every submission to be graded after the restart', () => courseSubmissions(second, token),
      (all) => all.every((s) => s.status === 'graded'), { interval: 200 });
    assert.equal(after.length, STUDENTS, 'submissions lost or added by the restart');
    assert.equal(new Set(after.map((s) => s.id)).size, STUDENTS);
    assert.deepEqual(after.map((s) => s.id).sort((a, b) => a - b), students.map((s) => s.id1).sort((a, b) => a - b));
    // Graded before the kill: kept as it was, not graded again.
    const scoreAfter = new Map(after.map((s) => [s.id, s.score]));
    for (const s of gradedBefore) assert.equal(scoreAfter.get(s.id), s.score, `submission ${s.id}`);

    await mapLimit(students, 8, async (student) => {
      const me = await getJson(second, '/api/me', { cookie: student.cookie });
      assert.deepEqual(me.body.assignments[0].history.map((h) => h.id), [student.id1], `${student.id}'s history`);
      const s = checkOwn(await getJson(second, `/api/submissions/${student.id1}`, { cookie: student.cookie }),
        student, student.id1, student.source, student.seed);
      assert.equal(s.result.score, 1, `the correct file scored ${s.result.score} (submission ${student.id1})`);
    });
    console.log(`kill: ${STUDENTS} submissions; at the SIGKILL ${gradedBefore.length} graded, ${gradingAtKill} being graded, ` +
      `the other ${STUDENTS - gradedBefore.length - gradingAtKill} waiting; all graded after the restart`);
  } finally {
    await second.stop();
  }
});
