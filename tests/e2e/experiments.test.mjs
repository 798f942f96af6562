// The experiment pages as a student meets them (issue 12), in headless Chromium against
// the real server: at a phone's size and a laptop's, nothing is wider than the screen and
// no control lies under a plot; /car plots the prior at t = 0; /ekf marks the run of a
// file that did not load, keeps the reader's settings when the data set changes, prints
// its command without float noise, marks the time slider's step on the plots over time,
// tells paths apart by line style, draws o3's ellipses large enough to see and says how
// much larger, resets its zoom; and every plot has a summary line in words.
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { bounded, correct, estlab, laptop, phone, tempDir, waitFor, withServerAndBrowser } from './harness.mjs';

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/**
 * A new page of `viewport`'s size that records console errors and uncaught exceptions in
 * `page.problems`, at `path` once its script says it is ready.
 */
async function open(path, viewport = laptop) {
  const page = await browser.newPage({ viewport });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  await page.goto(server.url + path);
  await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 60_000 });
  return page;
}

/** The data of the series `series` (its id or name) of the plot `plot`, as drawn. */
function seriesOf(page, plot, series) {
  return page.evaluate(([plot, series]) => {
    const { plot: p } = document.querySelector(`figure[data-name="${plot}"] .chart`);
    return p.series().find((s) => s.id === series || s.name === series) ?? null;
  }, [plot, series]);
}

/** The page's command-line flags. */
async function flags(page) {
  return JSON.parse(await page.locator('#command').getAttribute('data-flags'));
}

/** A number of a summary line: the one after `before` (a string that ends where it starts). */
function numberAfter(text, before) {
  const at = text.indexOf(before);
  assert.ok(at >= 0, `"${before}" in: ${text}`);
  return Number(text.slice(at + before.length).match(/^-?[\d.]+(e[-+]?\d+)?/)[0]);
}

/** Asserts that `got` is `expected` to the three significant digits of a summary line. */
function assertDigits(got, expected, what) {
  assert.ok(Math.abs(got - expected) <= 0.006 * Math.abs(expected), `${what}: ${got}, expected ${expected}`);
}

/**
 * The boxes, relative to the viewport, of what is shown: the page's controls (buttons,
 * fields, lists, labels, outside the plots: a plot's save buttons lie in its own
 * caption) and its plots.
 */
function boxes(page) {
  return page.evaluate(() => {
    const shown = (el) => el.getClientRects().length > 0 && getComputedStyle(el).visibility !== 'hidden';
    const box = (el) => {
      const r = el.getBoundingClientRect();
      return { left: r.left, top: r.top, right: r.right, bottom: r.bottom };
    };
    const name = (el) => `${el.tagName.toLowerCase()}${el.id ? `#${el.id}` : ''} "${(el.textContent || el.value || '').trim().slice(0, 30)}"`;
    const controls = [...document.querySelectorAll('main button, main input, main select, main label, main summary, main textarea')]
      .filter((el) => !el.closest('figure.plot') && shown(el))
      .map((el) => ({ what: name(el), ...box(el) }))
      .filter((b) => b.right > b.left && b.bottom > b.top);
    const plots = [...document.querySelectorAll('figure.plot')].filter(shown).map((el) => ({ what: el.dataset.name, ...box(el) }));
    return { controls, plots };
  });
}

const overlap = (a, b) => Math.min(a.right, b.right) - Math.max(a.left, b.left) > 0.5
  && Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) > 0.5;

