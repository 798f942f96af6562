// The odometry experiment (/odometry) in headless Chromium against the real server: it
// loads cleanly, every control changes what is drawn and said, a path drawn with clicks
// is driven, a bad setting shows the library's message naming the field and dims the
// last good plots, its numbers are those `estlab odometry --json` prints for the same
// settings, and nothing spills over or hides under a plot at a phone's size or a laptop's.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { spawnSync } from 'node:child_process';
import { bounded, estlab, estlabBinary, laptop, phone, withServerAndBrowser } from './harness.mjs';

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

/** /odometry at `viewport`'s size once its script is ready, console errors in `page.problems`. */
async function open(viewport = laptop) {
  const page = await browser.newPage({ viewport });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  await page.goto(`${server.url}/odometry`);
  await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 60_000 });
  return page;
}

/**
 * What the page shows now, as data: each plot's summary line, axes and series (every
 * series' numbers folded into a count and a weighted sum), every table cell's exact
 * number, the systematic summary, the error, which views are dimmed, and the command's
 * flags.
 */
function state(page) {
  return page.evaluate(() => {
    const digest = (value) => {
      let [count, sum] = [0, 0];
      const visit = (v) => {
        if (typeof v === 'number') {
          if (Number.isFinite(v)) sum += v * (1 + (count % 7));
          count++;
        } else if (v && typeof v === 'object') {
          for (const inner of (ArrayBuffer.isView(v) ? v : Object.values(v))) visit(inner);
        }
      };
      visit(value);
      return `${count}:${sum}`;
    };
    const plots = {};
    for (const figure of document.querySelectorAll('figure.plot')) {
      const { plot } = figure.querySelector('.chart');
      const series = Object.fromEntries(plot.series().map((s) => [s.id, { name: s.name, data: digest(s.data) }]));
      const option = plot.chart.getOption();
      plots[figure.dataset.name] = {
        summary: figure.querySelector('.plot-summary').textContent,
        axes: [option.xAxis[0].min, option.xAxis[0].max, option.yAxis[0].min, option.yAxis[0].max],
        series,
      };
    }
    const cells = {};
    for (const cell of document.querySelectorAll('table [data-value]')) {
      const table = cell.closest('table').id;
      const row = cell.closest('tr').dataset.row ?? cell.id;
      cells[`${table}/${row}/${cell.cellIndex}`] = Number(cell.dataset.value);
    }
    const command = document.getElementById('command');
    return {
      plots,
      cells,
      systematic: document.getElementById('systematic-summary').textContent,
      systematicError: JSON.parse(document.getElementById('systematic-summary').dataset.error ?? 'null'),
      error: document.getElementById('error').hidden ? null : document.getElementById('error').textContent,
      stale: [...document.querySelectorAll('section.view.stale')].map((s) => s.id),
      flags: command.dataset.flags ? JSON.parse(command.dataset.flags) : null,
    };
  });
}

/** Asserts that two numbers are the same double (0 and -0 alike: a cell's text has no sign of zero). */
function same(got, expected, what) {
  assert.ok(got === expected, `${what}: the page has ${got}, estlab odometry ${expected}`);
}

/** Asserts `same` of each number of two lists. */
function sameAll(got, expected, what) {
  assert.equal(got.length, expected.length, `${what}: as many numbers`);
  got.forEach((v, i) => same(v, expected[i], `${what}[${i}]`));
}

/** The value of `flag` in `flags`. */
const flagValue = (flags, flag) => flags[flags.indexOf(flag) + 1];

