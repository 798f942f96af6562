// The pages in headless Chromium against the real server: they load cleanly, every plot
// is on screen and draws the numbers of the command line for the same settings, the
// controls change them as the command line's flags do, the EKF summary is the command
// line's, bad files get the parser's message, and every plot saves as a PNG and an SVG
// that show the data.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { bounded, estlab, openPage, tempDir, waitFor, withServerAndBrowser } from './harness.mjs';

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** The plots each page shows when it opens. */
const plotsOf = {
  '/': [],
  '/car': ['position', 'velocity', 'errors', 'sigmas', 'gains'],
  '/ekf': ['map', 'errorX', 'errorY', 'errorTheta', 'covariance'],
};

/** The colour of the estimate in every plot (colours.estimate in static/src/plots.js). */
const estimateColour = [0xc6, 0x28, 0x28];

/**
 * The chart of the plot `name`, scrolled into view; fails unless it is shown at a size
 * and lies in the viewport.
 */
async function shown(page, name) {
  const chart = page.locator(`figure[data-name="${name}"] .chart`);
  await chart.scrollIntoViewIfNeeded();
  assert.ok(await chart.isVisible(), `the plot ${name} is visible`);
  const box = await chart.boundingBox();
  assert.ok(box && box.width >= 200 && box.height >= 150, `the plot ${name} has a size: ${JSON.stringify(box)}`);
  const { width, height } = page.viewportSize();
  // Within a pixel: scrolled to, a box may lie a fraction of a pixel past the edge.
  assert.ok(box.x >= -1 && box.y >= -1 && box.x + box.width <= width + 1 && box.y + box.height <= height + 1,
    `the plot ${name} is in the viewport (${width} x ${height}) once scrolled to: ${JSON.stringify(box)}`);
  return chart;
}

/** The data of the series `series` (its name or id) that the plot `plot` shows. */
async function seriesData(page, plot, series) {
  await shown(page, plot);
  const data = await page.evaluate(([plot, series]) => {
    const element = document.querySelector(`figure[data-name="${plot}"] .chart`);
    return element.plot.series().find((s) => s.name === series || s.id === series)?.data ?? null;
  }, [plot, series]);
  assert.ok(data, `the plot ${plot} has a series ${series}`);
  return data;
}

/** Asserts |got - expected| <= 1e-12 max(1, |expected|): the wasm build's numbers are the native ones. */
function assertNear(got, expected, what) {
  assert.ok(Math.abs(got - expected) <= 1e-12 * Math.max(1, Math.abs(expected)), `${what}: plotted ${got}, estlab ${expected}`);
}

/** Asserts that `points` ([[x, y], ...], as plotted) are (xs[i], ys[i]), one for one. */
function assertPoints(points, xs, ys, what) {
  assert.equal(points.length, xs.length, `${what}: the number of points`);
  points.forEach(([x, y], i) => {
    assertNear(x, xs[i], `${what}, point ${i}, x`);
    assertNear(y, ys[i], `${what}, point ${i}, y`);
  });
}

/**
 * What the plot `name` has painted on its canvases (the chart and its overlays), once it
 * is in view: the pixels painted, and those of the estimate's colour.
 */
async function painted(page, name) {
  await shown(page, name);
  const count = () => page.evaluate(([name, colour]) => {
    let pixels = 0;
    let estimate = 0;
    for (const canvas of document.querySelectorAll(`figure[data-name="${name}"] canvas`)) {
      const { data } = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height);
      for (let i = 0; i < data.length; i += 4) {
        if (data[i + 3] === 0) continue;
        pixels++;
        const distance = Math.abs(data[i] - colour[0]) + Math.abs(data[i + 1] - colour[1]) + Math.abs(data[i + 2] - colour[2]);
        if (data[i + 3] > 200 && distance < 60) estimate++;
      }
    }
    return { pixels, estimate };
  }, [name, estimateColour]);
  // A plot that has just come into view draws at its next frame.
  return waitFor(`the plot ${name} to draw its estimate`, count, (ink) => ink.estimate > 0, { timeout: 10_000, interval: 100 });
}