test('every experiment page at 390 x 844 and 1400 x 1000: nothing wider than the screen, no control under a plot', bounded, async () => {
  for (const viewport of [phone, laptop]) {
    for (const path of ['/', '/car', '/ekf']) {
      const page = await open(path, viewport);
      const what = `${path} at ${viewport.width} x ${viewport.height}`;
      if (path === '/car') {
        // The Monte Carlo plots too.
        await page.locator('#runs').fill('20');
        await page.locator('#monte-carlo').check();
      }
      assert.ok(await page.evaluate(() => document.documentElement.scrollWidth) <= viewport.width, `${what}: no sideways scrolling`);
      // At the top, and scrolled to each plot: the settings stay in view beside the plots
      // on a wide screen, and must not lie over them anywhere.
      const tops = await page.evaluate(() => [0, ...[...document.querySelectorAll('figure.plot')]
        .filter((f) => f.getClientRects().length > 0)
        .map((f) => f.getBoundingClientRect().top + scrollY - 20)]);
      let checked = 0;
      for (const top of tops) {
        await page.evaluate((y) => window.scrollTo(0, y), top);
        const { controls, plots } = await boxes(page);
        if (path !== '/') assert.ok(controls.length > 0, `${what}: controls found`);
        for (const plot of plots) {
          for (const control of controls) {
            assert.ok(!overlap(plot, control), `${what}, scrolled to ${Math.round(top)}: ${control.what} ${JSON.stringify(control)} lies under the plot ${plot.what} ${JSON.stringify(plot)}`);
            checked++;
          }
        }
      }
      if (path !== '/') assert.ok(checked > 0, `${what}: plots and controls were compared`);
      assert.ok(await page.evaluate(() => document.documentElement.scrollWidth) <= viewport.width, `${what}: no sideways scrolling after the plots drew`);
      assert.deepEqual(page.problems, [], what);
      await page.close();
    }
  }
});

