// A regrade of a whole assignment killed halfway (issue 11): a course of students who
// each submit files one after another, each graded before the next; the instructor
// regrades the assignment through the staff API; the server is killed with SIGKILL once
// half of it is done, restarted on the same data directory, and the regrade finishes with
// every submission regraded exactly once: one earlier result kept per submission, the
// current one by the regrade's grader, no score changed.
//
// 100 submissions by default: 20 students, 5 files each (the starter file with a unique
// first line: every function throws, so the student's code costs milliseconds; drawing
// each grading's plan and starting its worker cost the rest). A small class shows that
// nothing is lost or regraded twice as well as a large one; the figure, 500
// (ESTLAB_REGRADE_STUDENTS=50 ESTLAB_REGRADE_SUBMISSIONS=10), took 1.7 minutes with the
// debug build at a load average of about 3.5 (2026-11-30), 2.9 with the release build
// (ESTLAB_BIN=target/release/estlab) at about 7.
// Times are printed, never asserted; the waits are bounds against hanging.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { getJson, mapLimit, setUpCourse, signIn, starter, startServer, waitFor } from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
const STUDENTS = Number(process.env.ESTLAB_REGRADE_STUDENTS ?? 20);
const PER_STUDENT = Number(process.env.ESTLAB_REGRADE_SUBMISSIONS ?? 5);
const TOTAL = STUDENTS * PER_STUDENT;
/** Students submitting at once (each one file after another). */
const AT_ONCE = 10;
/** Gradings at once: one per core of this 2-core machine (regrades go one at a time whatever it is). */
const SERVER_ARGS = ['--parallel', '2'];
/** The bound on the whole test and on each long wait: against hanging, not a speed limit. */
const BOUND = 20 * 60_000;

/** The starter file made unique to a student and a submission by its first line. */
const quick = (student, n) => `// ${student}, submission ${n}\n${starter}`;

/** The regrade at `url` as the instructor sees it. */
async function regradeAt(server, url, token) {
  const { status, body } = await getJson(server, url, { authorization: `Bearer ${token}` });
  assert.equal(status, 200, `GET ${url}: ${JSON.stringify(body)}`);
  return body;
}

/** Signs a student in and submits their files one after another, each once graded; resolves to the ids. */
async function submitAll(server, student) {
  const cookie = await signIn(server, student.code);
  const ids = [];
  for (let n = 1; n <= PER_STUDENT; n++) {
    const response = await fetch(`${server.url}/api/submissions`, {
      method: 'POST',
      headers: { 'content-type': 'application/json', cookie },
      body: JSON.stringify({ source: quick(student.id, n) }),
    });
    const body = await response.json();
    assert.equal(response.status, 202, `${student.id}'s submission ${n}: ${JSON.stringify(body)}`);
    await waitFor(`${student.id}'s submission ${n} (${body.url}) to be graded`,
      () => getJson(server, body.url, { cookie }),
      (read) => read.status === 200 && read.body.status === 'graded',
      { timeout: BOUND, interval: 100 });
    ids.push(body.id);
  }
  return ids;
}

test(`a regrade of ${TOTAL} submissions killed with SIGKILL halfway finishes after a restart, every submission regraded once`, { timeout: BOUND }, async () => {
  const started = performance.now();
  const seconds = () => ((performance.now() - started) / 1000).toFixed(1);
  const first = await startServer({ args: SERVER_ARGS });
  let students, token, ids, regrade, seenBeforeKill;
  let submittedAt, killedAt;
  try {
    ({ students, token } = setUpCourse(first, { course: COURSE, title: 'Applied Estimation', prefix: 'r', count: STUDENTS, role: 'instructor' }));
    ids = (await mapLimit(students, AT_ONCE, (student) => submitAll(first, student))).flat();
    submittedAt = seconds();
    assert.equal(new Set(ids).size, TOTAL);

    const response = await fetch(`${first.url}/api/courses/${COURSE}/regrades`, {
      method: 'POST',
      headers: { 'content-type': 'application/json', authorization: `Bearer ${token}` },
      body: JSON.stringify({ scope: { kind: 'assignment' } }),
    });
    regrade = await response.json();
    assert.equal(response.status, 202, JSON.stringify(regrade));
    assert.equal(regrade.total, TOTAL);

    // Halfway: some items done, not all (a regrade goes one item at a time).
    seenBeforeKill = await waitFor('the regrade to be halfway', () => regradeAt(first, regrade.url, token),
      (r) => r.done >= TOTAL / 2, { timeout: BOUND, interval: 100 });
    assert.ok(seenBeforeKill.done < TOTAL && seenBeforeKill.finished_at === null,
      `the regrade finished before the kill: ${JSON.stringify({ ...seenBeforeKill, changed: undefined })}`);
  } finally {
    await first.kill();
    killedAt = seconds();
  }

  const second = await startServer({ dataDir: first.dataDir, args: SERVER_ARGS });
  try {
    const resumedFrom = (await regradeAt(second, regrade.url, token)).done;
    assert.ok(resumedFrom < TOTAL, 'the regrade was finished at the restart: nothing was cut off');
    const finished = await waitFor('the regrade to finish after the restart', () => regradeAt(second, regrade.url, token),
      (r) => r.finished_at !== null, { timeout: BOUND, interval: 250 });
    assert.equal(finished.total, TOTAL);
    assert.equal(finished.done, TOTAL);
    assert.equal(finished.scope, 'assignment');
    // The same files under the same grader: no score changed.
    assert.deepEqual(finished.changed, []);

    // Every submission regraded exactly once: one earlier result, the current one by the regrade's grader.
    const auth = { authorization: `Bearer ${token}` };
    await mapLimit(ids, 8, async (id) => {
      const { status, body } = await getJson(second, `/api/submissions/${id}`, auth);
      assert.equal(status, 200, `submission ${id}: ${JSON.stringify(body).slice(0, 300)}`);
      assert.equal(body.status, 'graded', `submission ${id}`);
      assert.equal(body.earlier?.length, 1,
        `submission ${id} has ${body.earlier?.length ?? 0} earlier results: ${JSON.stringify(body.earlier?.map((e) => e.graded_at))}`);
      assert.equal(body.grader, finished.grader, `submission ${id}'s grader`);
      assert.equal(body.earlier[0].replaced_by, regrade.id, `submission ${id}: replaced by another regrade`);
      assert.equal(body.earlier[0].score, body.score, `submission ${id}: the regrade changed the score`);
    });
    // Nothing was added or lost.
    const { status, body: list } = await getJson(second, `/api/courses/${COURSE}/submissions?lab=${LAB}`, auth);
    assert.equal(status, 200);
    assert.deepEqual(list.map((s) => s.id).sort((a, b) => a - b), [...ids].sort((a, b) => a - b));

    console.log(`regrade: ${STUDENTS} students x ${PER_STUDENT} submissions graded ${submittedAt} s after the start; ` +
      `SIGKILL at ${seenBeforeKill.done} of ${TOTAL} regraded (${killedAt} s), resumed from ${resumedFrom}; ` +
      `all ${TOTAL} regraded once ${seconds()} s after the start`);
  } finally {
    await second.stop();
  }
});
