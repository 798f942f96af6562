// estlab on several processes sharing one database, as on several machines: web
// processes that only store submissions (`serve --no-grading`) and grader processes
// (`estlab grader`) that take them under a lease. On SQLite by default (processes of one
// machine share its file); scripts/test runs this file again on PostgreSQL.
//
// Every accepted submission must be graded exactly once (each grader logs a line per
// grading it wrote, and a result is written only under the lease), by whichever grader,
// with each student's history intact; a grader killed mid-grading leaves its work to
// another once the lease runs out; a web process killed mid-request loses nothing it
// answered for. Nothing here asserts how long anything took: the lease is short so that
// the tests are short, and every wait is bounded only against hanging.
//
// scripts/bench-graders runs the first test on a release build with more students, a
// correct file and 1, 2 or 4 graders (ESTLAB_DISTRIBUTED_*), for BENCHMARKS.md.
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { test } from 'node:test';
import {
  bounded, correct, cpuOf, getJson, machineCpu, mapLimit, quantile, setUpCourse, signIn, starter, startGrader, startServer, tempDir,
  waitFor,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
const STUDENTS = Number(process.env.ESTLAB_DISTRIBUTED_STUDENTS ?? 24);
/** The first test's graders and web processes, and the file its students submit. */
const GRADERS = Number(process.env.ESTLAB_DISTRIBUTED_GRADERS ?? 3);
const WEBS = Number(process.env.ESTLAB_DISTRIBUTED_WEBS ?? 2);
const SOURCE = process.env.ESTLAB_DISTRIBUTED_SOURCE === 'correct' ? correct : starter;
/** Seconds a grading is leased (renewed at each third while it runs). */
const LEASE = '3';
const WEB = ['--no-grading'];
const GRADER = ['--parallel', '1', '--lease', LEASE];

/** `source` made unique to a student and a submission by its first line. */
const unique = (student, n, source) => `// student ${student} submission ${n}\n${source}`;

async function post(web, cookie, source) {
  const response = await fetch(`${web.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json', cookie },
    body: JSON.stringify({ source }),
  });
  return { status: response.status, body: await response.json() };
}

async function courseSubmissions(web, token) {
  const { status, body } = await getJson(web, `/api/courses/${COURSE}/submissions?lab=${LAB}`, { authorization: `Bearer ${token}` });
  assert.equal(status, 200, JSON.stringify(body));
  return body;
}

/**
 * Who graded each submission, by the graders' logs: read once the graders have stopped
 * (SIGTERM) and their output is read to the end, since a grader writes its line after
 * its result is in the database.
 */
async function gradings(graders) {
  await Promise.all(graders.map((g) => g.stop()));
  const count = new Map();
  for (const grader of graders) {
    for (const [, id] of grader.log().matchAll(/ graded submission=(\d+) /g)) {
      const by = count.get(Number(id)) ?? [];
      by.push(grader.holder);
      count.set(Number(id), by);
    }
  }
  return count;
}

/** Starts the web processes and graders over one fresh data directory (one secret, one database). */
async function startAll({ webs, graders }) {
  const dataDir = tempDir();
  const web = [await startServer({ dataDir, args: WEB })];
  for (let i = 1; i < webs; i++) web.push(await startServer({ dataDir, args: WEB }));
  const grading = [];
  for (let i = 0; i < graders; i++) grading.push(await startGrader({ dataDir, args: GRADER }));
  return { dataDir, web, grading };
}

async function stopAll({ web, grading }) {
  await Promise.all([...web.map((w) => w.stop()), ...grading.map((g) => g.stop())]);
}

/**
 * A student's own view of their submissions: ids in order, each with its source, seed and
 * result; resolves to the seconds from each one's storing to its grading.
 */
async function checkHistory(web, student) {
  const me = await getJson(web, '/api/me', { cookie: student.cookie });
  const waits = [];
  assert.equal(me.status, 200);
  assert.equal(me.body.member.login, student.id);
  assert.deepEqual(me.body.assignments[0].history.map((h) => h.id), student.submissions.map((s) => s.id), `${student.id}'s history`);
  for (const { id, source } of student.submissions) {
    const read = await getJson(web, `/api/submissions/${id}`, { cookie: student.cookie });
    assert.equal(read.status, 200, `${student.id} reading ${id}`);
    assert.equal(read.body.student, student.id, `submission ${id}`);
    assert.equal(read.body.source, source, `submission ${id} of ${student.id}: another source`);
    assert.equal(read.body.status, 'graded', `submission ${id}`);
    assert.equal(read.body.result.seed, read.body.seed, `submission ${id}: graded with another seed`);
    assert.equal(read.body.result.gradable, true, `submission ${id}: ${read.body.result.reason}`);
    waits.push((Date.parse(read.body.graded_at) - Date.parse(read.body.submitted_at)) / 1000);
  }
  return waits;
}

test(`${WEBS} web processes and ${GRADERS} graders under load: every submission graded exactly once, every history intact`, bounded, async () => {
  const all = await startAll({ webs: WEBS, graders: GRADERS });
  try {
    const [a, b = a] = all.web;
    const { students, token } = setUpCourse(a, { course: COURSE, title: 'Estimation, distributed', prefix: 'd', count: STUDENTS, role: 'assistant' });
    // Each student signs in on one web process and submits there, then submits again on
    // the other (a load balancer sends requests to either): the session is the database's.
    await mapLimit(students, 8, async (s, i) => { s.cookie = await signIn(i % 2 ? b : a, s.code); });
    const cpuBefore = all.grading.map((g) => cpuOf(g.process.pid));
    const machineBefore = machineCpu();
    const started = performance.now();
    for (const round of [1, 2]) {
      const answers = await Promise.all(students.map((s, i) => {
        const web = (i + round) % 2 ? b : a;
        const source = unique(s.id, round, SOURCE);
        return post(web, s.cookie, source).then((answer) => ({ answer, source }));
      }));
      answers.forEach(({ answer, source }, i) => {
        assert.equal(answer.status, 202, `${students[i].id}'s submission ${round}: ${JSON.stringify(answer.body)}`);
        (students[i].submissions ??= []).push({ id: answer.body.id, source });
      });
      await waitFor(`round ${round}'s submissions to be graded`, () => courseSubmissions(a, token),
        (list) => list.length === round * STUDENTS && list.every((s) => s.status === 'graded'), { timeout: 240_000, interval: 250 });
    }
    const seconds = (performance.now() - started) / 1000;
    const cpu = all.grading.map((g, i) => cpuOf(g.process.pid) - cpuBefore[i]).reduce((x, y) => x + y, 0);
    const machine = machineCpu() - machineBefore;
    const list = await courseSubmissions(b, token);
    assert.equal(list.length, 2 * STUDENTS);
    const made = students.flatMap((s) => s.submissions.map((x) => x.id)).sort((x, y) => x - y);
    assert.deepEqual(list.map((s) => s.id).sort((x, y) => x - y), made, 'submissions lost or added');

    const graded = await gradings(all.grading);
    for (const id of made) assert.deepEqual(graded.get(id)?.length, 1, `submission ${id} graded by ${JSON.stringify(graded.get(id))}`);
    assert.equal(graded.size, made.length, 'a grader logged a grading of a submission nobody made');
    const waits = (await mapLimit(students, 8, (s, i) => checkHistory(i % 2 ? a : b, s))).flat();
    const share = all.grading.map((g) => [...graded.values()].filter((by) => by[0] === g.holder).length);
    const report = {
      students: STUDENTS,
      submissions: made.length,
      webs: WEBS,
      graders: GRADERS,
      graded_by_each: share,
      seconds,
      per_second: made.length / seconds,
      grader_cpu_s_per_submission: cpu / made.length,
      machine_cpu_s_per_submission: machine / made.length,
      submit_to_graded_s: { median: quantile(waits, 0.5), p95: quantile(waits, 0.95), max: Math.max(...waits) },
    };
    console.log(`distributed: ${made.length} submissions of ${STUDENTS} students in two rounds through ${WEBS} web process(es), ` +
      `graded by ${GRADERS} grader(s) (${share.join(', ')}) in ${seconds.toFixed(1)} s: ${report.per_second.toFixed(2)} a second, ` +
      `${report.grader_cpu_s_per_submission.toFixed(2)} s of the graders' CPU each (the machine's: ${report.machine_cpu_s_per_submission.toFixed(2)} s); stored to graded median ${report.submit_to_graded_s.median.toFixed(1)} s, ` +
      `p95 ${report.submit_to_graded_s.p95.toFixed(1)} s`);
    if (process.env.ESTLAB_DISTRIBUTED_REPORT) writeFileSync(process.env.ESTLAB_DISTRIBUTED_REPORT, JSON.stringify(report, null, 2) + '\n');
  } finally {
    await stopAll(all);
  }
});

test('a grader killed mid-grading: another takes its work after the lease, each submission graded once', bounded, async () => {
  const all = await startAll({ webs: 1, graders: 1 });
  try {
    const [web] = all.web;
    const { students, token } = setUpCourse(web, { course: COURSE, title: 'Estimation, a grader lost', prefix: 'k', count: 6, role: 'assistant' });
    await mapLimit(students, 8, async (s) => { s.cookie = await signIn(web, s.code); });
    // The second grader starts before the kill: it finds the first one's leases running,
    // and takes their work only once they have run out.
    all.grading.push(await startGrader({ dataDir: all.dataDir, args: GRADER }));
    const [doomed, survivor] = all.grading;
    // Only the doomed grader grades, at first: the survivor is stopped (SIGSTOP) until
    // the kill, so that the doomed one is certain to hold a lease when it dies.
    survivor.process.kill('SIGSTOP');
    for (const s of students) {
      const source = unique(s.id, 1, correct);
      const answer = await post(web, s.cookie, source);
      assert.equal(answer.status, 202, JSON.stringify(answer.body));
      s.submissions = [{ id: answer.body.id, source }];
    }
    // Stopped (SIGSTOP) while the database says it grades, so that it holds a lease when
    // it dies: a grading seen may have ended before the stop, then it goes on and is
    // caught at the next.
    let atKill;
    for (;;) {
      await waitFor('a submission to be being graded', () => courseSubmissions(web, token),
        (list) => list.some((s) => s.status === 'grading') || list.every((s) => s.status === 'graded'), { interval: 50 });
      doomed.process.kill('SIGSTOP');
      atKill = await courseSubmissions(web, token);
      if (atKill.some((s) => s.status === 'grading')) break;
      assert.ok(!atKill.every((s) => s.status === 'graded'), 'every submission was graded before a lease could be cut off');
      doomed.process.kill('SIGCONT');
    }
    await doomed.kill();
    survivor.process.kill('SIGCONT');
    const cutOff = atKill.filter((s) => s.status === 'grading').map((s) => s.id);

    await waitFor('every submission to be graded', () => courseSubmissions(web, token),
      (list) => list.every((s) => s.status === 'graded'), { timeout: 240_000, interval: 250 });
    const graded = await gradings(all.grading);
    for (const s of atKill) {
      const by = graded.get(s.id) ?? [];
      if (s.status === 'graded') {
        // Graded before the kill (its log line may have been cut off with it).
        assert.ok(by.length <= 1 && !by.includes(survivor.holder), `submission ${s.id} graded by ${JSON.stringify(by)}`);
      } else {
        assert.deepEqual(by, [survivor.holder], `submission ${s.id}, ${s.status} at the kill, graded by ${JSON.stringify(by)}`);
      }
    }
    await mapLimit(students, 8, (s) => checkHistory(web, s));
    for (const s of students) {
      const read = await getJson(web, `/api/submissions/${s.submissions[0].id}`, { cookie: s.cookie });
      assert.equal(read.body.result.score, 1, `the correct file of ${s.id} scored ${read.body.result.score}`);
    }
    console.log(`grader killed: ${cutOff.length} submission(s) being graded at the SIGKILL, taken over after the ${LEASE} s lease`);
  } finally {
    await stopAll(all);
  }
});

test('a web process killed mid-request: what it answered for is stored and graded, nothing mixed up', bounded, async () => {
  const all = await startAll({ webs: 2, graders: 1 });
  try {
    const [doomed, other] = all.web;
    const { students, token } = setUpCourse(other, { course: COURSE, title: 'Estimation, a web process lost', prefix: 'w', count: STUDENTS, role: 'assistant' });
    await mapLimit(students, 8, async (s) => { s.cookie = await signIn(other, s.code); });
    // Every student posts to the doomed process at once; it is killed as the first answer
    // comes back, the others in flight.
    const inFlight = students.map((s) => {
      const source = unique(s.id, 1, starter);
      return post(doomed, s.cookie, source).then((answer) => ({ answer, source }), (error) => ({ error, source }));
    });
    await Promise.race(inFlight);
    await doomed.kill();
    const outcomes = await Promise.all(inFlight);
    const answered = outcomes.filter((o) => o.answer?.status === 202).length;

    // Those answered are stored; those not may or may not be (the kill came before or
    // after the database's commit): all that is stored gets graded, and belongs to its student.
    await waitFor('every stored submission to be graded', () => courseSubmissions(other, token),
      (list) => list.every((s) => s.status === 'graded'), { timeout: 240_000, interval: 250 });
    const stored = await courseSubmissions(other, token);
    students.forEach((s, i) => {
      const mine = stored.filter((x) => x.student === s.id);
      assert.ok(mine.length <= 1, `${s.id} has ${mine.length} submissions`);
      const { answer, source } = outcomes[i];
      if (answer?.status === 202) {
        assert.deepEqual(mine.map((x) => x.id), [answer.body.id], `${s.id}'s answered submission`);
      }
      s.submissions = mine.map((x) => ({ id: x.id, source }));
    });
    // The other web process serves every student, and takes their next submission.
    await mapLimit(students, 8, async (s) => {
      await checkHistory(other, s);
      const source = unique(s.id, 2, starter);
      const answer = await post(other, s.cookie, source);
      assert.equal(answer.status, 202, `${s.id}: ${JSON.stringify(answer.body)}`);
      s.submissions.push({ id: answer.body.id, source });
    });
    await waitFor('the next submissions to be graded', () => courseSubmissions(other, token),
      (list) => list.every((s) => s.status === 'graded'), { timeout: 240_000, interval: 250 });
    await mapLimit(students, 8, (s) => checkHistory(other, s));
    const graded = await gradings(all.grading);
    for (const s of students) for (const { id } of s.submissions) assert.equal(graded.get(id)?.length, 1, `submission ${id}`);
    console.log(`web killed: of ${STUDENTS} submissions in flight, ${answered} answered 202 before the SIGKILL, ` +
      `${stored.length} stored; all graded once`);
  } finally {
    all.web = all.web.slice(1);
    await stopAll(all);
  }
});

test('a web process killed while it makes a report\'s runs: another makes them once its lease has run out', bounded, async () => {
  const dataDir = tempDir();
  const args = [...WEB, '--lease', LEASE];
  const all = { web: [await startServer({ dataDir, args }), await startServer({ dataDir, args })], grading: [] };
  all.grading.push(await startGrader({ dataDir, args: GRADER }));
  try {
    const [doomed, other] = all.web;
    const { students: [student], token } = setUpCourse(other, { course: COURSE, title: 'Estimation, a report', prefix: 'r', count: 1, role: 'assistant' });
    student.cookie = await signIn(other, student.code);
    const answer = await post(other, student.cookie, correct);
    assert.equal(answer.status, 202, JSON.stringify(answer.body));
    await waitFor('the submission to be graded', () => courseSubmissions(other, token),
      (list) => list.every((s) => s.status === 'graded'), { timeout: 240_000, interval: 250 });
    const runs = (web) => getJson(web, `/api/courses/${COURSE}/labs/${LAB}/report/runs`, { cookie: student.cookie });

    // The doomed process begins making the runs (under its lease) and dies.
    const begun = await runs(doomed);
    assert.equal(begun.status, 200, JSON.stringify(begun.body));
    await doomed.kill();
    const states = [begun.body.state];
    const made = await waitFor('the other web process to make the runs', async () => {
      const read = await runs(other);
      assert.equal(read.status, 200, JSON.stringify(read.body));
      states.push(read.body.state);
      return read.body;
    }, (body) => body.state === 'made' || body.state === 'failed', { timeout: 240_000, interval: 500 });
    assert.equal(made.state, 'made', `the runs: ${JSON.stringify(made).slice(0, 300)}`);
    assert.equal(made.submission, answer.body.id);
    console.log(`report's runs: asked of the doomed process (${begun.body.state}), then of the other: ${[...new Set(states.slice(1))].join(' then ')}`);
  } finally {
    all.web = all.web.slice(1);
    await stopAll(all);
  }
});