/** Sets an input's value as a user would, firing its input and change events. */
async function setInput(page, selector, value) {
  await page.locator(selector).fill(String(value));
  await page.locator(selector).dispatchEvent('change');
}

test('every page loads without errors, with its formulas typeset and its plots on screen and drawn', bounded, async () => {
  for (const [path, plots] of Object.entries(plotsOf)) {
    const page = await openPage(browser, server.url + path);
    assert.deepEqual(page.problems, [], path);
    assert.ok(await page.locator('.katex').count() > 0, `${path} typesets its formulas`);
    const visible = await page.locator('figure.plot:visible').evaluateAll((figures) => figures.map((f) => f.dataset.name));
    assert.deepEqual(visible, plots, `${path} shows its plots`);
    for (const name of plots) {
      const series = await page.evaluate((n) => document.querySelector(`figure[data-name="${n}"] .chart`).plot.series(), name);
      assert.ok(series.some((s) => s.data.length > 0), `${path}: the plot ${name} has data`);
      const ink = await painted(page, name);
      assert.ok(ink.estimate >= 100, `${path}: the plot ${name} draws its estimate: ${JSON.stringify(ink)}`);
    }
    assert.deepEqual(page.problems, [], path);
    await page.close();
  }
});

/** `estlab car --json` with `flags`: { params, run }. */
const car = (...flags) => JSON.parse(estlab('car', '--json', ...flags));

/**
 * Asserts that the car page plots the run of `estlab car` with `flags`: the belief and the
 * truth from t = 0 (the prior, before the first update), the measurements and the gains
 * from the first update.
 */
async function assertCarPlotted(page, flags, what) {
  const { params, run: { steps } } = car(...flags);
  const t = steps.map((s) => s.t);
  for (const [plot, series, value, prior] of [
    ['position', 'true', (s) => s.truth[0], params.x0[0]],
    ['position', 'measurement', (s) => s.z],
    ['position', 'estimate', (s) => s.mu[0], params.mu0[0]],
    ['velocity', 'estimate', (s) => s.mu[1], params.mu0[1]],
    ['sigmas', '√P₁₁, position (m)', (s) => Math.sqrt(s.sigma[0]), Math.sqrt(params.sigma0[0][0])],
    ['gains', 'K₁, position', (s) => s.gain[0]],
    ['gains', 'K₂, velocity', (s) => s.gain[1]],
  ]) {
    const [xs, ys] = prior === undefined ? [t, steps.map(value)] : [[0, ...t], [prior, ...steps.map(value)]];
    assertPoints(await seriesData(page, plot, series), xs, ys, `${what}: ${plot}, ${series}`);
  }
}

