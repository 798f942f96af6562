// Two rules of a course held through the real server (estlab serve, its clock the
// system's, so the dates are set around now rather than waited for), each otherwise
// held by unit tests only:
// - a late penalty past 100 % takes the whole score and no more (⌈late / 1 day⌉ × 60 %
//   for four days begun is 240 %): the final score is 0 in the submission, on /api/me and
//   in the gradebook, never below;
// - a change asked from a page of another origin on the same site (another port of the
//   same host: Chromium sends `Sec-Fetch-Site: same-site`, and the SameSite=Lax session
//   cookie goes with it, to any port) is refused and changes nothing, while the same
//   request from estlab's own page is taken.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, correct, estlab, getJson, launchBrowser, parseCsv, signIn, startServer, tempDir,
} from './harness.mjs';

const COURSE = 'el2320';
const LAB = 'ekf-localization';
const DAY = 86_400_000;

let server;
/** The students' session cookies (`estlab_session=...`), by id, and the course's API token. */
const cookies = {};
let token;

/** A moment `days` from now (negative: in the past), as the command line takes it. */
function fromNow(days) {
  return new Date(Date.now() + days * DAY).toISOString().replace(/\.\d+Z$/, 'Z');
}

before(async () => {
  server = await startServer();
  const on = ['--data', server.dataDir, '--url', server.url];
  const dir = tempDir();
  estlab('course', 'create', COURSE, '--title', 'Applied Estimation', ...on);
  const roster = join(dir, 'roster.csv');
  writeFileSync(roster, 'id,name,email\nu-late,Late Student,late@example.org\nu-site,Site Student,site@example.org\n');
  const codes = join(dir, 'codes.csv');
  estlab('course', 'roster', COURSE, roster, '--out', codes, ...on);
  // Due three and a half days ago (a submission now is four days begun late), open for
  // two more.
  estlab('course', 'assign', COURSE, LAB, '--due', fromNow(-3.5), '--cutoff', fromNow(2),
    '--late-penalty', '60%/day', '--counts', 'best', '--data', server.dataDir);
  token = estlab('course', 'token', COURSE, '--role', 'instructor', '--data', server.dataDir).trim().split('\n').at(-1);
  for (const student of parseCsv(readFileSync(codes, 'utf8'))) cookies[student.id] = await signIn(server, student.code);
}, bounded);
after(async () => { await server.stop(); }, bounded);

/** A submission of `source` as the student whose cookie is given, with more headers. */
function submitAs(cookie, source, headers = {}) {
  return fetch(`${server.url}/api/submissions`, {
    method: 'POST',
    headers: { 'content-type': 'application/json', cookie, ...headers },
    body: JSON.stringify({ source }),
  });
}

test('a late penalty past 100 % takes the whole score and no more: 0, in the submission, on /api/me and in the gradebook', bounded, async () => {
  const cookie = cookies['u-late'];
  const response = await submitAs(cookie, correct);
  assert.equal(response.status, 202, await response.clone().text());
  const accepted = await response.json();
  assert.ok(accepted.late_seconds > 3.4 * 86_400, `late by ${accepted.late_seconds} s`);
  assert.equal(accepted.penalty, 1, 'four days begun at 60 % a day take all of it, and no more');

  const graded = await waitForGraded(cookie, accepted.url);
  assert.equal(graded.score, 1, 'the correct file scores 1');
  assert.equal(graded.final_score, 0);

  const me = await getJson(server, '/api/me', { cookie });
  assert.equal(me.status, 200);
  assert.equal(me.body.assignments[0].counting_score, 0);

  const csv = await fetch(`${server.url}/api/courses/${COURSE}/labs/${LAB}/export?format=csv`, {
    headers: { authorization: `Bearer ${token}` },
  });
  assert.equal(csv.status, 200);
  const row = parseCsv(await csv.text()).find((r) => r.id === 'u-late');
  assert.deepEqual([row.score, row.late_penalty, row.final_score], ['1.0000', '1.0000', '0.0000']);
});

