// Submissions over HTTP: a bad request names the field, the source is stored before it is
// graded, and grading cut off by a stop of the server resumes when it starts again.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { root, startServer } from './harness.mjs';

const correct = readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8');

function submit(server, body) {
  return fetch(`${server.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: typeof body === 'string' ? body : JSON.stringify(body),
  });
}

async function graded(server, url) {
  for (;;) {
    const submission = await (await fetch(server.url + url)).json();
    if (submission.status === 'graded') return submission;
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
}

test('a bad submission gets a 4xx that names what is wrong, and nothing is stored', async () => {
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

test('a submission is stored, graded and kept; grading cut off by a stop resumes at the next start', async () => {
  const first = await startServer();
  const response = await submit(first, { student: 'resume', source: correct });
  assert.equal(response.status, 202);
  const { id, url, seed } = await response.json();
  assert.equal(response.headers.get('location'), url);
  // Killed at once, before the grading (about a second) can end.
  await new Promise((resolve) => { first.process.once('exit', resolve); first.process.kill('SIGKILL'); });

  const second = await startServer({ dataDir: first.dataDir });
  try {
    const submission = await graded(second, url);
    assert.equal(submission.id, id);
    assert.equal(submission.student, 'resume');
    assert.equal(submission.seed, seed);
    assert.equal(submission.result.score, 1);
    assert.equal(submission.result.tests.length, 11);
    const again = await submit(second, { student: 'resume', source: correct });
    assert.equal((await again.json()).id, id + 1, 'the next submission is numbered after the stored one');
  } finally {
    await second.stop();
  }
});
