// The sensor-fusion experiment (/fusion) in headless Chromium against the real server: it
// loads cleanly with and without the Northstar report's trials, every control changes
// what is drawn and said, the reader's own CSV file runs and a broken one shows the
// parser's message naming its line, the generated trial downloads as the command line
// writes it, its numbers are those `estlab fusion --json` prints for the same trial and
// settings, the report's trials show beside the report's published figures, tuning on one
// trial and testing on another applies what `estlab fusion --tune` finds, and nothing
// spills over or lies over a plot at a phone's size or a laptop's.
import assert from 'node:assert/strict';
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { spawnSync } from 'node:child_process';
import {
  bounded, estlab, estlabBinary, laptop, launchBrowser, phone, requireSharedData, sharedDataDir, startServer, tempDir,
} from './harness.mjs';

/** Whether the report's trials are where `estlab serve --datasets` looks for them. */
const haveReport = ['trial1', 'trial2'].every((trial) =>
  ['odometry_northstar', 'kalman_groundtruth'].every((file) => existsSync(join(sharedDataDir, 'northstar', `${trial}_${file}.csv`))));
/** A test that needs the report's trials: skipped without them, unless they are required (then it fails, naming where it looked). */
const withReport = haveReport || requireSharedData
  ? bounded
  : { ...bounded, skip: `the Northstar report's trials are not in ${join(sharedDataDir, 'northstar')} (ESTLAB_SHARED_DATA)` };

/** A server without data sets, one with the report's trials (when there are any), and a browser. */
let plain;
let withData;
let browser;
before(async () => {
  plain = await startServer();
  if (haveReport) withData = await startServer({ args: ['--datasets', sharedDataDir] });
  browser = await launchBrowser();
}, bounded);
after(async () => {
  await browser?.close();
  await plain?.stop();
  await withData?.stop();
}, bounded);

/** /fusion (with the query `search`) of `server` at `viewport`'s size once its script is ready, console errors in `page.problems`. */
async function open(server, viewport = laptop, search = '') {
  const page = await browser.newPage({ viewport, acceptDownloads: true });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  await page.goto(`${server.url}/fusion${search}`);
  await page.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 60_000 });
  return page;
}

/**
 * What the page shows now, as data: each plot's summary line and series (every series'
 * numbers folded into a count and a weighted sum), every table cell's exact number, the
 * error, whether the run is dimmed, the command's flags and the values beside the controls.
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
      plots[figure.dataset.name] = {
        summary: figure.querySelector('.plot-summary').textContent,
        series: Object.fromEntries(plot.series().map((s) => [s.id, { name: s.name, data: digest(s.data) }])),
      };
    }
    const cells = {};
    for (const cell of document.querySelectorAll('table [data-value]')) {
      cells[`${cell.closest('table').id}/${cell.closest('tr').dataset.row}/${cell.cellIndex}`] = Number(cell.dataset.value);
    }
    const error = document.getElementById('error');
    const command = document.getElementById('command');
    const values = Object.fromEntries([...document.querySelectorAll('#fusion-controls .value[id]')].map((v) => [v.id, v.textContent]));
    return {
      plots,
      cells,
      error: error.hidden ? null : error.textContent,
      stale: document.getElementById('run-view').classList.contains('stale'),
      staleNote: document.getElementById('run-stale').hidden ? null : document.getElementById('run-stale').textContent,
      flags: command.dataset.flags ? JSON.parse(command.dataset.flags) : null,
      values,
    };
  });
}

/** The value of `flag` in `flags`. */
const flagValue = (flags, flag) => flags[flags.indexOf(flag) + 1];
/** A cell of `state(page)`'s tables. */
const cell = (s, table, row, column) => s.cells[`${table}/${row}/${column}`];
/** The plots' names, in the page's order. */
const plotNames = ['map', 'error-x', 'error-y', 'error-theta'];

/** Asserts that two numbers are the same double. */
function same(got, expected, what) {
  assert.ok(got === expected, `${what}: the page has ${got}, estlab fusion ${expected}`);
}

/**
 * `estlab fusion --json` for the page's `flags` (a report's trial read from the shared
 * data, the reader's file from `files`, by its name); `more` flags after them.
 */