/** The student's own submission at `url` once graded (it is theirs only: read with their cookie). */
async function waitForGraded(cookie, url) {
  for (let tries = 0; tries < 1200; tries += 1) {
    const { status, body } = await getJson(server, url, { cookie });
    assert.equal(status, 200, JSON.stringify(body));
    if (body.status === 'graded') return body;
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  throw new Error(`${url} was not graded within two minutes`);
}

/** How many submissions the student whose cookie is given has. */
async function submissionsOf(cookie) {
  const { status, body } = await getJson(server, `/api/me/submissions?lab=${LAB}`, { cookie });
  assert.equal(status, 200, JSON.stringify(body));
  return body.length;
}

test('Sec-Fetch-Site: same-site is another site: submitting and signing out are refused, nothing changes', bounded, async () => {
  const cookie = cookies['u-site'];
  const before = await submissionsOf(cookie);
  const sameSite = { 'sec-fetch-site': 'same-site', origin: 'http://127.0.0.1:1' };
  const refused = await submitAs(cookie, correct, sameSite);
  assert.equal(refused.status, 403);
  assert.match((await refused.json()).error, /another site \(Sec-Fetch-Site: same-site\)/);
  assert.equal(await submissionsOf(cookie), before, 'nothing was stored');

  const signOut = await fetch(`${server.url}/signout`, { method: 'POST', headers: { cookie, ...sameSite }, redirect: 'manual' });
  assert.equal(signOut.status, 403);
  const me = await getJson(server, '/api/me', { cookie });
  assert.equal(me.body.member?.login, 'u-site', 'still signed in');
});

/** A server on another port of the same host, serving an empty page; `echoed` holds the headers of each request it got. */
function elsewhere() {
  const echoed = [];
  const other = createServer((request, response) => {
    echoed.push(request.headers);
    response.writeHead(200, { 'content-type': 'text/html; charset=utf-8' });
    response.end('<!doctype html><title>elsewhere</title>');
  });
  return new Promise((resolve) => {
    other.listen(0, '127.0.0.1', () => resolve({ url: `http://127.0.0.1:${other.address().port}`, echoed, close: () => other.close() }));
  });
}

test('in Chromium, a page on another port of the same host submits with the student\'s cookie: refused, while estlab\'s own page is taken', bounded, async () => {
  const cookie = cookies['u-site'];
  const [name, value] = cookie.split('=');
  /** The POST any page can make to any address (a "simple" request: no preflight), run in `page`. */
  const post = (page, target) => page.evaluate(([target, body]) => fetch(target, {
    method: 'POST', mode: 'no-cors', credentials: 'include', headers: { 'content-type': 'text/plain' }, body,
  }).then(() => 'sent'), [target, JSON.stringify({ source: `${correct}\n// from a page of the same site\n` })]);
  const browser = await launchBrowser();
  const [page1, page2] = [await elsewhere(), await elsewhere()];
  try {
    const context = await browser.newContext();
    await context.addCookies([{ name, value, url: server.url, httpOnly: true, sameSite: 'Lax' }]);
    const page = await context.newPage();
    const before = await submissionsOf(cookie);

    // From the page on another port: the browser sends it, the server refuses it.
    await page.goto(page1.url);
    assert.equal(await post(page, `${server.url}/api/submissions`), 'sent');
    assert.equal(await submissionsOf(cookie), before, 'the same-site page\'s submission was refused');
    // What such a page sends to another port of the host: the session cookie, same-site.
    await post(page, `${page2.url}/echo`);
    const echoed = page2.echoed.at(-1);
    assert.equal(echoed['sec-fetch-site'], 'same-site');
    assert.ok(echoed.cookie?.includes(cookie), 'the session cookie goes to every port of the host');

    // The same request from estlab's own origin is taken.
    await page.goto(`${server.url}/healthz`);
    assert.equal(await post(page, `${server.url}/api/submissions`), 'sent');
    assert.equal(await submissionsOf(cookie), before + 1, 'estlab\'s own page submits');
    await context.close();
  } finally {
    page1.close();
    page2.close();
    await browser.close();
  }
});
