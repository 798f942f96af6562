// Submissions over HTTP: a bad request names the field, the source is stored before it is
// graded, and grading cut off by a stop of the server resumes when it starts again.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { bounded, correct, loopingInPredict, startServer, submit, waitForSubmission } from './harness.mjs';

test('a bad submission gets a 4xx that names what is wrong, and nothing is stored', bounded, async () => {
  const server = await startServer();
  try {
    const cases = [
      ['{"student": "a", "source": ', 400, /submission body: EOF while parsing/],
      [{ source: correct }, 400, /missing field `student`/],
      [{ student: '  ', source: correct }, 400, /field `student` is empty/],
      [{ student: 'a', source: correct, lab: 'particle-filter' }, 400, /field `lab`: unknown exercise "particle-filter"/],
      [{ student: 'a', source: correct, grade: 1 }, 400, /unknown field `grade`/],
      [{ student: 'a', source: 'x'.repeat(300 << 10) }, 413, /field `source`: 307200 bytes; a submission may have at most 256 KB/],
    ];
    for (const [body, status, message] of cases) {
      const response = await submit(server, body);
      assert.equal(response.status, status, JSON.stringify(body).slice(0, 60));
      assert.match((await response.json()).error, message);
    }
    const missing = await fetch(`${server.url}/api/submissions/1`);
    assert.equal(missing.status, 404);
    assert.match((await missing.json()).error, /there is no submission "1"/);
  } finally {
    await server.stop();
  }
});

test('a submission is stored, graded and kept; grading cut off by a stop resumes at the next start', bounded, async () => {
  assert.notEqual(loopingInPredict, correct);
  const first = await startServer();
  let id, url, seed, cut;
  try {
    const response = await submit(first, { student: 'resume', source: loopingInPredict });
    assert.equal(response.status, 202);
    ({ id, url, seed } = await response.json());
    assert.equal(response.headers.get('location'), url);
    // Killed while it grades: the endless loop in predict holds the grading for seconds
    // (2 s for the tests of predict, more for the data-set runs), far longer than a poll.
    cut = await waitForSubmission(first, url, { until: (s) => s.status !== 'queued', what: 'picked up for grading' });
  } finally {
    await first.kill();
  }
  assert.equal(cut.status, 'grading', 'the server was killed before the grading could end');
  assert.equal(cut.graded_at, null);

  const restarted = Date.now();
  const second = await startServer({ dataDir: first.dataDir });
  try {
    const submission = await waitForSubmission(second, url);
    assert.equal(submission.id, id);
    assert.equal(submission.student, 'resume');
    assert.equal(submission.seed, seed);
    assert.ok(Date.parse(submission.graded_at) >= restarted,
      `graded at ${submission.graded_at}, after the restart at ${new Date(restarted).toISOString()}: the grade is the resumed run's`);
    assert.equal(submission.result.gradable, true);
    assert.equal(submission.result.tests.length, 11);
    const predict = submission.result.tests.find((t) => t.name.startsWith('predict'));
    assert.equal(predict.status, 'failed');
    assert.match(predict.message, /Stopped after 2 s, the time limit/);
    const update = submission.result.tests.find((t) => t.name.startsWith('update'));
    assert.equal(update.status, 'passed', 'the functions without the loop pass');

    const next = await submit(second, { student: 'resume-next', source: correct });
    assert.equal((await next.json()).id, id + 1, 'the next submission is numbered after the stored one');
  } finally {
    await second.stop();
  }
});