test('/odometry loads cleanly and says in words and tables what every plot shows', bounded, async () => {
  const page = await open();
  const s = await state(page);
  assert.deepEqual(Object.keys(s.plots), ['path', 'position-std', 'heading-std', 'systematic', 'umbmark-paths', 'umbmark-errors']);
  for (const [name, plot] of Object.entries(s.plots)) {
    assert.match(plot.summary, /\d.*\.$/, `${name}: ${plot.summary}`);
  }
  assert.match(s.plots.path.summary, /^The counter-clockwise square of side 4 m: 344 steps from \(0, 0\) to \(0, 0\) m\. 3σ ellipses every 17 steps \(21 of them\)/);
  assert.match(s.plots.path.summary, /1000 robots \(seed 1\) end with a spread of .* of them inside the last 3σ ellipse, where a Gaussian puts 98\.89 %\.$/);
  assert.equal(s.cells['covariance-table/inside/1'], 1 - Math.exp(-4.5), 'the Gaussian share');
  assert.match(await page.locator('#covariance-table').textContent(), /inside the 3σ ellipse98\.89 %\d+(\.\d+)? %/);
  assert.equal(await page.locator('#robots-heading').textContent(), '1000 robots');
  assert.match(s.systematic, /^After 344 steps the robot is [\d.]+ m from where its odometry believes it is/);
  assert.ok(Number.isFinite(s.cells['umbmark-table/e-max/1']), 'E_max,syst in the table');
  assert.deepEqual(s.flags, ['--shape', 'square', '--size', '4', '--direction', 'ccw', '--speed', '0.05', '--wheel-base', '0.35',
    '--k-r', '0.0001', '--k-l', '0.0001', '--sigma0', '0,0,0', '--monte-carlo', '1000', '--seed', '1',
    '--e-d', '1.002', '--e-b', '1.01', '--umbmark', '4', '--runs', '5']);
  assert.equal(await page.locator('#command').textContent(), `estlab odometry ${s.flags.join(' ')}`);
  assert.deepEqual([s.error, s.stale], [null, []]);
  // The canvas is hidden from screen readers; the line is read in its place.
  assert.equal(await page.locator('figure[data-name="path"] .chart').getAttribute('aria-hidden'), 'true');
  // Saved as SVG, the path plot has both its layers: the path and the ellipses over it.
  const svg = await page.evaluate(() => document.querySelector('figure[data-name="path"] .chart').plot.svg());
  assert.match(svg, /^<svg\b/);
  assert.ok(svg.includes('stroke="#1565c0"') && svg.includes('stroke="#c62828"'), 'the path (blue) and the ellipses (red) in the SVG');
  // The site leads here.
  assert.equal(await page.locator('header.site nav a[href="/odometry"]').getAttribute('aria-current'), 'page');
  await page.goto(`${server.url}/`);
  assert.equal(await page.locator('.exercises a[href="/odometry"]').count(), 1);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('every control changes the plots and their text', bounded, async () => {
  const page = await open();
  const first = await state(page);
  let last = first;
  /**
   * Does `act`, then asserts that the plots `changed` (names) changed their series or
   * summary and the others did not, that the flags say `flag` (or change as the command
   * line does), and returns the new state.
   */
  const check = async (what, act, { changed, flag = null, axesOnly = [] }) => {
    await act();
    const now = await state(page);
    assert.equal(now.error, null, `${what}: no error`);
    for (const name of Object.keys(now.plots)) {
      const [before, after] = [last.plots[name], now.plots[name]];
      const differs = JSON.stringify([before.series, before.summary]) !== JSON.stringify([after.series, after.summary]);
      if (axesOnly.includes(name)) {
        assert.ok(!differs, `${what}: ${name} keeps its data`);
        assert.notDeepEqual(after.axes, before.axes, `${what}: ${name} shows another part of the plane`);
      } else {
        assert.equal(differs, changed.includes(name), `${what}: ${name} ${changed.includes(name) ? 'changes' : 'stays'}`);
      }
    }
    if (flag) assert.equal(flagValue(now.flags, flag[0]), flag[1], `${what}: ${flag[0]}`);
    last = now;
    return now;
  };
  const belief = ['path', 'position-std', 'heading-std'];
  const systematic = ['systematic'];
  const umbmark = ['umbmark-paths', 'umbmark-errors'];

  // The other way round the heading's errors are the same (the wheels' roles swap on the
  // turns, and k_r = k_l), its position's are not.
  await check('a clockwise square', () => page.locator('#direction').selectOption('clockwise'), { changed: ['path', 'position-std', ...systematic], flag: ['--direction', 'cw'] });
  await check('its side', () => page.locator('#size').fill('3'), { changed: [...belief, ...systematic], flag: ['--size', '3'] });
  await check('a straight line', () => page.locator('#shape').selectOption('line'), { changed: [...belief, ...systematic], flag: ['--shape', 'line'] });
  assert.equal(flagValue(last.flags, '--size'), '4', "the line's own length");
  assert.equal(last.flags.includes('--direction'), false, 'a line has no direction');
  assert.equal(await page.locator('#direction').isVisible(), false);
  assert.equal(await page.locator('#size-name').textContent(), 'length');
  await check('a circle', () => page.locator('#shape').selectOption('circle'), { changed: [...belief, ...systematic], flag: ['--size', '2'] });
  await check('a figure eight', () => page.locator('#shape').selectOption('figure-eight'), { changed: [...belief, ...systematic], flag: ['--shape', 'figure-eight'] });
  await check('back to the square', () => page.locator('#shape').selectOption('square'), { changed: [...belief, ...systematic], flag: ['--size', '3'] });
  await check('the speed', () => page.locator('#speed').fill('-1'), { changed: [...belief, ...systematic, ...umbmark], flag: ['--speed', '0.1'] });
  await check('the wheel base', () => page.locator('#wheel-base').fill('0.5'), { changed: [...belief, ...systematic, ...umbmark], flag: ['--wheel-base', '0.5'] });
  await check('k_r', () => page.locator('#k-r').fill('-3'), { changed: [...belief, ...umbmark], flag: ['--k-r', '0.001'] });
  await check('k_l', () => page.locator('#k-l').fill('-5'), { changed: [...belief, ...umbmark], flag: ['--k-l', '0.00001'] });
  await check('the heading σ at the start', () => page.locator('#sigma-theta').fill('5'), { changed: belief, flag: ['--sigma0', `0,0,${Number((((5 * Math.PI) / 180) ** 2).toPrecision(12))}`] });
  // The heading's errors do not depend on where the robot starts.
  await check('the position σ at the start', () => page.locator('#sigma-xy').fill('10'), { changed: ['path', 'position-std'] });
  assert.match(flagValue(last.flags, '--sigma0'), /^0\.01,0\.01,0\.0076/);
  const before = last;
  await check('the number of robots', () => page.locator('#robots').fill('500'), { changed: belief, flag: ['--monte-carlo', '500'] });
  // The propagated σ stay; the robots' spread beside them moves.
  assert.equal(last.plots['position-std'].series.σx.data, before.plots['position-std'].series.σx.data);
  assert.notEqual(last.plots['position-std'].series['robots 0'].data, before.plots['position-std'].series['robots 0'].data);
  await check('the seed', () => page.locator('#seed').fill('7'), { changed: ['path', 'position-std', 'heading-std', ...umbmark], flag: ['--seed', '7'] });
  await check('the ellipses every 10 steps', () => page.locator('#ellipse-every').selectOption('10'), { changed: ['path'] });
  assert.match(last.plots.path.summary, /3σ ellipses every 10 steps/);
  await check('the robots along the way', () => page.locator('#clouds').check(), { changed: belief });
  assert.match(last.plots.path.summary, /The robots are also drawn at \d+ steps along the way\.$/);
  assert.match(last.plots.path.series.clouds.data, /^[1-9]\d*:/);
  await check('the end only', () => page.locator('#map-view').selectOption('end'), { changed: [], axesOnly: ['path'] });
  await check('E_d', () => page.locator('#e-d').fill('0.99'), { changed: [...systematic, ...umbmark], flag: ['--e-d', '0.99'] });
  await check('E_b', () => page.locator('#e-b').fill('1.03'), { changed: [...systematic, ...umbmark], flag: ['--e-b', '1.03'] });
  await check("UMBmark's side", () => page.locator('#umbmark-side').fill('2'), { changed: umbmark, flag: ['--umbmark', '2'] });
  await check("UMBmark's runs", () => page.locator('#umbmark-runs').fill('8'), { changed: umbmark, flag: ['--runs', '8'] });
  assert.match(last.plots['umbmark-errors'].summary, /^Return errors \(true minus odometry\) of 8 runs each way\./);
  await check('the banana', () => page.locator('#banana').click(), { changed: [...belief, ...systematic, ...umbmark] });
  assert.deepEqual(['--shape', '--size', '--k-r', '--k-l'].map((flag) => flagValue(last.flags, flag)), ['line', '8', '0.000001', '0.000001']);
  assert.match(flagValue(last.flags, '--sigma0'), /^0,0,0\.0685389/);
  await check('every setting as at first', () => page.locator('#reset').click(), { changed: [...belief, ...systematic, ...umbmark], flag: ['--shape', 'square'] });
  assert.deepEqual(last.flags, first.flags);
  assert.deepEqual(last.plots.path.axes, first.plots.path.axes, 'the whole path shown again');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a path drawn with mouse clicks is driven, and its points can be typed and taken back', bounded, async () => {
  const page = await open();
  await page.locator('#shape').selectOption('polyline');
  assert.equal(await page.locator('#draw-hint').isVisible(), true);
  assert.equal(await page.locator('#size').isVisible(), false);
  assert.match(await page.locator('#points-value').textContent(), /^No points yet/);
  assert.equal(await page.locator('#error').isVisible(), false, 'no error before the first click');
  assert.match((await state(page)).plots.path.summary, /^No path yet: 0 points drawn/);
  const chart = page.locator('figure[data-name="path"] .chart');
  await chart.scrollIntoViewIfNeeded();
  const box = await chart.boundingBox();
  const targets = [[0, 0], [3, 0], [3, 2]];
  for (const [i, target] of targets.entries()) {
    // Where the chart's axes put the target now (they follow the points), once the plot,
    // scrolled into view, has drawn what it kept while out of view.
    const [px, py] = await page.evaluate((at) => {
      const { plot } = document.querySelector('figure[data-name="path"] .chart');
      plot.flush();
      return plot.chart.convertToPixel({ gridIndex: 0 }, at);
    }, target);
    await page.mouse.click(box.x + px, box.y + py);
    await page.waitForFunction((n) => document.getElementById('points').value.split(';').length === n, i + 1);
  }
  const s = await state(page);
  assert.equal(s.error, null);
  const points = flagValue(s.flags, '--points').split(';').map((p) => p.split(',').map(Number));
  assert.equal(points.length, 3);
  points.forEach(([x, y], i) => {
    assert.ok(Math.hypot(x - targets[i][0], y - targets[i][1]) < 0.06, `point ${i}: clicked at ${targets[i]}, got ${x},${y}`);
  });
  assert.equal(s.flags.includes('--shape'), false);
  assert.equal(await page.locator('#points').inputValue(), points.map(([x, y]) => `${x},${y}`).join('; '));
  assert.match(s.plots.path.summary, /^The path through your 3 points: \d+ steps from /);
  const path = await page.evaluate(() => document.querySelector('figure[data-name="path"] .chart').plot.series().find((series) => series.id === 'path').data);
  assert.deepEqual(path[0], points[0], 'the robot starts at the first point');
  const end = path.at(-1);
  assert.ok(Math.hypot(end[0] - points[2][0], end[1] - points[2][1]) < 1e-9, `and ends at the last: ${end}`);
  // The same path on the command line ends there too.
  const native = JSON.parse(estlab('odometry', '--json', ...s.flags));
  sameAll(end, native.propagation.poses.at(-1).slice(0, 2), 'the end');

  await page.locator('#undo-point').click();
  assert.equal(await page.locator('#points').inputValue(), points.slice(0, 2).map(([x, y]) => `${x},${y}`).join('; '));
  assert.match((await state(page)).plots.path.summary, /^The path through your 2 points/);
  await page.locator('#points').fill('0,0; 2,0; 2,2; 0,2; 0,0');
  assert.match((await state(page)).plots.path.summary, /^The path through your 5 points/);
  assert.equal(flagValue((await state(page)).flags, '--points'), '0,0;2,0;2,2;0,2;0,0');
  await page.locator('#points').fill('0,0; 2,x');
  const bad = await state(page);
  assert.equal(bad.error, 'shape.points: point 1 must be two numbers x,y, got "2,x"');
  assert.deepEqual(bad.stale, ['belief-view', 'systematic-view']);
  await page.locator('#points').fill('1,1; 1,1');
  const repeated = await state(page);
  assert.equal(repeated.error, null, 'one distinct point: no path yet, no error');
  assert.match(repeated.plots.path.summary, /^No path yet: 2 points drawn/);
  await page.locator('#clear-points').click();
  assert.equal(await page.locator('#points').inputValue(), '');
  assert.deepEqual(page.problems, []);
  await page.close();
});

/** The message `estlab odometry` gives for `flags`, without its "estlab: ". */
function nativeError(...flags) {
  const run = spawnSync(estlabBinary, ['odometry', ...flags], { encoding: 'utf8' });
  assert.notEqual(run.status, 0, `estlab odometry ${flags.join(' ')} fails`);
  return run.stderr.trim().replace(/^estlab: /, '');
}

test('a bad setting shows the library\'s message naming the field and keeps the last good plots, dimmed', bounded, async () => {
  const page = await open();
  const good = await state(page);
  await page.locator('#size').fill('0');
  const bad = await state(page);
  assert.equal(bad.error, nativeError('--size', '0'));
  assert.equal(bad.error, 'shape.side: must lie in (0, 1e6] metres, got 0');
  assert.deepEqual(bad.stale, ['belief-view', 'systematic-view'], 'the UMBmark square is its own');
  assert.equal(await page.locator('#belief-stale').isVisible(), true);
  assert.match(await page.locator('#belief-stale').textContent(), /still those of the last settings that ran, dimmed/);
  assert.equal(await page.locator('#umbmark-stale').isVisible(), false);
  assert.deepEqual(bad.plots.path, good.plots.path, 'the last good plot stays');
  assert.deepEqual(bad.cells, good.cells, 'and its numbers');
  assert.equal(bad.flags, null);
  assert.equal(await page.locator('#command').isVisible(), false, 'no command for settings that do not run');
  // The drawings are dimmed, not the text about them (see rough-edges.test.mjs).
  const opacity = await page.locator('#belief-view figure.plot > :is(.chart, .stack)').first().evaluate((el) => Number(getComputedStyle(el).opacity));
  assert.ok(opacity < 1, `dimmed: opacity ${opacity}`);
  // Another bad setting, of another view.
  await page.locator('#size').fill('4');
  await page.locator('#robots').fill('1');
  const few = await state(page);
  assert.equal(few.error, nativeError('--monte-carlo', '1'));
  assert.equal(few.error, 'robots: must lie in 2..=100000, got 1');
  assert.deepEqual(few.stale, ['belief-view']);
  await page.locator('#umbmark-runs').fill('0');
  const both = await state(page);
  assert.equal(both.error, ['robots: must lie in 2..=100000, got 1', nativeError('--umbmark', '--runs', '0')].join('\n'));
  assert.deepEqual(both.stale, ['belief-view', 'umbmark-view']);
  // Good settings again: current, and the same as at first.
  await page.locator('#robots').fill('1000');
  await page.locator('#umbmark-runs').fill('5');
  const again = await state(page);
  assert.deepEqual([again.error, again.stale], [null, []]);
  assert.deepEqual(again.cells, good.cells);
  assert.deepEqual(again.flags, good.flags);
  assert.equal(await page.locator('#belief-stale').isVisible(), false);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the numbers shown are those estlab odometry --json prints for the same settings', bounded, async () => {
  const page = await open();
  const settings = [
    ['the defaults', async () => {}],
    ['a line with an uncertain heading, ellipses along the way', async () => {
      await page.locator('#shape').selectOption('line');
      await page.locator('#size').fill('6');
      await page.locator('#sigma-theta').fill('12.5');
      await page.locator('#k-l').fill('-3.5');
      await page.locator('#clouds').check();
    }],
    ['a figure eight, other robots, wheels and wheel base', async () => {
      await page.locator('#shape').selectOption('figure-eight');
      await page.locator('#robots').fill('300');
      await page.locator('#seed').fill('42');
      await page.locator('#speed').fill('-1.5');
      await page.locator('#wheel-base').fill('0.27');
      await page.locator('#sigma-xy').fill('3');
      await page.locator('#e-d').fill('1.0135');
      await page.locator('#e-b').fill('0.962');
      await page.locator('#umbmark-runs').fill('12');
    }],
    ['a drawn path', async () => {
      await page.locator('#shape').selectOption('polyline');
      await page.locator('#points').fill('0.5,-1; 2.25,-1; 2.25,1.5; -0.75,0.3');
    }],
  ];
  for (const [what, act] of settings) {
    await act();
    const s = await state(page);
    assert.equal(s.error, null, what);
    const native = JSON.parse(estlab('odometry', '--json', ...s.flags));
    const mc = native.monte_carlo;
    const cell = (table, row, column) => s.cells[`${table}/${row}/${column}`];
    // Bit for bit: each cell carries its number in full.
    ['x', 'y', 'theta'].forEach((row, i) => {
      same(cell('covariance-table', row, 1), native.propagation.poses.at(-1)[i], `${what}: ${row}`);
      same(cell('covariance-table', row, 2), mc.sample_mean[i], `${what}: ${row} of the robots`);
    });
    for (const [i, j] of [[0, 0], [0, 1], [1, 1], [0, 2], [1, 2], [2, 2]]) {
      same(cell('covariance-table', `sigma-${i}${j}`, 1), native.propagation.covariances.at(-1)[i][j], `${what}: Σ${i}${j}`);
      same(cell('covariance-table', `sigma-${i}${j}`, 1), mc.covariance[i][j], `${what}: Σ${i}${j}, the Monte Carlo's`);
      same(cell('covariance-table', `sigma-${i}${j}`, 2), mc.sample_covariance[i][j], `${what}: Σ${i}${j} of the robots`);
    }
    same(cell('covariance-table', 'inside', 1), mc.gaussian_inside_3_sigma, `${what}: the Gaussian's share`);
    same(cell('covariance-table', 'inside', 2), mc.inside_3_sigma, `${what}: the robots' share`);
    sameAll(s.systematicError, native.systematic.run.final_error, `${what}: the systematic error`);
    const result = native.umbmark.result;
    for (const [row, direction] of [['clockwise', result.clockwise], ['counter-clockwise', result.counter_clockwise]]) {
      sameAll([1, 2, 3].map((c) => cell('umbmark-table', row, c)), [...direction.centre, direction.r], `${what}: UMBmark ${row}`);
    }
    same(cell('umbmark-table', 'e-max', 1), result.e_max_syst, `${what}: E_max,syst`);
    // And as people read them.
    const shown = await page.locator('#covariance-table tr[data-row="inside"] td').allTextContents();
    assert.equal(shown[1], `${Number((100 * mc.inside_3_sigma).toPrecision(4))} %`, `${what}: the share shown`);
    const sigmaXX = await page.locator('#covariance-table tr[data-row="sigma-00"] td').first().textContent();
    assert.equal(Number(sigmaXX), Number(mc.covariance[0][0].toPrecision(4)), `${what}: Σxx shown`);
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

/**
 * What is shown of the page's controls (outside the plots) and its plots, as boxes in
 * the viewport.
 */
function layout(page) {
  return page.evaluate(() => {
    const visible = (el) => el.getClientRects().length > 0 && getComputedStyle(el).visibility !== 'hidden';
    const rect = (el, what) => {
      const r = el.getBoundingClientRect();
      return { what, left: r.left, right: r.right, top: r.top, bottom: r.bottom };
    };
    const controls = [...document.querySelectorAll('main :is(button, input, select, label, summary, textarea)')]
      .filter((el) => !el.closest('figure.plot') && visible(el))
      .map((el) => rect(el, `${el.tagName.toLowerCase()}${el.id ? `#${el.id}` : ''}`))
      .filter((r) => r.right > r.left && r.bottom > r.top);
    const plots = [...document.querySelectorAll('figure.plot, table.numbers')].filter(visible)
      .map((el) => rect(el, el.dataset.name ?? el.id));
    return { controls, plots, width: document.documentElement.scrollWidth };
  });
}

test('at 390 x 844 and 1400 x 1000 nothing is wider than the screen and no control lies over a plot', bounded, async () => {
  for (const viewport of [phone, laptop]) {
    const page = await open(viewport);
    const what = `/odometry at ${viewport.width} x ${viewport.height}`;
    // With the drawing tools shown and the robots drawn along the way: every control out.
    await page.locator('#shape').selectOption('polyline');
    await page.locator('#points').fill('0,0; 4,0; 4,3');
    await page.locator('#clouds').check();
    const tops = await page.evaluate(() => [0, ...[...document.querySelectorAll('figure.plot, table.numbers')]
      .map((el) => el.getBoundingClientRect().top + scrollY - 20)]);
    let compared = 0;
    for (const top of tops) {
      await page.evaluate((y) => window.scrollTo(0, y), top);
      const { controls, plots, width } = await layout(page);
      assert.ok(width <= viewport.width, `${what}: no sideways scrolling (${width} px)`);
      assert.ok(controls.length > 10, `${what}: the controls are found`);
      for (const plot of plots) {
        assert.ok(plot.left >= -0.5 && plot.right <= viewport.width + 0.5, `${what}: ${plot.what} fits the width`);
        for (const control of controls) {
          const overlaps = Math.min(plot.right, control.right) - Math.max(plot.left, control.left) > 0.5
            && Math.min(plot.bottom, control.bottom) - Math.max(plot.top, control.top) > 0.5;
          assert.ok(!overlaps, `${what}, scrolled to ${Math.round(top)}: ${control.what} lies over ${plot.what}`);
          compared++;
        }
      }
    }
    assert.ok(compared > 0, `${what}: controls and plots compared`);
    if (viewport === phone) {
      // Above the plots, not over them, and folding away; equations scroll in their own box.
      const settings = page.locator('details.controls');
      assert.equal(await settings.evaluate((el) => getComputedStyle(el).position), 'static');
      await settings.locator('summary').click();
      assert.equal(await settings.getAttribute('open'), null);
      assert.equal(await page.locator('.katex-display').first().evaluate((el) => getComputedStyle(el).overflowX), 'auto');
    }
    assert.deepEqual(page.problems, [], what);
    await page.close();
  }
});
