// The pages in headless Chromium against the real server: they load cleanly, their
// controls change what is plotted, the EKF summary is the command line's, bad files get
// the parser's message, and every plot saves as PNG and SVG.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { estlab, launchBrowser, openPage, startServer, tempDir } from './harness.mjs';

let server;
let browser;
before(async () => {
  server = await startServer();
  browser = await launchBrowser();
});
after(async () => {
  await browser.close();
  await server.stop();
});

/** The data of the series `name` of the plot `plot` on the page. */
function seriesData(page, plot, name) {
  return page.evaluate(([plot, name]) => {
    const element = document.querySelector(`figure[data-name="${plot}"] .chart`);
    const series = element.plot.series().find((s) => s.name === name || s.id === name);
    return series ? series.data : null;
  }, [plot, name]);
}

/** Sets an input's value as a user would, firing its input and change events. */
async function setInput(page, selector, value) {
  await page.locator(selector).fill(String(value));
  await page.locator(selector).dispatchEvent('change');
}

test('every page loads without errors, with its formulas typeset and its plots drawn', async () => {
  for (const path of ['/', '/car', '/ekf']) {
    const page = await openPage(browser, server.url + path);
    assert.deepEqual(page.problems, [], path);
    assert.ok(await page.locator('.katex').count() > 0, `${path} typesets its formulas`);
    for (const figure of await page.locator('figure.plot:visible').all()) {
      const name = await figure.getAttribute('data-name');
      const series = await page.evaluate((n) => document.querySelector(`figure[data-name="${n}"] .chart`).plot.series(), name);
      assert.ok(series.some((s) => s.data.length > 0), `${path}: the plot ${name} shows data`);
    }
    assert.deepEqual(page.problems, [], path);
    await page.close();
  }
});

