// Every page of the site checked by axe-core in headless Chromium, at a phone's size and a
// laptop's, as a student and as the course's instructor would open them, after the page
// has drawn (and, on the workbenches, after a run of the tests, whose results panel axe
// reads too): no violation that axe rates serious or critical (contrast, names of
// fields and buttons, headings in order, table headers with text, scrollable regions a
// keyboard reaches, ...). A violation names the page, the rule and the elements.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import {
  bounded, correct, estlab, getJson, laptop, openIn, phone, runAndWait, setUpCourse, signIn, signedInContext, violations,
  waitFor, withServerAndBrowser,
} from './harness.mjs';

let server;
let browser;
withServerAndBrowser((s, b) => { server = s; browser = b; });

const COURSE = 'a11y';
const LAB = 'ekf-localization';

/** Opens `path` in a context of `size` (signed in with `cookie` when given), drawn. */
async function open(path, size, cookie) {
  // The site's Content-Security-Policy refuses scripts it did not serve; axe is the test's.
  const context = await signedInContext(browser, server, cookie, size, { bypassCSP: true });
  return openIn(context, server.url + path);
}

for (const [name, size] of [['phone', phone], ['laptop', laptop]]) {
  test(`at a ${name}'s size: no page has a serious or critical accessibility violation`, bounded, async () => {
    const course = `${COURSE}-${name}`;
    const { students } = setUpCourse(server, { course, title: 'Accessible', prefix: `${name[0]}`, count: 2, role: 'assistant' });
    const link = estlab('course', 'staff', course, `teacher@${name}.example`, '--role', 'instructor',
      '--data', server.dataDir, '--url', server.url).trim().split('\n').pop();
    const teacher = await signIn(server, link.split('#')[1]);
    const student = await signIn(server, students[0].code);
    // One graded submission, so that the staff's pages and /me show a result.
    const response = await fetch(`${server.url}/api/submissions`, {
      method: 'POST',
      headers: { cookie: student, 'content-type': 'application/json' },
      body: JSON.stringify({ source: correct }),
    });
    const sent = await response.json();
    assert.equal(response.status, 202, JSON.stringify(sent));
    await waitFor(`submission ${sent.id}`, async () => (await getJson(server, sent.url, { cookie: student })).body,
      (s) => s.status === 'graded', { timeout: 180_000 });

    const pages = [
      ['/', null], ['/car', null], ['/ekf', null], ['/odometry', null], ['/fusion', null], ['/mrclam', null], ['/signin', null],
      ['/ekf/code', student], ['/odometry/code', student], ['/fusion/code', student], ['/mrclam/code', student], ['/me', student],
      ['/me', teacher], [`/courses/${course}`, teacher], [`/courses/${course}/${LAB}`, teacher],
      [`/courses/${course}/${LAB}/students/${students[0].id}`, teacher],
      [`/courses/${course}/${LAB}/questions`, student], [`/courses/${course}/${LAB}/questions`, teacher],
      [`/courses/${course}/${LAB}/report`, student], [`/courses/${course}/${LAB}/report`, teacher],
      [`/courses/${course}/${LAB}/report?student=${students[0].id}`, teacher],
    ];
    const problems = [];
    for (const [path, cookie] of pages) {
      const page = await open(path, size, cookie);
      if (path.endsWith('/code')) await runAndWait(page, '#run-tests');
      for (const line of await violations(page)) problems.push(`${path}${cookie === teacher ? ' (staff)' : ''}: ${line}`);
      await page.context().close();
    }
    assert.deepEqual(problems, []);
  });
}