test('the car: the plots are the run of estlab car with the settings of the controls', bounded, async () => {
  const page = await openPage(browser, `${server.url}/car`);
  const lab = car().params;
  const r = (factor) => ['--R', [lab.r[0][0] * factor, lab.r[1][1] * factor].join(',')];
  const q = (factor) => ['--Q', String(lab.q * factor)];
  await assertCarPlotted(page, [], "the lab's settings");
  const gain = async () => (await seriesData(page, 'gains', 'K₁, position')).at(-1)[1];
  const labGain = await gain();

  await page.locator('#r-scale').fill('-2');
  assert.match(await page.locator('#r-value').textContent(), /×0\.01/);
  await assertCarPlotted(page, r(0.01), 'R ÷100');

  await page.locator('button[data-preset="lab"]').click();
  await assertCarPlotted(page, [], "back to the lab's settings");
  await page.locator('button[data-preset="q-up"]').click();
  await assertCarPlotted(page, q(100), 'Q ×100');
  assert.ok(await gain() < labGain / 2, 'distrusting the measurements lowers the position gain');
  await page.locator('button[data-preset="q-down"]').click();
  await assertCarPlotted(page, q(0.01), 'Q ÷100');
  assert.ok(await gain() > 2 * labGain, 'trusting them raises it');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the car: the Monte Carlo view shows the spread over many seeds beside the filter\'s σ', bounded, async () => {
  const page = await openPage(browser, `${server.url}/car`);
  assert.equal(await page.locator('#monte-carlo-plots').isVisible(), false);
  await page.locator('#runs').fill('50');
  await page.locator('#monte-carlo').check();
  assert.equal(await page.locator('#monte-carlo-plots').isVisible(), true);
  const spread = await seriesData(page, 'spread', 'actual spread of the position error (m)');
  const sigma = await seriesData(page, 'spread', 'filter σ, position (m)');
  // The filter's σ does not depend on the seed: it is the σ of estlab car's run, from
  // the prior's at t = 0. The spread starts at the first update (at t = 0 it is 0).
  const { params, run: { steps } } = car();
  assertPoints(sigma, [0, ...steps.map((s) => s.t)], [Math.sqrt(params.sigma0[0][0]), ...steps.map((s) => Math.sqrt(s.sigma[0]))], 'filter σ, position');
  assert.equal(spread.length, steps.length);
  // The lab's filter is told the true noise: its sigma is the spread, give or take.
  const ratio = spread.at(-1)[1] / sigma.at(-1)[1];
  assert.ok(ratio > 0.5 && ratio < 2, `spread / sigma = ${ratio}`);
  assert.ok((await painted(page, 'spread')).estimate >= 100, 'the spread is drawn');
  assert.deepEqual(page.problems, []);
  await page.close();
});

/** The page's command-line flags (the settings of its controls). */
async function pageFlags(page) {
  return JSON.parse(await page.locator('#command').getAttribute('data-flags'));
}

/** The report lines of `estlab run` for these files and the page's command-line flags. */
async function cliReport(page, sensor, map) {
  return estlab('run', sensor, map, ...await pageFlags(page)).split('\n').filter((l) => /^(mean|rejected)/.test(l)).join('\n');
}

/** `estlab run --json` for these files and the page's command-line flags. */
async function cliRun(page, sensor, map) {
  return JSON.parse(estlab('run', sensor, map, '--json', ...await pageFlags(page)));
}

/** Asserts that the EKF page plots the run `native` (from estlab run --json). */
async function assertEkfPlotted(page, native, what) {
  const { steps, readings } = native;
  const t = steps.map((s) => s.t);
  const column = (key, i) => steps.map((s) => s[key][i]);
  assertPoints(await seriesData(page, 'map', 'estimate'), column('mu', 0), column('mu', 1), `${what}: the estimated path`);
  assertPoints(await seriesData(page, 'map', 'true'), column('truth', 0), column('truth', 1), `${what}: the true path`);
  assertPoints(await seriesData(page, 'map', 'odometry only'), column('odometry', 0), column('odometry', 1), `${what}: the odometry-only path`);
  const rejected = await seriesData(page, 'map', 'rejected');
  assert.equal(rejected.length, readings.filter((r) => r.outlier).length, `${what}: the rejected readings`);
  for (const [i, plot] of ['errorX', 'errorY', 'errorTheta'].entries()) {
    assertPoints(await seriesData(page, plot, 'estimate − truth'), t, column('error', i), `${what}: ${plot}`);
    assertPoints(await seriesData(page, plot, 'band ±3σ high'), t, steps.map((s) => 3 * Math.sqrt(s.sigma[4 * i])), `${what}: ${plot} +3σ`);
  }
  assertPoints(await seriesData(page, 'covariance', 'Σₓₓ (m²)'), t, steps.map((s) => s.sigma[0]), `${what}: Σₓₓ`);
}

test('the EKF: the summary and the plots are what estlab run gives for the same data and settings', bounded, async () => {
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
    const [sensor, map] = [join(dir, `so_${kind}_${seed}.txt`), join(dir, `map_${kind}_${seed}.txt`)];
    const what = `${kind} seed ${seed} ${mode}`;
    assert.equal((await page.locator('#summary').textContent()).trim(), await cliReport(page, sensor, map), what);
    await assertEkfPlotted(page, await cliRun(page, sensor, map), what);
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: changing a setting re-runs the filter, and the time slider steps through the readings', bounded, async () => {
  const page = await openPage(browser, `${server.url}/ekf`);
  const dir = tempDir();
  const [kind, seed] = [await page.locator('#dataset-kind').inputValue(), await page.locator('#dataset-seed').inputValue()];
  estlab('simulate', '--kind', kind, '--seed', seed, '--out', dir);
  const [sensor, map] = [join(dir, `so_${kind}_${seed}.txt`), join(dir, `map_${kind}_${seed}.txt`)];
  const before = await seriesData(page, 'map', 'estimate');
  await page.locator('#q-range').fill('0.5');
  assert.match((await pageFlags(page)).join(' '), /--Q 0\.25,/, 'the range std 0.5 is the variance 0.25');
  assert.notDeepEqual(await seriesData(page, 'map', 'estimate'), before, 'a larger Q changes the estimate');
  const native = await cliRun(page, sensor, map);
  await assertEkfPlotted(page, native, 'Q range std 0.5');

  await page.locator('#delta-m').fill('0.99');
  assert.match(await page.locator('#lambda-m').textContent(), /Λ_M = 9\.21/);

  // Step 11 (index 10): from the estimate, a line to the landmark each reading is
  // associated with and one to where the reading puts it.
  await page.locator('#time').fill('10');
  const { steps, readings } = await cliRun(page, sensor, map);
  const now = readings.filter((r) => r.step === 10);
  assert.ok(now.length > 0, 'step 11 has readings');
  const lines = await seriesData(page, 'map', 'associations');
  const landmarks = await seriesData(page, 'map', 'landmarks');
  assert.equal(lines.length, 2 * now.length, 'two lines per reading of step 11');
  now.forEach((reading, j) => {
    const [from, to] = lines[2 * j].coords;
    assertNear(from[0], steps[10].mu[0], `reading ${j}: from the estimate, x`);
    assertNear(from[1], steps[10].mu[1], `reading ${j}: from the estimate, y`);
    assert.deepEqual(to, landmarks[reading.c], `reading ${j}: to landmark ${reading.c}, as estlab run associates it`);
  });
  const rejected = now.filter((r) => r.outlier).length;
  assert.match(await page.locator('#time-label').textContent(),
    new RegExp(`\\(step 11 of ${steps.length}\\): ${now.length} readings?, ${rejected} rejected`));
  await page.locator('#time-forward').click();
  assert.match(await page.locator('#time-label').textContent(), /step 12 of/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: a malformed file shows the parser message, and good files run', bounded, async () => {
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
  // The page reads the files before it parses them: the message before theirs ("Choose
  // a map file ...") stays until then, however long reading takes.
  await page.waitForFunction(() => document.getElementById('error').textContent.startsWith('so_broken.txt'));
  assert.match(await error.textContent(), /^so_broken\.txt:3: n = \d+ readings \(id bearing range each\) need \d+ values on the line, found \d+: reading \d+ of \d+ is incomplete$/);
  // The run before the error (o3, seed 1) is not passed off as the broken file's: its
  // summary and command go, its plots stay dimmed under a note that says whose they are.
  assert.equal(await page.locator('#stale').textContent(),
    'No run: the data did not load. The plots below are still those of the last run, on o3, seed 1, dimmed.');
  assert.equal(await page.locator('#summary').isVisible(), false, 'no summary under the error');
  assert.equal(await page.locator('#command').isVisible(), false, 'no command under the error');
  assert.equal(await page.locator('#command').getAttribute('data-flags'), null);
  assert.ok(await page.locator('#ekf-plots').evaluate((el) => el.classList.contains('stale')), 'the plots are marked stale');
  // The drawings are dimmed, not the text about them (see rough-edges.test.mjs).
  assert.equal(await page.locator('#ekf-plots figure[data-name="map"] > .stack').evaluate((el) => getComputedStyle(el).opacity), '0.35');
  await shown(page, 'map');

  await page.locator('#sensor-file').setInputFiles(sensor);
  await error.waitFor({ state: 'hidden' });
  assert.equal(await page.locator('#stale').isVisible(), false, 'the files ran: nothing is stale');
  assert.ok(await page.locator('#ekf-plots').evaluate((el) => !el.classList.contains('stale')), 'the plots are current');
  assert.match(await page.locator('#command').textContent(), /^estlab run so_o3_5\.txt map_o3_5\.txt --R/);
  assert.equal((await page.locator('#summary').textContent()).trim(), await cliReport(page, sensor, map));
  await assertEkfPlotted(page, await cliRun(page, sensor, map), 'so_o3_5.txt on map_o3_5.txt');
  assert.deepEqual(page.problems, []);
  await page.close();
});

/**
 * The PNG `bytes` decoded in the page: its size, the pixels not white, those of the
 * estimate's colour, and how many colours it has.
 */
function decodePng(page, bytes) {
  return page.evaluate(async ([base64, colour]) => {
    const png = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
    const image = await createImageBitmap(new Blob([png], { type: 'image/png' }));
    const canvas = new OffscreenCanvas(image.width, image.height);
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    const { data } = context.getImageData(0, 0, image.width, image.height);
    let ink = 0;
    let estimate = 0;
    const colours = new Set();
    for (let i = 0; i < data.length; i += 4) {
      const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
      colours.add((r << 16) | (g << 8) | b);
      if (r < 250 || g < 250 || b < 250) ink++;
      if (Math.abs(r - colour[0]) + Math.abs(g - colour[1]) + Math.abs(b - colour[2]) < 60) estimate++;
    }
    return { width: image.width, height: image.height, ink, estimate, colours: colours.size };
  }, [bytes.toString('base64'), estimateColour]);
}

/** The path elements of an SVG: their stroke colours and how many numbers each `d` holds. */
function svgPaths(svg) {
  return [...svg.matchAll(/<path\b[^>]*>/g)].map(([element]) => ({
    stroke: element.match(/\bstroke="([^"]*)"/)?.[1] ?? null,
    numbers: (element.match(/\bd="([^"]*)"/)?.[1].match(/-?\d+(\.\d+)?/g) ?? []).length,
  }));
}

test('every plot saves as a PNG and an SVG that show its data', bounded, async () => {
  for (const path of ['/car', '/ekf']) {
    const page = await openPage(browser, server.url + path);
    for (const name of plotsOf[path]) {
      const figure = page.locator(`figure[data-name="${name}"]`);
      await shown(page, name);
      const save = async (label) => {
        const [download] = await Promise.all([
          page.waitForEvent('download'),
          figure.locator('.save button', { hasText: label }).click(),
        ]);
        assert.equal(download.suggestedFilename(), `${path.slice(1)}-${name}.${label.toLowerCase()}`);
        return readFileSync(await download.path());
      };
      const size = await page.evaluate((n) => {
        const { chart } = document.querySelector(`figure[data-name="${n}"] .chart`).plot;
        return { width: chart.getWidth(), height: chart.getHeight() };
      }, name);

      const png = await decodePng(page, await save('PNG'));
      const what = `${path} ${name} as PNG`;
      assert.deepEqual([png.width, png.height], [2 * size.width, 2 * size.height], `${what}: twice the size on the page`);
      assert.ok(png.ink > 0.005 * png.width * png.height, `${what} is not blank: ${JSON.stringify(png)}`);
      assert.ok(png.estimate >= 200, `${what} draws the estimate in its colour: ${JSON.stringify(png)}`);
      assert.ok(png.colours >= 10, `${what} has lines, text and colours: ${JSON.stringify(png)}`);

      const svg = (await save('SVG')).toString('utf8');
      assert.match(svg, /^<svg\b/, `${path} ${name} as SVG`);
      assert.ok(svg.trimEnd().endsWith('</svg>'), `${path} ${name} as SVG is whole`);
      const paths = svgPaths(svg);
      const estimate = paths.filter((p) => p.stroke === '#c62828' && p.numbers >= 100);
      assert.ok(estimate.length > 0,
        `${path} ${name} as SVG draws the estimate as a path through its points: ${JSON.stringify(paths.slice(0, 20))}`);
    }
    assert.deepEqual(page.problems, [], path);
    await page.close();
  }
});

test('on a phone every page fits the screen: the settings fold above the plots, equations and the editor scroll in their own boxes', bounded, async () => {
  for (const width of [360, 390]) {
    for (const path of ['/', '/car', '/ekf', '/ekf/code', '/signin']) {
      const page = await browser.newPage({ viewport: { width, height: 844 } });
      await page.goto(server.url + path);
      await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 120_000 });
      const what = `${path} at ${width} px`;
      assert.equal(await page.evaluate(() => document.documentElement.scrollWidth), width, `${what}: no sideways scrolling`);
      for (const name of plotsOf[path] ?? []) {
        const box = await (await shown(page, name)).boundingBox();
        assert.ok(box.x >= 0 && box.x + box.width <= width, `${what}: the plot ${name} fits`);
      }
      if (path === '/car' || path === '/ekf') {
        // Above the plots, not pinned over them, and folding away.
        const settings = page.locator('details.controls');
        assert.equal(await settings.evaluate((el) => getComputedStyle(el).position), 'static', what);
        await settings.locator('summary').click();
        assert.equal(await settings.getAttribute('open'), null, `${what}: the settings fold away`);
        const equation = page.locator('.katex-display').first();
        assert.equal(await equation.evaluate((el) => getComputedStyle(el).overflowX), 'auto', what);
      }
      if (path === '/ekf/code') {
        const editor = await page.locator('.editor').boundingBox();
        assert.ok(editor.x >= 0 && editor.x + editor.width <= width, `${what}: the editor fits`);
        for (const button of ['#run-tests', '#submit', '#reset']) {
          const box = await page.locator(button).boundingBox();
          assert.ok(box.x + box.width <= width, `${what}: ${button} is on the screen`);
        }
      }
      await page.close();
    }
  }
});

