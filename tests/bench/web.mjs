// Measures the browser side in headless Chromium and prints a Markdown report:
// wasm whole runs (median of many) beside native, the wasm module's size, every page's
// first-load transferred bytes, and the time from moving a control to the redrawn plots.
//
//   node tests/bench/web.mjs   (scripts/bench-web builds what it needs first)
import { readFileSync, readdirSync } from 'node:fs';
import { brotliCompressSync, gzipSync } from 'node:zlib';
import { join } from 'node:path';
import { launchBrowser, openPage, root, startServer } from '../e2e/harness.mjs';

const shared = process.env.ESTLAB_SHARED_DATA ?? join(root, '..', 'shared', 'data');
const pkg = join(root, 'target', 'web', 'pkg');
const kb = (bytes) => `${(bytes / 1024).toFixed(1)} KB`;
const lines = [];
const say = (line = '') => { lines.push(line); console.error(line); };

const browser = await launchBrowser();

// --- wasm whole runs ---
const page = await browser.newPage();
await page.route('http://wasm.test/**', (route) => {
  const name = new URL(route.request().url()).pathname.slice(1);
  if (name === '') return route.fulfill({ contentType: 'text/html', body: '<!doctype html><title>bench</title>' });
  return route.fulfill({ contentType: name.endsWith('.wasm') ? 'application/wasm' : 'text/javascript', body: readFileSync(join(pkg, name)) });
});
await page.goto('http://wasm.test/');
await page.evaluate(async () => {
  window.estlab = await import('/estlab_wasm.js');
  await window.estlab.default({ module_or_path: '/estlab_wasm_bg.wasm' });
});

const originals = [
  ['so_o3_ie', 'so_o3_ie.txt', 'map_o3.txt', 'o3'],
  ['so_pb_10_outlier', 'so_pb_10_outlier.txt', 'map_pent_big_10.txt', 'outliers'],
  ['so_pb_40_no', 'so_pb_40_no.txt', 'map_pent_big_40.txt', 'no-odometry'],
];
say('| data set | sequential (wasm) | batch (wasm) |');
say('| --- | ---: | ---: |');
for (const [name, sensor, map, kind] of originals) {
  const dir = join(shared, 'el2320', 'datasets');
  let files = null;
  try {
    files = [readFileSync(join(dir, map), 'utf8'), readFileSync(join(dir, sensor), 'utf8')];
  } catch {
    console.error(`(no ${name}: the shared data is not at ${dir})`);
  }
  for (const [label, source] of [[name, files], [`generated ${kind}, seed 1`, null]]) {
    if (label === name && !files) continue;
    const times = await page.evaluate(([kind, source, mapName, sensorName]) => {
      const e = window.estlab;
      const data = source ? e.Dataset.parse(source[0], mapName, source[1], sensorName) : e.Dataset.simulate(kind, 1);
      // The lab's settings for the kind, from a simulated data set of that kind.
      const lab = e.Dataset.simulate(kind, 1);
      const settings = JSON.parse(lab.labSettings());
      lab.free();
      const median = (mode) => {
        const json = JSON.stringify({ ...settings, mode });
        for (let i = 0; i < 20; i++) data.run(json).free();
        const samples = [];
        for (let i = 0; i < 200; i++) {
          const start = performance.now();
          data.run(json).free();
          samples.push(performance.now() - start);
        }
        samples.sort((a, b) => a - b);
        return samples[100];
      };
      const out = [median('sequential'), median('batch')];
      data.free();
      return out;
    }, [kind, files, map, sensor]);
    say(`| ${label} | ${times[0].toFixed(2)} ms | ${times[1].toFixed(2)} ms |`);
  }
}
await page.close();

// --- the wasm module ---
const wasm = readFileSync(join(pkg, 'estlab_wasm_bg.wasm'));
say();
say(`wasm module: ${kb(wasm.length)}, ${kb(brotliCompressSync(wasm).length)} with brotli, ${kb(gzipSync(wasm, { level: 9 }).length)} with gzip`);