function native(flags, files = {}, ...more) {
  const args = flags.map((flag, i) => (flags[i - 1] === '--trial' ? files[flag] : flag));
  const datasets = flags.includes('--report-trial') ? ['--datasets', sharedDataDir] : [];
  return JSON.parse(estlab('fusion', '--json', ...datasets, ...args, ...more));
}

/** Asserts that the page's tables hold, bit for bit, the summary `estlab fusion --json` prints for its flags. */
function assertNative(s, what, files = {}) {
  assert.equal(s.error, null, `${what}: no error`);
  const { summary } = native(s.flags, files);
  for (const [row, errors] of [['filter', summary.filter], ['odometry', summary.odometry], ['sensor', summary.sensor], ['report', summary.report]]) {
    if (errors === null) {
      assert.equal(cell(s, 'errors-table', row, 1), undefined, `${what}: no ${row} figures`);
      continue;
    }
    ['mean', 'rms', 'max', 'steps'].forEach((field, i) => same(cell(s, 'errors-table', row, i + 1), errors[field], `${what}: ${row} ${field}`));
  }
  same(cell(s, 'readings-table', 'inside', 1), summary.inside_three_sigma, `${what}: inside 3σ`);
  for (const count of ['used', 'outside_view', 'gated']) same(cell(s, 'readings-table', count, 1), summary[count], `${what}: ${count}`);
  return summary;
}

/** The CSV `estlab fusion --write-trial` writes of the generated trial of `seed` and `waypoints`. */
function writtenTrial(seed, waypoints) {
  const file = join(tempDir(), 'trial.csv');
  estlab('fusion', '--seed', String(seed), '--waypoints', String(waypoints), '--write-trial', file);
  return readFileSync(file, 'utf8');
}

/** `csv` without the platforms' columns: the sensor's pose alone, as the report's trials have it. */
function poseOnly(csv) {
  const rows = csv.trim().split('\n').map((line) => line.split(','));
  const keep = rows[0].map((column, i) => (/^p[12]_/.test(column) ? -1 : i)).filter((i) => i >= 0);
  return rows.map((row) => keep.map((i) => row[i]).join(',')).join('\n') + '\n';
}

/** Chooses the reader's own file on the page: `name` holding `text`. */
async function upload(page, name, text) {
  await page.locator('#trial').selectOption('file');
  await page.locator('#trial-file').setInputFiles({ name, mimeType: 'text/csv', buffer: Buffer.from(text) });
  // Loaded: the command names the file, or the error does.
  await page.waitForFunction((file) => {
    const flags = document.getElementById('command').dataset.flags;
    const error = document.getElementById('error');
    return (!error.hidden && error.textContent.startsWith(`${file}:`)) || (flags && JSON.parse(flags).includes(file));
  }, name);
}