test('the home page and the navigation lead to every exercise, its workbench beside its experiments; plots\' save buttons name their plot; no rejection reads as ∞', bounded, async () => {
  const home = await openPage(browser, `${server.url}/`);
  const links = (selector) => home.locator(selector).evaluateAll((found) => found.map((a) => a.getAttribute('href')));
  // A card per page on its own or per exercise, the workbench's under its experiments'.
  assert.deepEqual(await links('.exercises > li > h2 a'), ['/car', '/ekf', '/odometry', '/fusion', '/mrclam']);
  assert.deepEqual(await links('.exercises > li > h3 a'), ['/ekf/code', '/odometry/code', '/fusion/code', '/mrclam/code']);
  assert.deepEqual(await home.locator('.exercises > li').evaluateAll((cards) => cards.map((card) =>
    [...card.querySelectorAll('a')].map((a) => a.getAttribute('href')))),
  [['/car'], ['/ekf', '/ekf/code'], ['/odometry', '/odometry/code'], ['/fusion', '/fusion/code'], ['/mrclam', '/mrclam/code']]);
  // The navigation groups them alike.
  assert.deepEqual(await home.locator('header.site nav .group').evaluateAll((groups) => groups.map((group) =>
    [...group.querySelectorAll('a')].map((a) => a.getAttribute('href')))),
  [['/car'], ['/ekf', '/ekf/code'], ['/odometry', '/odometry/code'], ['/fusion', '/fusion/code'], ['/mrclam', '/mrclam/code']]);
  await home.close();
  const page = await openPage(browser, `${server.url}/ekf`);
  assert.equal(await page.locator('figure[data-name="map"] .save button').first().getAttribute('aria-label'),
    'Save the plot "The map: true (green, solid), estimated (red, dashed) and odometry-only (blue, dotted) paths" as PNG');
  await page.locator('#dataset-kind').selectOption('no-odometry');
  await page.waitForFunction(() => document.getElementById('lambda-m').textContent.includes('∞'));
  assert.equal(await page.locator('#lambda-m').textContent(), 'Λ_M = ∞: no reading is rejected');
  await page.locator('#dataset-kind').selectOption('files');
  assert.equal(await page.locator('#dataset-seed').isVisible(), false, 'uploaded files have no seed');
  assert.deepEqual(page.problems.filter((p) => !p.includes('Choose a map file')), []);
  await page.close();
});