test('the car: the plots start with the prior at t = 0, so that a wrong start shows', bounded, async () => {
  const page = await open('/car');
  const { params } = JSON.parse(estlab('car', '--json'));
  const [mu0, x0] = [params.mu0[0], params.x0[0]];
  assert.equal(mu0, -2, "the lab's wrong start");
  const first = async (plot, series) => (await seriesOf(page, plot, series)).data[0];
  assert.deepEqual(await first('position', 'estimate'), [0, mu0], 'the estimate starts at μ₀ at t = 0');
  assert.deepEqual((await seriesOf(page, 'position', 'prior')).data, [[0, mu0]], 'the prior is marked');
  assert.deepEqual(await first('position', 'band ±2σ low'), [0, mu0 - 2 * Math.sqrt(params.sigma0[0][0])]);
  assert.deepEqual(await first('position', 'band ±2σ high'), [0, mu0 + 2 * Math.sqrt(params.sigma0[0][0])]);
  assert.deepEqual(await first('position', 'true'), [0, x0], 'the car starts at x₀');
  assert.deepEqual(await first('errors', 'position error (m)'), [0, mu0 - x0]);
  assert.deepEqual(await first('sigmas', '√P₁₁, position (m)'), [0, Math.sqrt(params.sigma0[0][0])]);
  // t = 0 is on the axis: drawn at the grid's left edge, not cut off.
  for (const plot of ['position', 'velocity', 'errors', 'sigmas', 'gains']) {
    const left = await page.evaluate((n) => document.querySelector(`figure[data-name="${n}"] .chart`).plot.chart.convertToPixel({ xAxisIndex: 0 }, 0), plot);
    assert.equal(left, 76, `${plot}: t = 0 at the left edge of the plot`);
  }
  // Another start, surer of itself: the prior follows the controls.
  await page.locator('#mu0-position').fill('3');
  await page.locator('button[data-preset="sigma0-down"]').click();
  assert.deepEqual(await first('position', 'estimate'), [0, 3]);
  const [low, high] = [(await first('position', 'band ±2σ low'))[1], (await first('position', 'band ±2σ high'))[1]];
  assert.ok(Math.abs(low - 2.8) < 1e-12 && Math.abs(high - 3.2) < 1e-12, `3 ± 2 × 0.1: ${low}, ${high}`);
  assert.match(await page.locator('figure[data-name="position"] .plot-summary').textContent(), /^Position from t = 0 to 10 s\. The prior at t = 0: 3 m ± 0\.2 m \(2σ\), the car at 1 m\./);
  // Monte Carlo: the filter's σ and the mean error start from the prior too.
  await page.locator('#runs').fill('20');
  await page.locator('#monte-carlo').check();
  assert.deepEqual(await first('bias', 'position (m)'), [0, 3 - x0]);
  assert.deepEqual(await first('spread', 'filter σ, position (m)'), [0, 0.1]);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the car: the Monte Carlo plots keep their legend off the y axis\'s title, and no title is cut', bounded, async () => {
  const page = await open('/car');
  await page.locator('#runs').fill('20');
  await page.locator('#monte-carlo').check();
  for (const plot of ['spread', 'bias', 'position', 'gains']) {
    const layout = await page.evaluate((n) => {
      const { plot } = document.querySelector(`figure[data-name="${n}"] .chart`);
      plot.flush();
      const option = plot.chart.getOption();
      return { width: plot.chart.getWidth(), yAxis: option.yAxis[0], grid: option.grid[0], legendTop: option.legend[0].top };
    }, plot);
    // The title runs up the side of the y axis, between the chart's edge and its labels;
    // the legend is a line above the plot area.
    assert.equal(layout.yAxis.nameLocation, 'middle', plot);
    assert.ok(layout.yAxis.nameGap < layout.grid.left, `${plot}: the y title lies inside the chart`);
    assert.ok(layout.legendTop + 20 <= layout.grid.top, `${plot}: the legend lies above the plot area`);
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: a file that does not load leaves no summary or command of another run, and marks the old plots', bounded, async () => {
  const dir = tempDir();
  estlab('simulate', '--kind', 'o3', '--seed', '5', '--out', dir);
  const broken = join(dir, 'so_broken.txt');
  const lines = readFileSync(join(dir, 'so_o3_5.txt'), 'utf8').split('\n');
  lines[4] = lines[4].split(' ').slice(0, -2).join(' ');
  writeFileSync(broken, lines.join('\n'));
  const page = await open('/ekf');
  const before = await page.locator('#summary').textContent();
  assert.match(before, /mean absolute error/);
  await page.locator('#dataset-kind').selectOption('files');
  await page.locator('#map-file').setInputFiles(join(dir, 'map_o3_5.txt'));
  await page.locator('#sensor-file').setInputFiles(broken);
  // The message before the file's ("Choose a map file ...") stays until the page has read it.
  await page.waitForFunction(() => document.getElementById('error').textContent.startsWith('so_broken.txt'));
  assert.match(await page.locator('#error').textContent(), /^so_broken\.txt:5: /);
  assert.equal(await page.locator('#stale').isVisible(), true);
  assert.match(await page.locator('#stale').textContent(), /still those of the last run, on o3, seed 1, dimmed/);
  assert.equal(await page.locator('#summary').isVisible(), false);
  assert.equal(await page.locator('#summary').textContent(), '');
  assert.equal(await page.locator('#command').textContent(), '');
  assert.ok(await page.locator('#ekf-plots').evaluate((el) => el.classList.contains('stale')));
  // Settings moved meanwhile run nothing: there is no data set to run them on.
  await page.locator('#q-range').fill('0.3');
  assert.equal(await page.locator('#summary').isVisible(), false);
  assert.equal(await page.locator('#command').textContent(), '');
  // Back to a simulated data set: a run of its own, current again.
  await page.locator('#dataset-kind').selectOption('outliers');
  await page.locator('#error').waitFor({ state: 'hidden' });
  assert.equal(await page.locator('#stale').isVisible(), false);
  assert.match(await page.locator('#summary').textContent(), /mean absolute error/);
  assert.match(await page.locator('#command').textContent(), /--kind outliers --seed 1 /);
  assert.ok(!await page.locator('#ekf-plots').evaluate((el) => el.classList.contains('stale')));
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: another data set keeps the settings the reader changed, says so, and "the lab\'s settings" sets the lab\'s', bounded, async () => {
  const page = await open('/ekf');
  const note = page.locator('#settings-note');
  const labO3 = ['--R', '0.0001,0.0001,0.000304617419787', '--Q', '0.0001,0.000304617419787', '--delta-m', '0.999'];
  assert.deepEqual(await flags(page), labO3);
  assert.equal(await note.textContent(), "These are the lab's settings for o3.");
  // Untouched settings follow the data: the lab's for each kind.
  await page.locator('#dataset-kind').selectOption('no-odometry');
  assert.deepEqual(await flags(page), ['--R', '1,1,1', '--Q', '0.01,0.01', '--delta-m', '1', '--batch']);
  assert.equal(await note.textContent(), "These are the lab's settings for no-odometry.");
  await page.locator('#dataset-kind').selectOption('o3');
  assert.deepEqual(await flags(page), labO3);
  // The reader's own R stays when the data set changes; Q, untouched, becomes the new data's.
  await page.locator('#r-x').fill('0.05');
  assert.equal(await note.textContent(), "Your own settings: R differs from the lab's settings for o3; the button “the lab's settings” sets those.");
  await page.locator('#dataset-kind').selectOption('outliers');
  assert.equal(await page.locator('#r-x').inputValue(), '0.05');
  assert.deepEqual(await flags(page), ['--R', '0.0025,0.0001,0.000304617419787', '--Q', '0.04,0.04', '--delta-m', '0.999']);
  assert.equal(await note.textContent(),
    "Your settings, kept when the data set changed: R differs from the lab's settings for outliers; the button “the lab's settings” sets those.");
  await page.locator('#dataset-seed').fill('7');
  await page.locator('#dataset-seed').dispatchEvent('change');
  assert.match(await page.locator('#command').textContent(), /--seed 7 .* --R 0\.0025,/);
  await page.locator('#lab-settings').click();
  assert.deepEqual(await flags(page), ['--R', '0.0001,0.0001,0.000304617419787', '--Q', '0.04,0.04', '--delta-m', '0.999']);
  assert.equal(await note.textContent(), "These are the lab's settings for outliers.");
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: the command carries the numbers typed, without float noise, and runs what the page ran', bounded, async () => {
  const page = await open('/ekf');
  await page.locator('#q-range').fill('0.2');
  await page.locator('#q-bearing').fill('2');
  await page.locator('#r-y').fill('0.3');
  const command = await page.locator('#command').textContent();
  assert.ok(!command.includes('0.04000000000000001'), command);
  assert.match(command, / --R 0\.0001,0\.09,0\.000304617419787 --Q 0\.04,0\.00121846967915 --delta-m 0\.999$/);
  for (const number of command.match(/--[RQ] (\S+)/g).flatMap((flag) => flag.split(' ')[1].split(','))) {
    assert.ok(number.replace(/^0\.0*/, '').replace('.', '').length <= 12, `${number} in ${command}`);
  }
  const dir = tempDir();
  estlab('simulate', '--kind', 'o3', '--seed', '1', '--out', dir);
  const report = estlab('run', join(dir, 'so_o3_1.txt'), join(dir, 'map_o3_1.txt'), ...await flags(page))
    .split('\n').filter((l) => /^(mean|rejected)/.test(l)).join('\n');
  assert.equal((await page.locator('#summary').textContent()).trim(), report);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: the time slider\'s step is marked on the plots over time, and follows the slider', bounded, async () => {
  const page = await open('/ekf');
  const t = (await seriesOf(page, 'errorX', 'estimate − truth')).data.map(([x]) => x);
  let previous = null;
  for (const k of [100, 300]) {
    await page.locator('#time').fill(String(k));
    for (const plot of ['errorX', 'errorY', 'errorTheta', 'covariance']) {
      const figure = page.locator(`figure[data-name="${plot}"]`);
      await figure.scrollIntoViewIfNeeded();
      const marker = figure.locator('.marker');
      await marker.waitFor({ state: 'visible', timeout: 10_000 });
      assert.equal(Number(await marker.getAttribute('data-x')), t[k], `${plot}: the marker is at step ${k + 1}`);
      // Where the chart draws t[k], within a pixel: the chart's own axis places it.
      const [at, x] = await page.evaluate(([plot, time]) => {
        const chart = document.querySelector(`figure[data-name="${plot}"] .chart`);
        const marker = document.querySelector(`figure[data-name="${plot}"] .marker`);
        const middle = marker.getBoundingClientRect();
        return [(middle.left + middle.right) / 2 - chart.getBoundingClientRect().left, chart.plot.chart.convertToPixel({ xAxisIndex: 0 }, time)];
      }, [plot, t[k]]);
      assert.ok(Math.abs(at - x) <= 1.5, `${plot}: the marker is drawn at t = ${t[k]}: ${at} px, the axis puts it at ${x} px`);
      if (plot === 'errorX') {
        if (previous !== null) assert.ok(at > previous, 'a later step lies further right');
        previous = at;
      }
    }
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the EKF: the truth is solid, the estimate dashed, odometry dotted, and the legends say so', bounded, async () => {
  const page = await open('/ekf');
  const styles = {};
  for (const [id, word] of [['true', 'solid'], ['estimate', 'dashed'], ['odometry only', 'dotted']]) {
    const series = await seriesOf(page, 'map', id);
    assert.ok(series.name.endsWith(`(${word})`), `the legend says "${series.name}"`);
    styles[id] = JSON.stringify(series.lineStyle.type);
  }
  assert.equal(new Set(Object.values(styles)).size, 3, `three line styles: ${JSON.stringify(styles)}`);
  assert.equal(styles.true, '"solid"');
  // As saved: the estimate's path is dashed in the SVG, the truth's is not.
  const svg = await page.evaluate(() => document.querySelector('figure[data-name="map"] .chart').plot.svg());
  const paths = [...svg.matchAll(/<path\b[^>]*>/g)].map(([p]) => p);
  assert.ok(paths.some((p) => p.includes('stroke="#c62828"') && p.includes('stroke-dasharray')), 'the estimate is dashed in the SVG');
  assert.ok(paths.some((p) => p.includes('stroke="#2e7d32"') && !p.includes('stroke-dasharray')), 'the truth is solid in the SVG');
  assert.match(await page.locator('figure[data-name="map"] figcaption').textContent(), /true \(green, solid\), estimated \(red, dashed\) and odometry-only \(blue, dotted\)/);
  const car = await open('/car');
  const [truth, estimate] = [await seriesOf(car, 'position', 'true'), await seriesOf(car, 'position', 'estimate')];
  assert.notDeepEqual(truth.lineStyle.type, estimate.lineStyle.type);
  assert.deepEqual([truth.name, estimate.name], ['true (solid)', 'estimate (dashed)']);
  assert.deepEqual([...page.problems, ...car.problems], []);
  await car.close();
  await page.close();
});

test('the EKF map: on o3 the ellipses are drawn large enough to see, by a factor the legend states; the zoom says how and resets', bounded, async () => {
  const page = await open('/ekf');
  await page.locator('figure[data-name="map"]').scrollIntoViewIfNeeded();
  const ellipses = async () => page.evaluate(() => {
    const { plot } = document.querySelector('figure[data-name="map"] .chart');
    const series = plot.series().find((s) => s.id === 'ellipses');
    // The largest extent of each ellipse in pixels, as the chart's axes place it.
    const across = series.data.map(({ coords }) => {
      const px = coords.map((c) => plot.chart.convertToPixel({ gridIndex: 0 }, c));
      const xs = px.map(([x]) => x);
      const ys = px.map(([, y]) => y);
      return Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys));
    }).sort((a, b) => a - b);
    const legend = plot.chart.getOption().series.find((s) => s.id === 'ellipses').name;
    return { name: series.name, legend, median: across[Math.floor(across.length / 2)], count: across.length };
  });
  const auto = await ellipses();
  const factor = Number(auto.name.match(/^3σ ellipses, drawn ×(\d+)$/)?.[1]);
  assert.ok(factor > 1, `o3's ellipses are enlarged: ${JSON.stringify(auto)}`);
  assert.equal(auto.legend, auto.name, 'the legend states the factor');
  assert.ok(auto.median >= 4, `the typical ellipse is ${auto.median} px across`);
  assert.match(await page.locator('#ellipse-note').textContent(), new RegExp(`^drawn ${factor} times their size \\(typically [\\d.e-]+ m across`));
  assert.match(await page.locator('figure[data-name="map"] .plot-summary').textContent(), new RegExp(`3σ ellipses every \\d+th step, typically [\\d.e-]+ m across, drawn ${factor} times their size\\.$`));
  await page.locator('#ellipse-scale').selectOption('1');
  const trueSize = await ellipses();
  assert.equal(trueSize.name, '3σ ellipses');
  assert.equal(trueSize.legend, '3σ ellipses');
  assert.ok(Math.abs(trueSize.median * factor - auto.median) < 0.05 * auto.median, `${trueSize.median} px × ${factor} = ${auto.median} px`);
  assert.match(await page.locator('#ellipse-note').textContent(), /^at their true size/);

  // The zoom: said where the map is, and undone by a button.
  assert.equal(await page.locator('#zoom-hint').isVisible(), true);
  assert.match(await page.locator('#zoom-hint').textContent(), /wheel/);
  const reset = page.locator('#map-reset');
  assert.equal(await reset.isDisabled(), true, 'nothing to reset yet');
  const zoom = () => page.evaluate(() => document.querySelector('figure[data-name="map"] .chart').plot.chart.getOption().dataZoom.map((z) => [z.start, z.end]));
  const box = await page.locator('figure[data-name="map"] .chart').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel(0, -600);
  await waitFor('the map to zoom in', zoom, (z) => z.every(([start, end]) => end - start < 100), { timeout: 10_000, interval: 100 });
  assert.equal(await reset.isDisabled(), false, 'zoomed in: the reset is offered');
  await reset.click();
  assert.deepEqual(await zoom(), [[0, 100], [0, 100]], 'the whole map again');
  assert.equal(await reset.isDisabled(), true);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('every plot says what it shows in a summary line, with the run\'s numbers', bounded, async () => {
  const summaries = (page) => page.evaluate(() => Object.fromEntries([...document.querySelectorAll('figure.plot')]
    .filter((f) => !f.closest('[hidden]'))
    .map((f) => [f.dataset.name, f.querySelector('.plot-summary')?.textContent ?? null])));
  const car = await open('/car');
  await car.locator('#runs').fill('20');
  await car.locator('#monte-carlo').check();
  const carLines = await summaries(car);
  assert.deepEqual(Object.keys(carLines), ['position', 'velocity', 'errors', 'sigmas', 'gains', 'spread', 'bias']);
  for (const [name, text] of Object.entries(carLines)) assert.match(text, /\d.*\.$/, `/car ${name}: ${text}`);
  // The canvas is hidden from screen readers; the line is read in its place.
  assert.equal(await car.locator('figure[data-name="position"] .chart').getAttribute('aria-hidden'), 'true');
  await car.close();

  const page = await open('/ekf');
  const lines = await summaries(page);
  assert.deepEqual(Object.keys(lines), ['map', 'errorX', 'errorY', 'errorTheta', 'covariance']);
  const report = await page.locator('#summary').textContent();
  const meanAbsolute = report.match(/mean absolute error \(x, y, theta\): \(([-\d.]+), ([-\d.]+), ([-\d.]+)\)/).slice(1).map(Number);
  ['errorX', 'errorY', 'errorTheta'].forEach((plot, i) => {
    assert.match(lines[plot], /^Error in (x|y|θ) over \d+ steps \(t = [\d.]+ to [\d.]+ s\): mean /);
    assertDigits(numberAfter(lines[plot], 'mean absolute '), meanAbsolute[i], `${plot}: the mean absolute error`);
  });
  const rejected = Number(report.match(/rejected readings: (\d+) of/)[1]);
  assert.match(lines.map, new RegExp(`; ${rejected} readings? rejected `));
  assert.match(lines.covariance, /^The covariance diagonal on a log scale over \d+ steps/);
  // Another run, other numbers.
  await page.locator('#q-range').fill('0.1');
  const after = await summaries(page);
  assert.notEqual(after.errorX, lines.errorX);
  const again = (await page.locator('#summary').textContent()).match(/mean absolute error \(x, y, theta\): \(([-\d.]+),/)[1];
  assertDigits(numberAfter(after.errorX, 'mean absolute '), Number(again), 'errorX after the change');
  assert.deepEqual(page.problems, []);
  await page.close();

  // The workbench's runs use the same views, summary lines included.
  const code = await open('/ekf/code');
  await code.locator('.cm-content').click();
  await code.keyboard.press('Control+A');
  await code.keyboard.press('Delete');
  await code.keyboard.insertText(correct);
  await code.locator('#run-datasets').click();
  await code.waitForFunction(() => document.getElementById('stop').disabled && !document.getElementById('runs').hidden, null, { timeout: 120_000 });
  const runLines = await summaries(code);
  assert.deepEqual(Object.keys(runLines), ['map', 'errorX', 'errorY', 'errorTheta', 'covariance']);
  assert.match(runLines.errorX, /^Error in x over \d+ steps .*mean absolute [\d.e-]+ m/);
  assert.match(runLines.map, /^The map: \d+ landmarks/);
  assert.deepEqual(code.problems, []);
  await code.close();
});