test('/fusion loads cleanly without the report\'s trials and says in words and tables what it shows', bounded, async () => {
  const page = await open(plain);
  const s = await state(page);
  assert.deepEqual(Object.keys(s.plots), plotNames);
  assert.match(s.plots.map.summary, /^The room of the generated trial of seed 1 \(12 waypoints\): \d+ steps over [\d.]+ s\. The true path \(green, solid\)/);
  assert.match(s.plots.map.summary, /\d+ readings \(\d+ at intensity 1500 or more, \d+ from 500 to 1500, \d+ below 500\): \d+ used, \d+ outside the field of view \(the grey circle of radius 2 m round the point under the detector\), \d+ rejected by the gate \(orange diamonds\)\.$/);
  for (const name of plotNames.slice(1)) assert.match(s.plots[name].summary, /^The filter's error in (x|y|θ) over \d+ steps: .* within its ±3σ at [\d.]+ % of the steps/, name);
  assert.deepEqual(s.flags, ['--seed', '1', '--waypoints', '12', '--process-xy', '0.05', '--process-theta', '0.05',
    '--c-xy', '90', '--c-theta', '250', '--field-of-view', '2', '--gate', '0.999']);
  assert.equal(await page.locator('#command').textContent(), `estlab fusion ${s.flags.join(' ')}`);
  assert.deepEqual([s.error, s.stale], [null, false]);
  assert.equal(s.values['gate-value'], '0.999: a reading is rejected when its Mahalanobis distance is above χ²₃ = 16.27');
  assert.match(s.values['c-theta-value'], /not used on this trial, whose platforms give the heading's σ/);
  // The table: the filter, odometry and the sensor alone; no report here.
  assert.deepEqual(await page.locator('#errors-table tbody tr').evaluateAll((rows) => rows.map((r) => r.dataset.row)), ['filter', 'odometry', 'sensor']);
  assert.equal(await page.locator('#published-heading').isVisible(), false);
  assert.ok(cell(s, 'errors-table', 'filter', 1) < cell(s, 'errors-table', 'odometry', 1), 'the filter beats odometry');
  assert.match(await page.locator('#readings-table').textContent(), /where a consistent filter has 98\.89 %/);
  // Without the report's trials: generated ones (and the reader's own), and where the real ones come from.
  assert.deepEqual(await page.locator('#trial option').evaluateAll((options) => options.map((o) => o.value)), ['generated', 'file']);
  assert.match(await page.locator('#real-trials').textContent(), /not loaded on this server: the page runs on generated\s+trials\. To see them, start it with estlab serve --datasets DIR/);
  assert.deepEqual(await (await fetch(`${plain.url}/api/datasets/northstar`)).json(), []);
  assert.equal(await page.locator('#tune-next-seed').isVisible(), true);
  assert.equal(await page.locator('#tune-1-2').isVisible(), false);
  // The canvas is hidden from screen readers; the line is read in its place. The map saves as SVG.
  assert.equal(await page.locator('figure[data-name="map"] .chart').getAttribute('aria-hidden'), 'true');
  const svg = await page.evaluate(() => document.querySelector('figure[data-name="map"] .chart').plot.svg());
  assert.ok(svg.startsWith('<svg') && svg.includes('stroke="#2e7d32"') && svg.includes('stroke="#c62828"'), 'the truth (green) and the filter (red) in the SVG');
  assert.equal(await page.locator('header.site nav a[href="/fusion"]').getAttribute('aria-current'), 'page');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('every control changes the plots and their text, and the command says it', bounded, async () => {
  const page = await open(plain);
  const first = await state(page);
  let last = first;
  /**
   * Does `act`, then asserts that the plots `changed` changed their series or summary and
   * the others did not, and that the flags say `flag`.
   */
  const check = async (what, act, { changed = plotNames, flag = null } = {}) => {
    await act();
    const now = await state(page);
    assert.equal(now.error, null, `${what}: no error`);
    for (const name of plotNames) {
      const differs = JSON.stringify(last.plots[name]) !== JSON.stringify(now.plots[name]);
      assert.equal(differs, changed.includes(name), `${what}: ${name} ${changed.includes(name) ? 'changes' : 'stays'}`);
    }
    if (flag) assert.equal(flagValue(now.flags, flag[0]), flag[1], `${what}: ${flag[0]}`);
    last = now;
    return now;
  };
  await check('the seed', () => page.locator('#seed').fill('3'), { flag: ['--seed', '3'] });
  await check('the waypoints', () => page.locator('#waypoints').fill('8'), { flag: ['--waypoints', '8'] });
  assert.match(last.plots.map.summary, /^The room of the generated trial of seed 3 \(8 waypoints\)/);
  await check('k_xy', () => page.locator('#process-xy').fill('-2'), { flag: ['--process-xy', '0.01'] });
  assert.equal(last.values['process-xy-value'], 'k_xy = 0.01: σ grows 1 cm per metre moved');
  await check('k_theta', () => page.locator('#process-theta').fill('-0.7'), { flag: ['--process-theta', '0.2'] });
  await check('c_xy', () => page.locator('#c-xy').fill('200'), { flag: ['--c-xy', '200'] });
  // The platforms give a generated trial's heading σ: c_theta changes nothing drawn here.
  await check('c_theta on a generated trial', () => page.locator('#c-theta').fill('500'), { changed: [], flag: ['--c-theta', '500'] });
  await check('the field of view', () => page.locator('#field-of-view').fill('3.5'), { flag: ['--field-of-view', '3.5'] });
  assert.match(last.plots.map.summary, /the grey circle of radius 3\.5 m/);
  assert.equal(last.plots.map.series['field of view'].name, 'field of view, 3.5 m (grey, dashed)');
  await check('the gate', () => page.locator('#gate').fill('1'), { flag: ['--gate', '0.9'] });
  assert.match(last.values['gate-value'], /^0\.9: a reading is rejected when its Mahalanobis distance is above χ²₃ = 6\.25/);
  await check('the gate off', () => page.locator('#gate').fill('6'), { flag: ['--gate', '1'] });
  assert.equal(last.values['gate-value'], '1: the gate is off, no reading is rejected');
  assert.equal(cell(last, 'readings-table', 'gated', 1), 0);
  await check('the round settings', () => page.locator('#round-settings').click());
  assert.deepEqual(last.flags.slice(4), first.flags.slice(4));
  await check('back to seed 1 with 12 waypoints', async () => {
    await page.locator('#seed').fill('1');
    await page.locator('#waypoints').fill('12');
  });
  assert.deepEqual(last.plots, first.plots, 'the same plots as at first');
  assert.deepEqual(last.cells, first.cells);
  // The reader's own file, with the sensor's pose alone: now c_theta counts.
  await check('a file of poses alone', () => upload(page, 'poses.csv', poseOnly(writtenTrial(1, 12))), { flag: ['--trial', 'poses.csv'] });
  assert.equal(await page.locator('#download-trial').isDisabled(), true, 'only a generated trial downloads');
  assert.match(last.plots.map.summary, /^The room of your file poses\.csv: \d+ steps over [\d.]+ s\. .* \d+ readings: \d+ used/);
  assert.equal(last.plots.map.series.readings.name, 'readings of the sensor (grey dots)');
  assert.doesNotMatch(last.values['c-theta-value'], /not used/);
  await check('c_theta on poses alone', () => page.locator('#c-theta').fill('100'), { flag: ['--c-theta', '100'] });
  // The file choice without a file: nothing runs, and the page says what to do.
  await page.locator('#trial-file').setInputFiles([]);
  const waiting = await state(page);
  assert.equal(waiting.error, null);
  assert.match(waiting.staleNote, /^No run yet: choose a CSV file of your trial above\. The plots and tables below are still those of the last run, on your file poses\.csv, dimmed\.$/);
  assert.equal(waiting.flags, null);
  assert.deepEqual(page.problems, []);
  await page.close();
});

/** The message `estlab fusion` gives for `args`, without its "estlab: ". */
function nativeError(...args) {
  const run = spawnSync(estlabBinary, ['fusion', ...args], { encoding: 'utf8' });
  assert.notEqual(run.status, 0, `estlab fusion ${args.join(' ')} fails`);
  return run.stderr.trim().replace(/^estlab: /, '');
}

test('the address follows the trial and the settings, and a link to it opens the same run', bounded, async () => {
  const page = await open(plain);
  await page.locator('#seed').fill('7');
  await page.locator('#gate').fill('3');
  await page.waitForFunction(() => /[?&]seed=7(&|$)/.test(location.search) && /[?&]gate=0\.99(&|$)/.test(location.search));
  const search = await page.evaluate(() => location.search);
  assert.ok(!search.includes('process-xy'), `the round settings stay out of ${search}`);
  const shown = await state(page);
  const again = await open(plain, laptop, search);
  const reopened = await state(again);
  assert.deepEqual(reopened.flags, shown.flags);
  assert.deepEqual(reopened.cells, shown.cells);
  assert.deepEqual(again.problems, []);
  await page.close();
  await again.close();
});

test('a broken trial file or a bad number of waypoints shows the message naming the line or field, and dims the last run', bounded, async () => {
  const page = await open(plain);
  const good = await state(page);
  const lines = writtenTrial(1, 12).split('\n');
  lines[2] = lines[2].replace(/^([^,]*),[^,]*,/, '$1,abc,');
  const bad = lines.join('\n');
  const file = join(tempDir(), 'broken.csv');
  writeFileSync(file, bad);
  await upload(page, 'broken.csv', bad);
  const broken = await state(page);
  assert.equal(broken.error, "broken.csv:3: odom_x is 'abc', which is not a finite number");
  assert.equal(broken.error, nativeError('--trial', file));
  assert.equal(broken.stale, true);
  assert.match(broken.staleNote, /^No run: the trial did not load\. The plots and tables below are still those of the last run, on the generated trial of seed 1 \(12 waypoints\), dimmed\.$/);
  assert.deepEqual(broken.plots, good.plots, 'the last plots stay');
  assert.deepEqual(broken.cells, good.cells, 'and their numbers');
  assert.equal(broken.flags, null);
  assert.equal(await page.locator('#command').isVisible(), false, 'no command for a trial that does not load');
  const opacity = await page.locator('#run-view figure.plot > :is(.chart, .stack)').first().evaluate((el) => Number(getComputedStyle(el).opacity));
  assert.ok(opacity < 1, `dimmed: opacity ${opacity}`);
  // A file without the columns it needs.
  await upload(page, 'no-truth.csv', 'odom_x,odom_y,odom_theta\n0,0,0\n');
  assert.equal((await state(page)).error, 'no-truth.csv:1: no column gt_x, gt_y, gt_theta');
  // A generated trial out of range: the library's message, beside its field too.
  await page.locator('#trial').selectOption('generated');
  await page.locator('#waypoints').fill('0');
  const none = await state(page);
  assert.equal(none.error, nativeError('--waypoints', '0'));
  assert.equal(none.error, 'waypoints: must be 1 to 200');
  assert.equal(await page.locator('#waypoints-problem').textContent(), none.error);
  assert.equal(await page.locator('#waypoints').getAttribute('aria-invalid'), 'true');
  assert.equal(none.stale, true);
  await page.locator('#seed').fill('');
  await page.locator('#waypoints').fill('12');
  assert.equal((await state(page)).error, 'seed: must be a whole number of 0 or more, got nothing');
  await page.locator('#seed').fill('1');
  const again = await state(page);
  assert.deepEqual([again.error, again.stale, again.staleNote], [null, false, null]);
  assert.deepEqual(again.cells, good.cells);
  assert.equal(await page.locator('#waypoints').getAttribute('aria-invalid'), null);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the generated trial downloads as estlab fusion --write-trial writes it', bounded, async () => {
  const page = await open(plain);
  await page.locator('#seed').fill('4');
  await page.locator('#waypoints').fill('5');
  await page.waitForFunction(() => JSON.parse(document.getElementById('command').dataset.flags).includes('4'));
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#download-trial').click()]);
  assert.equal(download.suggestedFilename(), 'fusion_trial_seed4_5waypoints.csv');
  const saved = readFileSync(await download.path(), 'utf8');
  assert.equal(saved, writtenTrial(4, 5));
  // And the file read back runs.
  await upload(page, 'seed4.csv', saved);
  assert.match((await state(page)).plots.map.summary, /^The room of your file seed4\.csv/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the numbers shown are those estlab fusion --json prints for the same trial and settings', bounded, async () => {
  const page = await open(plain);
  const files = {};
  const settings = [
    ['the defaults', async () => {}],
    ['another trial, loose process noise, a narrow view', async () => {
      await page.locator('#seed').fill('7');
      await page.locator('#waypoints').fill('20');
      await page.locator('#process-xy').fill('-0.45');
      await page.locator('#process-theta').fill('-2.63');
      await page.locator('#field-of-view').fill('1.35');
    }],
    ['a trusted sensor, a tight gate', async () => {
      await page.locator('#c-xy').fill('35');
      await page.locator('#gate').fill('2');
    }],
    ['the reader\'s file of poses alone', async () => {
      files['poses.csv'] = join(tempDir(), 'poses.csv');
      writeFileSync(files['poses.csv'], poseOnly(writtenTrial(2, 9)));
      await upload(page, 'poses.csv', readFileSync(files['poses.csv'], 'utf8'));
      await page.locator('#c-theta').fill('640');
      await page.locator('#gate').fill('6');
    }],
  ];
  for (const [what, act] of settings) {
    await act();
    const s = await state(page);
    const summary = assertNative(s, what, files);
    // And as people read them.
    const shown = await page.locator('#errors-table tr[data-row="filter"] td').allTextContents();
    assert.equal(Number(shown[0]), Number(summary.filter.mean.toPrecision(3)), `${what}: the mean shown`);
  }
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('tune on this seed, test on the next: the settings estlab fusion --tune finds, applied to the next seed', bounded, async () => {
  const page = await open(plain);
  await page.locator('#waypoints').fill('10');
  await page.locator('#tune-next-seed').click();
  await page.waitForFunction(() => !document.getElementById('tuning-table').hidden && document.getElementById('seed').value === '2');
  const s = await state(page);
  const tuned = native(['--seed', '1', '--waypoints', '10'], {}, '--tune').settings;
  assert.deepEqual([flagValue(s.flags, '--process-xy'), flagValue(s.flags, '--process-theta')], [String(tuned.process_xy), String(tuned.process_theta)]);
  assert.deepEqual(s.flags.slice(0, 4), ['--seed', '2', '--waypoints', '10'], 'the next seed is shown');
  same(cell(s, 'tuning-table', 'tuned', 1), tuned.process_xy, 'k_xy tuned');
  same(cell(s, 'tuning-table', 'tuned', 2), tuned.process_theta, 'k_theta tuned');
  const onTrained = native(['--seed', '1', '--waypoints', '10', ...s.flags.slice(4)]).summary.filter.mean;
  same(cell(s, 'tuning-table', 'tuned', 3), onTrained, 'tuned, on seed 1');
  same(cell(s, 'tuning-table', 'tuned', 4), cell(s, 'errors-table', 'filter', 1), 'tuned, on seed 2: the run shown');
  assertNative(s, 'the next seed');
  const round = ['--process-xy', '0.05', '--process-theta', '0.05'];
  same(cell(s, 'tuning-table', 'round', 3), native(['--seed', '1', '--waypoints', '10', ...round]).summary.filter.mean, 'round, on seed 1');
  same(cell(s, 'tuning-table', 'round', 4), native(['--seed', '2', '--waypoints', '10', ...round]).summary.filter.mean, 'round, on seed 2');
  assert.match(await page.locator('#tuning-caption').textContent(), /^Tuned on seed 1, tested on seed 2, with c_xy = 90, c_θ = 250, a field of view of 2 m and the gate at 0\.999/);
  assert.match(await page.locator('#tune-note').textContent(), /^Tuned on seed 1: k_xy = [\d.]+, k_θ = [\d.]+, [\d.]+ m on seed 1 .* On seed 2, which the tuning never saw, [\d.]+ m/);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('with the report\'s trials: its figures beside the page\'s, and tuned on one trial, tested on the other', withReport, async () => {
  assert.ok(haveReport, `the Northstar report's trials are required (ESTLAB_REQUIRE_SHARED_DATA=1) but not in ${join(sharedDataDir, 'northstar')}`);
  const page = await open(withData);
  assert.deepEqual(await page.locator('#trial option').evaluateAll((options) => options.map((o) => [o.value, o.textContent])),
    [['generated', 'generated from a seed'], ['report:trial1', "the report's trial 1"], ['report:trial2', "the report's trial 2"], ['file', 'your own CSV file']]);
  assert.match(await page.locator('#real-trials').textContent(), /The report's 2 real trials are loaded/);
  /** The report's published mean errors, by the table's rows. */
  const published = { trial1: { report: 0.139, odometry: 0.292, sensor: 0.155 }, trial2: { report: 0.057, odometry: 0.082, sensor: 0.123 } };
  for (const [trial, figures] of Object.entries(published)) {
    await page.locator('#trial').selectOption(`report:${trial}`);
    const s = await state(page);
    assertNative(s, trial);
    assert.deepEqual(s.flags.slice(0, 2), ['--report-trial', trial]);
    assert.match(await page.locator('#command').textContent(), new RegExp(`^estlab fusion --datasets DIR --report-trial ${trial} `));
    assert.equal(await page.locator('#published-heading').isVisible(), true);
    for (const [row, figure] of Object.entries(figures)) {
      assert.equal(cell(s, 'errors-table', row, 5), figure, `${trial}: the report's ${row}`);
      assert.equal(await page.locator(`#errors-table tr[data-row="${row}"] td`).nth(4).textContent(), String(figure));
      // The report rounded to millimetres what the page computes from its tables.
      assert.ok(Math.abs(cell(s, 'errors-table', row, 1) - figure) <= 0.0005 + 1e-12, `${trial}: ${row} ${cell(s, 'errors-table', row, 1)} against the report's ${figure}`);
    }
    assert.match(s.plots.map.summary, new RegExp(`^The room of the report's trial ${trial.slice(-1)}: \\d+ steps\\. .*the report's estimate \\(purple\\) [\\d.]+ m from it on average`));
    assert.equal(s.plots.map.series.report.name, "the report's estimate (purple, dash-dotted)");
    assert.match(s.plots['error-x'].summary, /at step \d+;/, 'the report\'s trials have steps, not times');
  }
  // c_theta is the heading's noise of a pose alone.
  const before = await state(page);
  await page.locator('#c-theta').fill('120');
  assert.notDeepEqual((await state(page)).plots, before.plots, 'c_theta changes the run on a report trial');
  await page.locator('#round-settings').click();

  // Tuned on trial 1, tested on trial 2.
  await page.locator('#tune-1-2').click();
  await page.waitForFunction(() => document.getElementById('tuning-caption').textContent.startsWith('Tuned on trial 1'));
  const oneTwo = await state(page);
  const tunedOn1 = native(['--report-trial', 'trial1'], {}, '--tune').settings;
  assert.deepEqual([flagValue(oneTwo.flags, '--process-xy'), flagValue(oneTwo.flags, '--process-theta')], [String(tunedOn1.process_xy), String(tunedOn1.process_theta)]);
  assert.deepEqual(oneTwo.flags.slice(0, 2), ['--report-trial', 'trial2'], 'trial 2 is shown');
  const mean = (trial, flags) => native(['--report-trial', trial, ...flags]).summary.filter.mean;
  const tunedFlags = oneTwo.flags.slice(2);
  const round = ['--process-xy', '0.05', '--process-theta', '0.05'];
  same(cell(oneTwo, 'tuning-table', 'tuned', 3), mean('trial1', tunedFlags), 'tuned on trial 1, on trial 1');
  same(cell(oneTwo, 'tuning-table', 'tuned', 4), mean('trial2', tunedFlags), 'tuned on trial 1, on trial 2');
  same(cell(oneTwo, 'tuning-table', 'tuned', 4), cell(oneTwo, 'errors-table', 'filter', 1), 'the run shown');
  same(cell(oneTwo, 'tuning-table', 'round', 3), mean('trial1', round), 'round, on trial 1');
  same(cell(oneTwo, 'tuning-table', 'round', 4), mean('trial2', round), 'round, on trial 2');
  assert.match(await page.locator('#tune-note').textContent(), /^Tuned on trial 1: .* On trial 2, which the tuning never saw, [\d.]+ m/);
  const headings = await page.locator('#tuning-table thead th').allTextContents();
  assert.deepEqual(headings.slice(2), ['on trial 1, tuned on (m)', 'on trial 2, not seen (m)']);

  // Tuned on trial 2, tested on trial 1: over-fitted, worse there than the round settings.
  await page.locator('#tune-2-1').click();
  await page.waitForFunction(() => document.getElementById('tuning-caption').textContent.startsWith('Tuned on trial 2'));
  const twoOne = await state(page);
  const tunedOn2 = native(['--report-trial', 'trial2'], {}, '--tune').settings;
  assert.deepEqual([flagValue(twoOne.flags, '--process-xy'), flagValue(twoOne.flags, '--process-theta')], [String(tunedOn2.process_xy), String(tunedOn2.process_theta)]);
  assert.deepEqual(twoOne.flags.slice(0, 2), ['--report-trial', 'trial1'], 'trial 1 is shown');
  same(cell(twoOne, 'tuning-table', 'tuned', 4), cell(twoOne, 'errors-table', 'filter', 1), 'the run shown');
  assert.ok(cell(twoOne, 'tuning-table', 'tuned', 3) < cell(twoOne, 'tuning-table', 'round', 3), 'better on the trial it was tuned on');
  assert.ok(cell(twoOne, 'tuning-table', 'tuned', 4) > cell(twoOne, 'tuning-table', 'round', 4), 'worse than the round settings on the trial it never saw');
  assert.match(await page.locator('#tune-note').textContent(), /On trial 1, which the tuning never saw, [\d.]+ m: worse than the round settings' [\d.]+ m: the tuning fitted the chance errors of trial 2 too\./);
  assertNative(twoOne, 'tuned on trial 2, on trial 1');
  assert.deepEqual(page.problems, []);
  await page.close();
});

/** What is shown of the page's controls (outside the plots) and its plots and tables, as boxes in the viewport. */
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
    const page = await open(withData ?? plain, viewport);
    const what = `/fusion at ${viewport.width} x ${viewport.height}`;
    // Every table out: the tuning's too, on the report's trials where there are any.
    await page.locator(withData ? '#tune-2-1' : '#tune-next-seed').click();
    await page.waitForFunction(() => !document.getElementById('tuning-table').hidden);
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
      // Above the plots, not over them, and folding away.
      const settings = page.locator('details.controls');
      assert.equal(await settings.evaluate((el) => getComputedStyle(el).position), 'static');
      await settings.locator('summary').click();
      assert.equal(await settings.getAttribute('open'), null);
    }
    assert.deepEqual(page.problems, [], what);
    await page.close();
  }
});
