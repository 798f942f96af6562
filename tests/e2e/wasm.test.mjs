// The wasm build gives the native build's numbers: the car, the simulated data sets
// (byte for byte), whole EKF runs and the generated test cases, run in headless
// Chromium and compared with the estlab command line.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { estlab, launchBrowser, root, tempDir } from './harness.mjs';

const pkg = join(root, 'target', 'web', 'pkg');
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
});
after(async () => { await browser.close(); });

/** Asserts |got - expected| <= 1e-12 max(1, |expected|) elementwise. */
function assertClose(got, expected, what) {
  assert.equal(got.length, expected.length, `${what}: length`);
  for (let i = 0; i < expected.length; i++) {
    const tolerance = 1e-12 * Math.max(1, Math.abs(expected[i]));
    assert.ok(Math.abs(got[i] - expected[i]) <= tolerance, `${what}[${i}]: wasm ${got[i]}, native ${expected[i]}`);
  }
}

test('the car', async () => {
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

test('simulated data sets and whole EKF runs', async () => {
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
        assert.ok(estlab('run', sensor, map, ...flags).includes(wasm.report), `${what}: the report`);
      }
    }
  }
});

test('generated test cases', async () => {
  for (const seed of [3, 99]) {
    const wasm = JSON.parse(await page.evaluate((seed) => window.estlab.generateCases(seed, 12), seed));
    const native = JSON.parse(estlab('cases', '--seed', String(seed), '--per-function', '12'));
    assert.deepEqual(wasm, native, `seed ${seed}`);
    const verdict = await page.evaluate(([c]) => window.estlab.checkCase(JSON.stringify(c), JSON.stringify(c.expected)), [wasm[5]]);
    assert.equal(verdict, '[]', 'a case passes its own expected output');
  }
});