// --- first loads and redraws, through the real server ---
const server = await startServer();
say();
say('| page | requests | transferred on first load |');
say('| --- | ---: | ---: |');
for (const path of ['/', '/car', '/ekf', '/ekf/code']) {
  const context = await browser.newContext();
  const fresh = await context.newPage();
  const cdp = await context.newCDPSession(fresh);
  await cdp.send('Network.enable');
  let bytes = 0;
  let requests = 0;
  cdp.on('Network.loadingFinished', (event) => { bytes += event.encodedDataLength; requests += 1; });
  await fresh.goto(server.url + path);
  await fresh.waitForSelector('body[data-ready=true]');
  await fresh.evaluate(() => document.fonts.ready);
  await fresh.waitForTimeout(500);
  say(`| ${path} | ${requests} | ${kb(bytes)} |`);
  await context.close();
}

say();
say('The experiment scrolled into view (1400 x 1000 viewport): the plots on screen redraw at');
say('once, the others when they come into view.');
say();
say('| control moved | re-run and redraw (script), median of 60 | until the next frame is painted, median (max) |');
say('| --- | ---: | ---: |');
const redraw = async (path, setup, selector, values) => {
  const p = await openPage(browser, server.url + path);
  if (setup) await setup(p);
  // Look at the experiment, as a reader moving its controls does.
  await p.evaluate(() => document.querySelector('.experiment').scrollIntoView());
  await p.waitForTimeout(300);
  const work = [];
  const painted = [];
  for (let i = 0; i < 60; i++) {
    const [sync, frame] = await p.evaluate(([selector, value]) => new Promise((resolve, reject) => {
      setTimeout(() => reject(new Error(`no frame within 5 s after moving ${selector}`)), 5000);
      const input = document.querySelector(selector);
      const start = performance.now();
      input.value = value;
      input.dispatchEvent(new Event('input', { bubbles: true }));
      const sync = performance.now() - start;
      requestAnimationFrame(() => setTimeout(() => resolve([sync, performance.now() - start])));
    }), [selector, values[i % values.length]]);
    work.push(sync);
    painted.push(frame);
  }
  const median = (xs) => xs.sort((a, b) => a - b)[30].toFixed(1);
  await p.close();
  return `${median(work)} ms | ${median(painted)} ms (max ${painted.at(-1).toFixed(1)})`;
};
say(`| car: R slider | ${await redraw('/car', null, '#r-scale', ['-1', '1', '0.5', '-0.5'])} |`);
say(`| car: R slider, Monte Carlo over 200 seeds | ${await redraw('/car', (p) => p.locator('#monte-carlo').check(), '#r-scale', ['-1', '1', '0.5', '-0.5'])} |`);
for (const kind of ['o3', 'outliers', 'no-odometry']) {
  say(`| EKF ${kind}: Q range | ${await redraw('/ekf', (p) => p.locator('#dataset-kind').selectOption(kind), '#q-range', ['0.02', '0.05', '0.3', '0.1'])} |`);
}
say(`| EKF o3: time slider | ${await redraw('/ekf', null, '#time', ['10', '200', '400', '50'])} |`);

// --- grading in the browser: the correct student file, every test and every run ---
say();
say('Grading the correct student file in the browser (Web Worker and wasm), median of 5:');
say();
say('| what | time |');
say('| --- | ---: |');
{
  const p = await openPage(browser, `${server.url}/ekf/code`);
  await p.locator('.cm-content').click();
  await p.keyboard.press('Control+A');
  await p.keyboard.insertText(readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8'));
  const timed = async (button) => {
    const samples = [];
    for (let i = 0; i < 5; i++) {
      const start = Date.now();
      await p.locator(button).click();
      await p.waitForFunction(() => document.getElementById('stop').disabled);
      samples.push(Date.now() - start);
    }
    return `${samples.sort((a, b) => a - b)[2]} ms`;
  };
  say(`| Run tests: 8 functions, 96 cases, judged after each function | ${await timed('#run-tests')} |`);
  say(`| Run data sets: 4 runs, plotted | ${await timed('#run-datasets')} |`);
  await p.close();
}
await server.stop();
await browser.close();
console.log(lines.join('\n'));
