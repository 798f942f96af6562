// The wasm build gives the native build's numbers: the car, the simulated data sets
// (byte for byte), whole EKF runs and the generated test cases, run in headless
// Chromium and compared with the estlab command line.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { bounded, estlab, launchBrowser, tempDir, webDir } from './harness.mjs';

const pkg = join(webDir, 'pkg');
let browser;
let page;

before(async () => {
  browser = await launchBrowser();
  page = await browser.newPage();
  // An origin of its own that serves the wasm-bindgen package from disk.
  await page.route('http://wasm.test/**', (route) => {
    const name = new URL(route.request().url()).pathname.slice(1);
    if (name === '') return route.fulfill({ contentType: 'text/html', body: '<!doctype html><title>wasm</title>' });
    const type = name.endsWith('.wasm') ? 'application/wasm' : 'text/javascript';
    return route.fulfill({ contentType: type, body: readFileSync(join(pkg, name)) });
  });
  await page.goto('http://wasm.test/');
  await page.evaluate(async () => {
    window.estlab = await import('/estlab_wasm.js');
    await window.estlab.default({ module_or_path: '/estlab_wasm_bg.wasm' });
  });
}, bounded);
after(async () => { await browser.close(); }, bounded);

/** Asserts |got - expected| <= 1e-12 max(1, |expected|) elementwise. */
function assertClose(got, expected, what) {
  assert.equal(got.length, expected.length, `${what}: length`);
  for (let i = 0; i < expected.length; i++) {
    const tolerance = 1e-12 * Math.max(1, Math.abs(expected[i]));
    assert.ok(Math.abs(got[i] - expected[i]) <= tolerance, `${what}[${i}]: wasm ${got[i]}, native ${expected[i]}`);
  }
}

test('the car', bounded, async () => {
  for (const [seed, extra] of [[1, {}], [7, { q: 1e-6, steps: 300 }]]) {
    const wasm = await page.evaluate(([seed, extra]) => {
      const params = { ...JSON.parse(window.estlab.carDefaults()), seed, ...extra };
      const run = window.estlab.runCar(JSON.stringify(params));
      const out = {
        position: [...run.position()], velocity: [...run.velocity()], truth: [...run.truePosition()],
        z: [...run.measurement()], gain: [...run.gainVelocity()], std: [...run.positionStd()], errorStd: [...run.errorStd()],
      };
      run.free();
      return out;
    }, [seed, extra]);
    const flags = ['car', '--json', '--seed', String(seed)];
    if (extra.q) flags.push('--Q', String(extra.q));
    if (extra.steps) flags.push('--steps', String(extra.steps));
    const native = JSON.parse(estlab(...flags)).run;
    const steps = native.steps;
    assertClose(wasm.position, steps.map((s) => s.mu[0]), 'position');
    assertClose(wasm.velocity, steps.map((s) => s.mu[1]), 'velocity');
    assertClose(wasm.truth, steps.map((s) => s.truth[0]), 'true position');
    assertClose(wasm.z, steps.map((s) => s.z), 'measurement');
    assertClose(wasm.gain, steps.map((s) => s.gain[1]), 'velocity gain');
    assertClose(wasm.std, steps.map((s) => Math.sqrt(s.sigma[0])), 'position std');
    assertClose(wasm.errorStd, native.error_std, 'error std');
  }
});