test('the car: moving a control changes the plotted estimate and the gains', async () => {
  const page = await openPage(browser, `${server.url}/car`);
  const before = await seriesData(page, 'position', 'estimate');
  await page.locator('#r-scale').fill('-2');
  const after = await seriesData(page, 'position', 'estimate');
  assert.equal(after.length, before.length);
  assert.notDeepEqual(after, before, 'R ÷100 changes the estimate');
  assert.match(await page.locator('#r-value').textContent(), /×0\.01/);

  const gain = async () => (await seriesData(page, 'gains', 'K₁, position')).at(-1)[1];
  await page.locator('button[data-preset="lab"]').click();
  const lab = await gain();
  await page.locator('button[data-preset="q-up"]').click();
  assert.ok(await gain() < lab / 2, 'distrusting the measurements lowers the position gain');
  await page.locator('button[data-preset="q-down"]').click();
  assert.ok(await gain() > 2 * lab, 'trusting them raises it');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the car: the Monte Carlo view shows the spread over many seeds', async () => {
  const page = await openPage(browser, `${server.url}/car`);
  assert.equal(await page.locator('#monte-carlo-plots').isVisible(), false);
  await page.locator('#runs').fill('50');
  await page.locator('#monte-carlo').check();
  assert.equal(await page.locator('#monte-carlo-plots').isVisible(), true);
  const spread = await seriesData(page, 'spread', 'actual spread of the position error (m)');
  const sigma = await seriesData(page, 'spread', 'filter σ, position (m)');
  assert.equal(spread.length, 100);
  // The lab's filter is told the true noise: its sigma is the spread, give or take.
  const ratio = spread.at(-1)[1] / sigma.at(-1)[1];
  assert.ok(ratio > 0.5 && ratio < 2, `spread / sigma = ${ratio}`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

/** The report lines of `estlab run` for these files and the page's command-line flags. */
async function cliReport(page, sensor, map) {
  const flags = JSON.parse(await page.locator('#command').getAttribute('data-flags'));
  return estlab('run', sensor, map, ...flags).split('\n').filter((l) => /^(mean|rejected)/.test(l)).join('\n');
}

test('the EKF: the summary on the page is what estlab run prints for the same data and settings', async () => {
  const dir = tempDir();
  const page = await openPage(browser, `${server.url}/ekf`);
  for (const [kind, seed, mode] of [['o3', 2, 'sequential'], ['outliers', 3, 'batch'], ['no-odometry', 4, 'batch'], ['no-odometry', 4, 'sequential']]) {
    estlab('simulate', '--kind', kind, '--seed', String(seed), '--out', dir);
    await page.locator('#dataset-kind').selectOption(kind);
    await setInput(page, '#dataset-seed', seed);
    await page.locator(`input[name=mode][value=${mode}]`).check();
    const command = await page.locator('#command').textContent();
    assert.match(command, new RegExp(`--kind ${kind} --seed ${seed} .*--delta-m`));
    assert.equal(command.includes('--batch'), mode === 'batch');
    const expected = await cliReport(page, join(dir, `so_${kind}_${seed}.txt`), join(dir, `map_${kind}_${seed}.txt`));
    assert.equal((await page.locator('#summary').textContent()).trim(), expected, `${kind} seed ${seed} ${mode}`);
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: changing a setting re-runs the filter, and the time slider steps through the readings', async () => {
  const page = await openPage(browser, `${server.url}/ekf`);
  const before = await seriesData(page, 'map', 'estimate');
  await page.locator('#q-range').fill('0.5');
  const after = await seriesData(page, 'map', 'estimate');
  assert.notDeepEqual(after, before, 'a larger Q changes the estimate');

  await page.locator('#delta-m').fill('0.99');
  assert.match(await page.locator('#lambda-m').textContent(), /Λ_M = 9\.21/);

  await page.locator('#time').fill('10');
  const lines = await seriesData(page, 'map', 'associations');
  assert.ok(lines.length > 0, 'the readings of step 11 are drawn');
  assert.match(await page.locator('#time-label').textContent(), /\(step 11 of \d+\): \d+ readings?, \d+ rejected/);
  await page.locator('#time-forward').click();
  assert.match(await page.locator('#time-label').textContent(), /step 12 of/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: a malformed file shows the parser message, and good files run', async () => {
  const dir = tempDir();
  estlab('simulate', '--kind', 'o3', '--seed', '5', '--out', dir);
  const map = join(dir, 'map_o3_5.txt');
  const sensor = join(dir, 'so_o3_5.txt');
  const broken = join(dir, 'so_broken.txt');
  const lines = readFileSync(sensor, 'utf8').split('\n');
  lines[2] = lines[2].split(' ').slice(0, -1).join(' ');
  writeFileSync(broken, lines.join('\n'));

  const page = await openPage(browser, `${server.url}/ekf`);
  await page.locator('#dataset-kind').selectOption('files');
  assert.match(await page.locator('#error').textContent(), /Choose a map file and a sensor file/);
  await page.locator('#map-file').setInputFiles(map);
  await page.locator('#sensor-file').setInputFiles(broken);
  const error = page.locator('#error');
  await error.waitFor({ state: 'visible' });
  assert.match(await error.textContent(), /^so_broken\.txt:3: n = \d+ readings \(id bearing range each\) need \d+ values on the line, found \d+: reading \d+ of \d+ is incomplete$/);
  assert.ok(await page.locator('figure[data-name=map]').isVisible(), 'the page is still there');

  await page.locator('#sensor-file').setInputFiles(sensor);
  await error.waitFor({ state: 'hidden' });
  assert.match(await page.locator('#command').textContent(), /^estlab run so_o3_5\.txt map_o3_5\.txt --R/);
  assert.equal((await page.locator('#summary').textContent()).trim(), await cliReport(page, sensor, map));
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('every plot saves as PNG and as SVG', async () => {
  for (const path of ['/car', '/ekf']) {
    const page = await openPage(browser, server.url + path);
    for (const figure of await page.locator('figure.plot:visible').all()) {
      const name = await figure.getAttribute('data-name');
      for (const [label, check] of [
        ['PNG', (bytes) => bytes.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]))],
        ['SVG', (bytes) => bytes.toString('utf8').startsWith('<svg') && bytes.toString('utf8').includes('</svg>')],
      ]) {
        const [download] = await Promise.all([
          page.waitForEvent('download'),
          figure.locator('.save button', { hasText: label }).click(),
        ]);
        assert.equal(download.suggestedFilename(), `${path.slice(1)}-${name}.${label.toLowerCase()}`);
        const bytes = readFileSync(await download.path());
        assert.ok(bytes.length > 1000 && check(bytes), `${path} ${name} as ${label}`);
      }
    }
    assert.deepEqual(page.problems, [], path);
    await page.close();
  }
});
