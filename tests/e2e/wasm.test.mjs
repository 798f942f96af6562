// The wasm build gives the native build's numbers: the car, the simulated data sets
// (byte for byte), whole EKF runs, the generated test cases, the odometry model and the
// fusion filter (bit for bit), run in headless Chromium and compared with the estlab
// command line.
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
/** The name of each output in its exercise's contract, where it has one (the root of paths). */
const outputName = {
  calculate_odometry: 'u', observation_model: 'z_hat', jacobian_observation_model: 'H',
  odometry_step: 'p_next', pose_jacobian: 'F_p', increment_jacobian: 'F_delta',
  wheel_noise: 'Sigma_delta', propagate: 'Sigma_p_next',
  combine_platforms: 'z', heading_sigma: 'sigma_theta', measurement_noise: 'Q', in_field_of_view: 'in_view',
  mahalanobis: 'd2',
  motion: 'pose', process_noise: 'R', sample_motion: 'particles', particle_weights: 'weights', needs_resampling: 'resample',
  low_variance_resample: 'indices', learn_alphas: 'alphas',
};

/**
 * `expected` with its first number that is not a whole number (not an index) moved by a
 * hundredth, towards zero, or a flag the other way: [the wrong output, the path of the
 * change, the old and the new value]. The path is in the contract's notation: `u[1]`,
 * `mu_bar[0]`, `nu[0][1]`.
 */
