// The MRCLAM experiment (/mrclam) in headless Chromium against the real server: on a
// generated robot its tables hold the three filters and dead reckoning, the learned, used
// and true noise, and the numbers `estlab mrclam --json` prints for the same robot and
// settings; the sliders re-run the filters and the time slider moves the particles and
// sigma points; with the real data set the menu offers its robots and a real robot's
// figures are the command line's; at a phone's size nothing spills over.
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import {
  bounded, estlab, laptop, launchBrowser, phone, requireSharedData, sharedDataDir, startServer,
} from './harness.mjs';

const dataset = join(sharedDataDir, 'mrclam', 'MRCLAM_Dataset6');
const haveData = existsSync(join(dataset, 'Robot1_Odometry.dat'));
/** A test that needs the real data set: skipped without it, unless it is required. */
const withData = haveData || requireSharedData ? bounded : { ...bounded, skip: `MRCLAM data set 6 is not in ${dataset} (ESTLAB_SHARED_DATA)` };

let plain;
let real;
let browser;
before(async () => {
  plain = await startServer();
  if (haveData) real = await startServer({ args: ['--datasets', sharedDataDir] });
  browser = await launchBrowser();
}, bounded);
after(async () => {
  await browser?.close();
  await plain?.stop();
  await real?.stop();
}, bounded);

/** /mrclam of `server` at `viewport`'s size once its script is ready; console errors in `page.problems`. */
async function open(server, viewport = laptop) {
  const page = await browser.newPage({ viewport });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  await page.goto(`${server.url}/mrclam`);
  await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 120_000 });
  return page;
}