test('simulated data sets and whole EKF runs', bounded, async () => {
  const dir = tempDir();
  for (const kind of ['o3', 'outliers', 'no-odometry']) {
    for (const seed of [1, 2]) {
      estlab('simulate', '--kind', kind, '--seed', String(seed), '--out', dir);
      const [sensor, map] = [join(dir, `so_${kind}_${seed}.txt`), join(dir, `map_${kind}_${seed}.txt`)];
      const data = await page.evaluate(([kind, seed]) => {
        const data = window.estlab.Dataset.simulate(kind, seed);
        const out = { sensor: data.sensorFile(), map: data.mapFile(), settings: JSON.parse(data.labSettings()) };
        data.free();
        return out;
      }, [kind, seed]);
      assert.equal(data.sensor, readFileSync(sensor, 'utf8'), `${kind} ${seed}: the sensor file is the same, byte for byte`);
      assert.equal(data.map, readFileSync(map, 'utf8'), `${kind} ${seed}: the map file`);

      for (const mode of ['sequential', 'batch']) {
        const settings = { ...data.settings, mode };
        const wasm = await page.evaluate(([kind, seed, settings]) => {
          const data = window.estlab.Dataset.simulate(kind, seed);
          const run = data.run(JSON.stringify(settings));
          const out = {
            estimate: [0, 1, 2].map((i) => [...run.estimate(i)]),
            std: [0, 1, 2].map((i) => [...run.std(i)]),
            association: [...run.readingAssociation()],
            outlier: [...run.readingOutlier()].map(Boolean),
            report: run.report(),
          };
          run.free();
          data.free();
          return out;
        }, [kind, seed, settings]);
        const flags = ['--R', settings.r.join(','), '--Q', settings.q.join(','), '--delta-m', String(settings.delta_m)];
        if (mode === 'batch') flags.push('--batch');
        const native = JSON.parse(estlab('run', sensor, map, '--json', ...flags));
        const what = `${kind} ${seed} ${mode}`;
        for (const i of [0, 1, 2]) {
          assertClose(wasm.estimate[i], native.steps.map((s) => s.mu[i]), `${what} mu[${i}]`);
          assertClose(wasm.std[i], native.steps.map((s) => Math.sqrt(s.sigma[4 * i])), `${what} std[${i}]`);
        }
        assert.deepEqual(wasm.association, native.readings.map((r) => r.c), `${what}: associations`);
        assert.deepEqual(wasm.outlier, native.readings.map((r) => r.outlier), `${what}: rejections`);
        // The report is the summary of estlab run, line for line, with the native numbers.
        const printed = estlab('run', sensor, map, ...flags).split('\n').filter((l) => /^(mean|rejected)/.test(l));
        assert.equal(wasm.report, `${printed.join('\n')}\n`, `${what}: the report is estlab run's`);
        const { summary } = native;
        const triple = (v) => `(${v.map((x) => x.toFixed(6)).join(', ')})`;
        assert.equal(wasm.report, [
          `mean error (x, y, theta):          ${triple(summary.mean_error)}`,
          `mean absolute error (x, y, theta): ${triple(summary.mean_absolute_error)}`,
          `rejected readings: ${summary.rejected} of ${summary.readings}`,
          '',
        ].join('\n'), `${what}: the report's numbers`);
      }
    }
  }
});

/** The name of each function's output where it is an array (the root of a mismatch's path). */
const outputName = { calculate_odometry: 'u', observation_model: 'z_hat', jacobian_observation_model: 'H' };

/**
 * `expected` with its first number that is not a whole number (not an index) moved by a
 * hundredth, towards zero: [the wrong output, the path of the change, the old and the new
 * number]. The path is in the contract's notation: `u[1]`, `mu_bar[0]`, `nu[0][1]`.
 */
function oneNumberWrong(expected, path) {
  if (typeof expected === 'number' && !Number.isInteger(expected)) {
    const wrong = expected - Math.sign(expected) * 0.01 * (1 + Math.abs(expected));
    return [wrong, path, expected, wrong];
  }
  const entries = Array.isArray(expected) ? expected.entries() : Object.entries(expected ?? {});
  for (const [key, value] of entries) {
    if (typeof value !== 'number' && typeof value !== 'object') continue;
    const inner = Array.isArray(expected) ? `${path}[${key}]` : (path ? `${path}.${key}` : key);
    const found = oneNumberWrong(value, inner);
    if (found) {
      const copy = Array.isArray(expected) ? [...expected] : { ...expected };
      copy[key] = found[0];
      return [copy, ...found.slice(1)];
    }
  }
  return null;
}

test('generated test cases', bounded, async () => {
  for (const seed of [3, 99]) {
    const wasm = JSON.parse(await page.evaluate((seed) => window.estlab.generateCases(seed, 12), seed));
    const native = JSON.parse(estlab('cases', '--seed', String(seed), '--per-function', '12'));
    assert.deepEqual(wasm, native, `seed ${seed}`);
    const functions = [...new Set(native.map((c) => c.function))];
    assert.equal(functions.length, 8, 'cases of every student function');

    // Every case passes with its own expected output, and one number wrong is found.
    const check = (pairs) => page.evaluate((pairs) => pairs.map(([c, got]) => JSON.parse(window.estlab.checkCase(JSON.stringify(c), JSON.stringify(got)))), pairs);
    const verdicts = await check(native.map((c) => [c, c.expected]));
    verdicts.forEach((verdict, i) => assert.deepEqual(verdict, [], `${native[i].id} passes with its own expected output`));
    for (const name of functions) {
      const c = native.find((k) => k.function === name);
      const [wrong, path, expected, got] = oneNumberWrong(c.expected, outputName[name] ?? '');
      const [verdict] = await check([[c, wrong]]);
      assert.equal(verdict.length, 1, `${c.id} with ${path} wrong: ${JSON.stringify(verdict)}`);
      const { path: at, expected: was, got: is, problem } = verdict[0];
      assert.deepEqual({ at, was, is, problem }, { at: path, was: expected, is: got, problem: 'differs' }, `${c.id} with ${path} wrong`);
    }
  }
});