test('on a phone the navigation is one row that scrolls sideways, its last link within reach', bounded, async () => {
  const page = await browser.newPage({ viewport: { width: 360, height: 844 } });
  await page.goto(`${server.url}/`);
  const nav = page.locator('header.site nav');
  // One row: every link's top within the height of the smallest (the workbenches' are
  // set smaller, on the same baseline).
  const boxes = await nav.locator('a').evaluateAll((links) => links.map((a) => a.getBoundingClientRect().toJSON()));
  const tops = boxes.map((box) => box.top);
  assert.ok(Math.max(...tops) - Math.min(...tops) < Math.min(...boxes.map((box) => box.height)), `one row: ${tops}`);
  const box = await nav.boundingBox();
  assert.ok(box.x >= 0 && box.x + box.width <= 360, 'the row fits the screen');
  assert.equal(await page.evaluate(() => document.documentElement.scrollWidth), 360, 'the page does not scroll sideways');
  const last = nav.locator('a').last();
  await last.scrollIntoViewIfNeeded();
  const reached = await last.boundingBox();
  assert.ok(reached.x >= 0 && reached.x + reached.width <= 360, 'the last link scrolls into view');
  await last.click();
  await page.waitForURL(/\/mrclam\/code$/);
  await page.close();
});

test('on a wide screen the workbench uses the room it has', bounded, async () => {
  const page = await browser.newPage({ viewport: { width: 1800, height: 1000 } });
  await page.goto(`${server.url}/ekf/code`);
  await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 120_000 });
  const editor = await page.locator('.editor').boundingBox();
  assert.ok(editor.width > 900, `the editor is ${editor.width} px wide at 1800 px`);
  await page.close();
});