/** The rows of table `id`: header, then cells. */
const rows = (page, id) => page.locator(`#${id} tbody tr`).evaluateAll((trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
/** Each plot's summary line and how many points each of its series holds, by the plot's name. */
const plots = (page) => page.evaluate(() => Object.fromEntries([...document.querySelectorAll('figure.plot')].map((figure) => {
  const { plot } = figure.querySelector('.chart');
  const series = plot.series().map((s) => [s.id, s.data.length]);
  return [figure.dataset.name, { summary: figure.querySelector('.plot-summary')?.textContent ?? '', series: Object.fromEntries(series) }];
})));

test('a generated robot: three filters, their numbers as the command line\'s, the noise learned and true', bounded, async () => {
  const page = await open(plain);
  const native = JSON.parse(estlab('mrclam', '--json', '--generate', '1', '--robot', '1', '--particles', '500', '--rho', '1'));
  assert.equal(await page.locator('#command').textContent(), 'estlab mrclam --generate 1 --robot 1 --rho 1 --particles 500');
  const filters = await rows(page, 'filters-table');
  assert.deepEqual(filters.map((r) => r[0]), ['RMS error (m)', 'mean error (m)', 'largest error (m)', 'NEES (3 if consistent)',
    'truth in 3σ (98.9 % if consistent)', 'readings used', 'readings rejected', 'time in this browser (ms)']);
  for (const [i, f] of native.filters.entries()) {
    assert.equal(Number(filters[0][i + 1]), Number(f.consistency.errors.rms.toPrecision(3)), `${f.filter}: RMS`);
    assert.equal(filters[5][i + 1], String(f.readings.used), `${f.filter}: readings used`);
  }
  assert.equal(Number(filters[0][4]), Number(native.dead_reckoning.rms.toPrecision(3)), 'dead reckoning');
  const noise = await rows(page, 'noise-table');
  assert.deepEqual(noise.map((r) => r[0]), ['α₁', 'α₂', 'α₃', 'α₄', 'range σ (m)', 'bearing σ (°)']);
  assert.equal(Number(noise[0][1]), Number(native.noise.alphas[0].toPrecision(3)), 'learned alpha1');
  assert.equal(Number(noise[0][3]), 0.2, 'the true alpha1');
  assert.equal(await page.locator('#used-heading').textContent(), 'used by the filters (R₂ × ρ = 1)');
  assert.match(await page.locator('#real-robots').textContent(), /not loaded on this server/);
  assert.deepEqual(await (await fetch(`${plain.url}/api/datasets/mrclam`)).json(), []);
  assert.equal((await fetch(`${plain.url}/api/datasets/mrclam/robot?dataset=6&robot=1`)).status, 404);

  // The map at the last step: 500 particles, seven sigma points.
  let shown = await plots(page);
  assert.equal(shown.map.series.particles, 500);
  assert.equal(shown.map.series['sigma points'], 7);
  assert.match(shown.map.summary, /^The room of robot 1 of the data set generated from seed 1, seen from above: 15 posts/);
  assert.equal(shown['close-up'].series.particles, 500);
  assert.equal(shown['close-up'].series['sigma points'], 7);
  for (const kind of ['ekf', 'ukf', 'particle']) assert.equal(shown['close-up'].series[`${kind} ellipse`], 65, `${kind}: its 3σ ellipse`);
  assert.match(shown['close-up'].summary, /^Round the truth at t = 120 s, [\d.]+ m across: EKF [\d.]+ m off, its 3σ ellipse (not )?round the truth; UKF/);
  for (const kind of ['ekf', 'ukf', 'particle']) assert.match(shown[`error-${kind}`].summary, /within its ±3σ at [\d.]+ % of the steps\. No post is in sight from [\d.]+ s to [\d.]+ s \(shaded\)\./);
  // The time slider moves the snapshot; the map says the new time.
  const step = Math.round((10 * (native.steps - 1)) / 99);
  await page.locator('#when').fill('10');
  await page.waitForFunction((k) => document.querySelector('#when-value').textContent === `t = ${k / 50} s (step ${k})`, step);
  shown = await plots(page);
  assert.ok(shown.map.summary.includes(`At t = ${step / 50} s the filters are this far from the truth: EKF `), shown.map.summary);
  // Fewer particles, a larger rho: re-run, and the command says so.
  await page.locator('#particles').fill('1');
  await page.locator('#particles').dispatchEvent('change');
  await page.locator('#rho').fill('1');
  await page.locator('#rho').dispatchEvent('change');
  await page.waitForFunction(() => document.querySelector('#command').textContent.endsWith('--rho 10 --particles 100'));
  shown = await plots(page);
  assert.equal(shown.map.series.particles, 100);
  assert.equal(await page.locator('#used-heading').textContent(), 'used by the filters (R₂ × ρ = 10)');
  const noise10 = await rows(page, 'noise-table');
  assert.ok(Math.abs(Number(noise10[4][2]) / Number(noise10[4][1]) - Math.sqrt(10)) < 0.01, 'the range sigma used grows by sqrt(rho)');
  // Another robot, another seed; a seed that is no number is said beside its field.
  await page.locator('#robot').selectOption('3');
  await page.waitForFunction(() => document.querySelector('#command').textContent.includes('--robot 3'));
  // The address follows, and opens the same run.
  assert.equal(new URL(page.url()).search, '?data=generated&seed=1&robot=3&rho=10&particles=100');
  const again = await browser.newPage({ viewport: laptop });
  await again.goto(page.url());
  await again.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 120_000 });
  assert.equal(await again.locator('#command').textContent(), 'estlab mrclam --generate 1 --robot 3 --rho 10 --particles 100');
  await again.close();
  await page.locator('#seed').fill('1.5');
  await page.locator('#seed').dispatchEvent('change');
  await page.waitForFunction(() => document.querySelector('#seed-problem')?.textContent.startsWith('seed: must be a whole number'));
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('at a phone\'s size and a laptop\'s nothing is wider than the screen', bounded, async () => {
  for (const viewport of [phone, laptop]) {
    const page = await open(plain, viewport);
    const what = `/mrclam at ${viewport.width} x ${viewport.height}`;
    const { width, plots } = await page.evaluate(() => ({
      width: document.documentElement.scrollWidth,
      plots: [...document.querySelectorAll('figure.plot, table.numbers')].map((el) => {
        const box = el.getBoundingClientRect();
        return { what: el.dataset.name ?? el.id, left: box.left, right: box.right };
      }),
    }));
    assert.ok(width <= viewport.width, `${what}: no sideways scrolling (${width} px)`);
    for (const plot of plots) assert.ok(plot.left >= -0.5 && plot.right <= viewport.width + 0.5, `${what}: ${plot.what} fits the width`);
    assert.deepEqual(page.problems, [], what);
    await page.close();
  }
});

test('the real data set: its robots offered, robot 1 as the command line runs it', withData, async () => {
  const listed = await (await fetch(`${real.url}/api/datasets/mrclam`)).json();
  assert.deepEqual(listed.map((r) => [r.dataset, r.robot, r.steps]), [[6, 1, 38_594], [6, 2, 45_001], [6, 3, 45_001]]);
  assert.equal((await fetch(`${real.url}/api/datasets/mrclam/robot?dataset=6&robot=4`)).status, 404);
  // Gzipped once at the start, for a browser that takes it so; plain for one that does not.
  const address = `${real.url}/api/datasets/mrclam/robot?dataset=6&robot=1`;
  const zipped = await fetch(address, { headers: { 'accept-encoding': 'gzip' } });
  assert.equal(zipped.headers.get('content-encoding'), 'gzip');
  const plainAnswer = await fetch(address, { headers: { 'accept-encoding': 'identity' } });
  assert.equal(plainAnswer.headers.get('content-encoding'), null);
  const [a, b] = [await zipped.json(), await plainAnswer.json()];
  assert.equal(a.run.steps.length, 38_594);
  assert.deepEqual(a.noise, b.noise);
  const bad = await fetch(`${real.url}/api/datasets/mrclam/robot?dataset=six&robot=1`);
  assert.equal(bad.status, 400);
  assert.match((await bad.json()).error, /dataset/);
  const page = await open(real);
  assert.match(await page.locator('#real-robots').textContent(), /3 real robots are loaded/);
  await page.locator('#data').selectOption('real:6:1');
  await page.waitForFunction(() => document.querySelector('#command').textContent.includes('--dataset 6 --robot 1'), null, { timeout: 120_000 });
  const native = JSON.parse(estlab('mrclam', '--json', '--datasets', sharedDataDir, '--filter', 'ekf'));
  const filters = await rows(page, 'filters-table');
  assert.equal(Number(filters[0][1]), Number(native.filters[0].consistency.errors.rms.toPrecision(3)), 'the EKF\'s RMS');
  assert.equal(Number(filters[0][4]), Number(native.dead_reckoning.rms.toPrecision(3)), 'dead reckoning');
  assert.equal(await page.locator('#true-heading').isVisible(), false, 'no true noise for a real robot');
  assert.equal((await rows(page, 'noise-table'))[0].length, 3, 'learned and used');
  assert.match((await plots(page))['error-ekf'].summary, /No post is in sight from 137\.7 s to 190\.3 s/);
  assert.deepEqual(page.problems, []);
  await page.close();
});