function oneNumberWrong(expected, path) {
  if (typeof expected === 'boolean') return [!expected, path, expected, !expected];
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

test('generated test cases of every exercise', bounded, async () => {
  for (const [lab, count, seed] of [['ekf-localization', 8, 3], ['ekf-localization', 8, 99], ['odometry', 5, 3], ['odometry', 5, 99],
    ['sensor-fusion', 7, 3], ['sensor-fusion', 7, 99], ['ukf-particle', 12, 3], ['ukf-particle', 12, 99]]) {
    const wasm = JSON.parse(await page.evaluate(([lab, seed]) => window.estlab.generateCases(lab, seed, 12), [lab, seed]));
    const native = JSON.parse(estlab('cases', '--lab', lab, '--seed', String(seed), '--per-function', '12'));
    assert.deepEqual(wasm, native, `${lab}, seed ${seed}`);
    const functions = [...new Set(native.map((c) => c.function))];
    assert.equal(functions.length, count, `${lab}: cases of every student function`);

    // Every case passes with its own expected output, and one number wrong is found.
    const check = (pairs) => page.evaluate(([lab, pairs]) => pairs.map(([c, got]) => JSON.parse(window.estlab.checkCase(lab, JSON.stringify(c), JSON.stringify(got)))), [lab, pairs]);
    const verdicts = await check(native.map((c) => [c, c.expected]));
    verdicts.forEach((verdict, i) => assert.deepEqual(verdict, [], `${native[i].id} passes with its own expected output`));
    for (const name of functions) {
      const c = native.find((k) => k.function === name);
      if (name === 'low_variance_resample') {
        // Indices only: one moved to its neighbour.
        const wrong = [...c.expected];
        wrong[0] = wrong[0] === 0 ? 1 : wrong[0] - 1;
        const [verdict] = await check([[c, wrong]]);
        assert.deepEqual(verdict.map((m) => [m.path, m.problem]), [['indices[0]', 'differs']], `${c.id} with indices[0] wrong`);
        continue;
      }
      const [wrong, path, expected, got] = oneNumberWrong(c.expected, outputName[name] ?? '');
      const [verdict] = await check([[c, wrong]]);
      assert.equal(verdict.length, 1, `${c.id} with ${path} wrong: ${JSON.stringify(verdict)}`);
      const { path: at, expected: was, got: is, problem } = verdict[0];
      assert.deepEqual({ at, was, is, problem }, { at: path, was: expected, is: got, problem: 'differs' }, `${c.id} with ${path} wrong`);
    }
  }
});

test('odometry: the propagation, the robots, systematic errors and UMBmark', bounded, async () => {
  const cases = [
    {
      params: { sigma0: [[0.01, 0, 0], [0, 0.02, 0], [0, 0, 0.03]] },
      robots: 200, seed: 9, errors: { e_d: 1.01, e_b: 0.98 }, umbmark: { side: 3, runs: 4 },
      flags: ['--sigma0', '0.01,0.02,0.03', '--monte-carlo', '200', '--seed', '9', '--e-d', '1.01', '--e-b', '0.98', '--umbmark', '3', '--runs', '4'],
    },
    {
      params: { shape: { kind: 'figure-eight', radius: 1.2 }, speed: 0.1, wheel_base: 0.5, k_r: 1e-3, k_l: 2e-5, sigma0: [[0, 0, 0], [0, 0, 0], [0, 0, 0.04]] },
      robots: 150, seed: 3, errors: { e_d: 0.995, e_b: 1.02 }, umbmark: { side: 4, runs: 2 },
      flags: ['--shape', 'figure-eight', '--size', '1.2', '--speed', '0.1', '--wheel-base', '0.5', '--k-r', '0.001', '--k-l', '0.00002',
        '--sigma0', '0,0,0.04', '--monte-carlo', '150', '--seed', '3', '--e-d', '0.995', '--e-b', '1.02', '--umbmark', '4', '--runs', '2'],
    },
    {
      params: { shape: { kind: 'polyline', points: [[0.5, -1], [2.25, -1], [2.25, 1.5], [-0.75, 0.3]] }, speed: 0.02 },
      robots: 64, seed: 1, errors: { e_d: 1, e_b: 1.05 }, umbmark: { side: 1, runs: 1 },
      flags: ['--points', '0.5,-1;2.25,-1;2.25,1.5;-0.75,0.3', '--speed', '0.02', '--monte-carlo', '64', '--e-b', '1.05', '--umbmark', '1', '--runs', '1'],
    },
  ];
  for (const c of cases) {
    const wasm = await page.evaluate((c) => {
      const e = window.estlab;
      const params = JSON.stringify(c.params);
      const errors = JSON.stringify(c.errors);
      const run = e.propagateOdometry(params);
      const steps = run.steps();
      const every = Math.max(1, Math.floor(steps / 3));
      const mc = e.odometryMonteCarlo(params, JSON.stringify({ robots: c.robots, seed: c.seed, cloud_every: every }));
      const sys = e.odometrySystematic(params, errors);
      const umb = e.odometryUmbmark(params, errors, JSON.stringify({ ...c.umbmark, seed: c.seed }));
      const list = (v) => [...v];
      const out = {
        steps,
        pose: [0, 1, 2].map((i) => list(run.pose(i))),
        covariance: [0, 1, 2].map((i) => [0, 1, 2].map((j) => list(run.covariance(i, j)))),
        finalCovariance: list(run.finalCovariance()),
        robots: mc.robots(),
        finalPoses: [0, 1, 2].map((i) => list(mc.finalPoses(i))),
        finalPositions: list(mc.finalPositions()),
        cloudSteps: list(mc.cloudSteps()),
        clouds: list(mc.cloudSteps()).map((_, k) => [0, 1, 2].map((i) => list(mc.cloud(k, i)))),
        cloudPositions: list(mc.cloudSteps()).map((_, k) => list(mc.cloudPositions(k))),
        nominal: list(mc.nominal()),
        mcCovariance: list(mc.covariance()),
        sampleMean: list(mc.sampleMean()),
        sampleCovariance: list(mc.sampleCovariance()),
        inside: mc.insideThreeSigma(),
        gaussian: mc.gaussianInsideThreeSigma(),
        systematic: { odometry: [0, 1, 2].map((i) => list(sys.odometry(i))), truth: [0, 1, 2].map((i) => list(sys.truth(i))), error: list(sys.finalError()) },
        umbmark: {
          runs: umb.runs(),
          directions: [0, 1].map((d) => ({
            odometry: [0, 1, 2].map((i) => list(umb.odometry(d, i))),
            truths: [0, 1, 2].map((i) => list(umb.truths(d, i))),
            errors: [0, 1, 2].map((i) => list(umb.errors(d, i))),
            centre: list(umb.centre(d)),
            r: umb.r(d),
          })),
          eMax: umb.eMaxSyst(),
        },
      };
      for (const object of [run, mc, sys, umb]) object.free();
      return out;
    }, c);
    const native = JSON.parse(estlab('odometry', '--json', ...c.flags));
    const what = c.flags.join(' ');
    /** Bit for bit (0 and -0 alike). */
    const same = (got, expected, name) => {
      assert.equal(got.length, expected.length, `${what}: ${name}: length`);
      expected.forEach((v, i) => assert.ok(got[i] === v, `${what}: ${name}[${i}]: wasm ${got[i]}, native ${v}`));
    };
    const column = (poses, i) => poses.map((p) => p[i]);
    const { propagation, monte_carlo: mc, systematic, umbmark } = native;
    assert.equal(wasm.steps, propagation.path.increments.length, `${what}: steps`);
    for (const i of [0, 1, 2]) {
      same(wasm.pose[i], column(propagation.poses, i), `pose ${i}`);
      for (const j of [0, 1, 2]) same(wasm.covariance[i][j], propagation.covariances.map((s) => s[i][j]), `covariance ${i}${j}`);
      same(wasm.finalPoses[i], column(mc.final_poses, i), `the robots' final poses ${i}`);
      same(wasm.systematic.odometry[i], column(systematic.run.odometry, i), `systematic odometry ${i}`);
      same(wasm.systematic.truth[i], column(systematic.run.truth, i), `systematic truth ${i}`);
    }
    same(wasm.finalPositions, mc.final_poses.flatMap(([x, y]) => [x, y]), "the robots' final positions");
    same(wasm.finalCovariance, propagation.covariances.at(-1).flat(), 'the final covariance');
    same(wasm.mcCovariance, mc.covariance.flat(), "the Monte Carlo's covariance");
    same(wasm.nominal, mc.nominal, 'the nominal pose');
    same(wasm.sampleMean, mc.sample_mean, 'the sample mean');
    same(wasm.sampleCovariance, mc.sample_covariance.flat(), 'the sample covariance');
    same([wasm.robots, wasm.inside, wasm.gaussian], [mc.robots, mc.inside_3_sigma, mc.gaussian_inside_3_sigma], 'the shares inside 3σ');
    same(wasm.systematic.error, systematic.run.final_error, 'the systematic error');
    // The clouds are the robots along the way: the one at the last step holds the final poses.
    assert.ok(wasm.cloudSteps.length >= 3 && wasm.cloudSteps[0] === 0, `${what}: clouds at ${wasm.cloudSteps}`);
    const last = wasm.cloudSteps.indexOf(wasm.steps);
    if (last >= 0) for (const i of [0, 1, 2]) same(wasm.clouds[last][i], column(mc.final_poses, i), `the last cloud ${i}`);
    wasm.clouds.forEach(([x, y], k) => same(wasm.cloudPositions[k], x.flatMap((v, r) => [v, y[r]]), `cloud ${k}'s positions`));
    assert.equal(wasm.umbmark.runs, umbmark.test.runs);
    for (const [d, direction] of [[0, umbmark.result.clockwise], [1, umbmark.result.counter_clockwise]]) {
      const w = wasm.umbmark.directions[d];
      for (const i of [0, 1, 2]) {
        same(w.odometry[i], column(direction.odometry, i), `UMBmark ${d} odometry ${i}`);
        // One run after the other, each ended by a NaN.
        const runs = [[]];
        for (const v of w.truths[i]) {
          if (Number.isNaN(v)) runs.push([]);
          else runs.at(-1).push(v);
        }
        assert.deepEqual(runs.pop(), [], `${what}: UMBmark ${d} truths end with a NaN`);
        assert.equal(runs.length, direction.truths.length, `${what}: UMBmark ${d} runs`);
        runs.forEach((run, k) => same(run, column(direction.truths[k], i), `UMBmark ${d} run ${k} truth ${i}`));
        same(w.errors[i], column(direction.errors, i), `UMBmark ${d} errors ${i}`);
      }
      same([...w.centre, w.r], [...direction.centre, direction.r], `UMBmark ${d} centre and r`);
    }
    same([wasm.umbmark.eMax], [umbmark.result.e_max_syst], 'E_max,syst');
  }
});

test('sensor fusion: generated trials, whole runs and tuning', bounded, async () => {
  const dir = tempDir();
  for (const [seed, flags] of [[1, []], [5, ['--process-xy', '0.2', '--gate', '1', '--field-of-view', '1.5']]]) {
    const file = join(dir, `trial_${seed}.csv`);
    const native = JSON.parse(estlab('fusion', '--json', '--seed', String(seed), '--write-trial', file, ...flags));
    const tuned = JSON.parse(estlab('fusion', '--json', '--seed', String(seed), '--tune', ...flags));
    const wasm = await page.evaluate(([seed, settings]) => {
      const defaults = JSON.parse(window.estlab.fusionDefaults());
      const trial = window.estlab.FusionTrial.generate(JSON.stringify({ ...defaults.trial, seed }));
      const run = trial.run(JSON.stringify(settings));
      const out = { csv: trial.csv(), summary: JSON.parse(run.summary()), tuned: JSON.parse(trial.tune(JSON.stringify(settings))) };
      run.free();
      trial.free();
      return out;
    }, [seed, native.settings]);
    assert.equal(wasm.csv, readFileSync(file, 'utf8'), `seed ${seed}: the trial's file is the same, byte for byte`);
    assert.deepEqual(wasm.summary, native.summary, `seed ${seed}: the run's summary`);
    assert.deepEqual(wasm.tuned.settings, tuned.settings, `seed ${seed}: the tuned settings`);
  }
});

test('MRCLAM: a generated robot, its learned noise and the three filters', bounded, async () => {
  const flags = ['--generate', '2', '--robot', '2', '--particles', '300', '--seed', '5', '--rho', '2'];
  const native = JSON.parse(estlab('mrclam', '--json', ...flags));
  const wasm = await page.evaluate(() => {
    const defaults = JSON.parse(window.estlab.mrclamDefaults());
    const robot = window.estlab.MrclamRobot.generate(JSON.stringify({ ...defaults.dataset, seed: 2 }), 2);
    const settings = JSON.stringify({ rho: 2, particles: 300, seed: 5 });
    const filters = ['ekf', 'ukf', 'particle'].map((kind) => {
      const run = robot.run(kind, settings, 4);
      const out = {
        summary: JSON.parse(run.summary()), snapshots: [...run.snapshotSteps()],
        samples: [0, 1, 2, 3].map((i) => run.samples(i).length), errors: run.positionError().length,
      };
      run.free();
      return out;
    });
    const out = { steps: robot.steps(), noise: JSON.parse(robot.noise()), drift: JSON.parse(robot.drift()), filters };
    robot.free();
    return out;
  });
  assert.equal(wasm.steps, native.steps);
  assert.deepEqual(wasm.noise, native.noise, 'the learned noise, bit for bit');
  assert.deepEqual(wasm.drift, native.dead_reckoning, 'dead reckoning, bit for bit');
  for (const [i, filter] of wasm.filters.entries()) {
    const expected = native.filters[i];
    assert.deepEqual(filter.summary.readings, expected.readings, expected.filter);
    // The EKF and UKF bit for bit; the particle filter's normal draws take a logarithm
    // or an exponential in their rare tails, which may round apart in the last bit.
    const c = filter.summary.consistency;
    const e = expected.consistency;
    for (const [got, want] of [[c.errors.rms, e.errors.rms], [c.nees, e.nees], [c.inside_three_sigma, e.inside_three_sigma]]) {
      assert.ok(Math.abs(got - want) <= 1e-9 * Math.max(1, Math.abs(want)), `${expected.filter}: wasm ${got}, native ${want}`);
    }
    if (i < 2) assert.deepEqual(c, e, `${expected.filter}: bit for bit`);
    assert.deepEqual(filter.snapshots, [0, Math.round((wasm.steps - 1) / 3), Math.round((2 * (wasm.steps - 1)) / 3), wasm.steps - 1]);
    assert.equal(filter.errors, wasm.steps);
  }
  assert.deepEqual(wasm.filters.map((f) => f.samples), [[0, 0, 0, 0], [0, 14, 14, 14], [600, 600, 600, 600]],
    'no samples for the EKF; seven sigma points after a prediction; the particles');
});