test('a page that plots asks for its wasm module and its chunks at once, and the module is fetched once', bounded, async () => {
  for (const path of ['/car', '/ekf', '/odometry', '/fusion', '/mrclam']) {
    const context = await browser.newContext();
    const page = await context.newPage();
    const wasmRequests = [];
    page.on('request', (request) => { if (request.url().endsWith('.wasm')) wasmRequests.push(request.url()); });
    const warnings = [];
    page.on('console', (message) => { if (/preload/i.test(message.text())) warnings.push(message.text()); });
    await page.goto(server.url + path);
    await page.waitForSelector('body[data-ready=true]', { timeout: 60_000 });
    const links = await page.evaluate(() => [...document.head.querySelectorAll('link[rel=preload], link[rel=modulepreload]')]
      .map((link) => ({ rel: link.rel, href: link.href, as: link.getAttribute('as') })));
    const wasm = links.filter((l) => l.rel === 'preload' && l.as === 'fetch');
    assert.equal(wasm.length, 1, `${path}: one wasm preload`);
    assert.ok(links.some((l) => l.rel === 'modulepreload'), `${path}: its chunks preloaded`);
    // The preload is the very request the page's script makes: the module comes once.
    assert.deepEqual(wasmRequests, [wasm[0].href], `${path}: ${wasmRequests}`);
    assert.deepEqual(warnings, [], `${path}: the browser used what was preloaded`);
    await context.close();
  }
});
