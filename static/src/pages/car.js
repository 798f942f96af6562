// The warm-up: a car on a line and its Kalman filter, computed in the browser by the
// wasm build of the reference filters. What the filter assumes (R, Q, the initial
// belief) is the reader's; what the simulation draws stays the lab's.
import { LogSlider, byId, showError } from '../controls.js';
import { fmt } from '../format.js';
import { renderMath } from '../math.js';
import { band, colours, dashes, overTime, pairs, plotsIn, stats, styled, timeLine } from '../plots.js';
import { loadEstlab } from '../wasm.js';

renderMath();
const estlab = await loadEstlab();
const lab = JSON.parse(estlab.carDefaults());
const plots = plotsIn(byId('car-plots'), 'car');

const scale = (matrix, factor) => matrix.map((row) => row.map((v) => v * factor));
const controls = {
  r: new LogSlider(byId('r-scale'), byId('r-value'), (s) => `×${fmt(s, 2)}: R = diag(${scale(lab.r, s).map((row, i) => fmt(row[i], 3)).join(', ')})`),
  q: new LogSlider(byId('q-scale'), byId('q-value'), (s) => `×${fmt(s, 2)}: Q = ${fmt(lab.q * s, 3)}`),
  sigma0: new LogSlider(byId('sigma0-scale'), byId('sigma0-value'), (s) => `×${fmt(s, 2)}: Σ₀ = diag(${fmt(lab.sigma0[0][0] * s, 3)}, ${fmt(lab.sigma0[1][1] * s, 3)})`),
  mu0Position: byId('mu0-position', HTMLInputElement),
  mu0Velocity: byId('mu0-velocity', HTMLInputElement),
  seed: byId('seed', HTMLInputElement),
  steps: byId('steps', HTMLInputElement),
  monteCarlo: byId('monte-carlo', HTMLInputElement),
  runs: byId('runs', HTMLInputElement),
};

/** The parameters of a run: the lab's, with what the controls change. */
function params() {
  return {
    ...lab,
    r: scale(lab.r, controls.r.value),
    q: lab.q * controls.q.value,
    sigma0: scale(lab.sigma0, controls.sigma0.value),
    mu0: [Number(controls.mu0Position.value), Number(controls.mu0Velocity.value)],
    seed: Number(controls.seed.value),
    steps: Number(controls.steps.value),
  };
}

const presets = {
  lab: { r: 1, q: 1, sigma0: 1 },
  'r-up': { r: 100 },
  'r-down': { r: 0.01 },
  'q-up': { q: 100 },
  'q-down': { q: 0.01 },
  'both-up': { r: 100, q: 100 },
  'both-down': { r: 0.01, q: 0.01 },
  'sigma0-up': { sigma0: 100 },
  'sigma0-down': { sigma0: 0.01 },
};
for (const button of /** @type {NodeListOf<HTMLButtonElement>} */ (document.querySelectorAll('button[data-preset]'))) {
  button.addEventListener('click', () => {
    const preset = presets[button.dataset.preset];
    for (const [name, value] of Object.entries(preset)) controls[name].value = value;
    if (button.dataset.preset === 'lab') {
      controls.mu0Position.value = lab.mu0[0];
      controls.mu0Velocity.value = lab.mu0[1];
    }
    update();
  });
}

/** The prior at t = 0, then one value per update: what the filter believed over time. */
const fromPrior = (prior, series) => [prior, ...series];

/** A series for the prior's point at t = 0: a hollow circle on the estimate's line. */
function priorPoint(value) {
  return {
    id: 'prior',
    name: 'prior at t = 0 (μ₀)',
    type: 'scatter',
    data: [[0, value]],
    symbol: 'emptyCircle',
    symbolSize: 9,
    itemStyle: { color: colours.estimate, borderWidth: 2 },
    z: 4,
    silent: true,
  };
}

/** Summary lines: a few significant digits. */
const f = (v) => fmt(v, 3);

function draw(run, p) {
  // The plots over time start at t = 0 with the prior, N(μ₀, Σ₀), before the first
  // update: where a wrong start shows. The gains start at the first update.
  const updates = run.t();
  const t = fromPrior(0, updates);
  const n = updates.length;
  const position = fromPrior(p.mu0[0], run.position());
  const velocity = fromPrior(p.mu0[1], run.velocity());
  const positionStd = fromPrior(Math.sqrt(p.sigma0[0][0]), run.positionStd());
  const velocityStd = fromPrior(Math.sqrt(p.sigma0[1][1]), run.velocityStd());
  const truePosition = fromPrior(p.x0[0], run.truePosition());
  const trueVelocity = fromPrior(p.x0[1], run.trueVelocity());
  const positionError = fromPrior(p.mu0[0] - p.x0[0], run.positionError());
  const velocityError = fromPrior(p.mu0[1] - p.x0[1], run.velocityError());
  const twoSigma = (mu, std, sign) => mu.map((m, i) => m + sign * 2 * std[i]);
  const estimate = (name, ys) => styled(timeLine(name, t, ys, colours.estimate, { name: `${name} (dashed)` }), dashes.estimate);
  const truth = (ys) => timeLine('true', t, ys, colours.truth, { name: 'true (solid)' });
  const end = t[n];

  plots.position.set(overTime('position (m)', [
    ...band('±2σ', t, twoSigma(position, positionStd, -1), twoSigma(position, positionStd, 1), colours.band),
    { name: 'measurement', type: 'scatter', data: pairs(updates, run.measurement()), symbolSize: 4, itemStyle: { color: colours.measurement } },
    truth(truePosition),
    estimate('estimate', position),
    priorPoint(p.mu0[0]),
  ]));
  plots.position.describe(
    `Position from t = 0 to ${f(end)} s. The prior at t = 0: ${f(position[0])} m ± ${f(2 * positionStd[0])} m (2σ), ` +
    `the car at ${f(truePosition[0])} m. After the last of ${n} updates: the estimate ${f(position[n])} m ± ${f(2 * positionStd[n])} m, ` +
    `the car at ${f(truePosition[n])} m. ${n} measurements, one per update.`);
  plots.velocity.set(overTime('velocity (m/s)', [
    ...band('±2σ', t, twoSigma(velocity, velocityStd, -1), twoSigma(velocity, velocityStd, 1), colours.band),
    truth(trueVelocity),
    estimate('estimate', velocity),
    priorPoint(p.mu0[1]),
  ]));
  plots.velocity.describe(
    `Velocity from t = 0 to ${f(end)} s. The prior at t = 0: ${f(velocity[0])} m/s ± ${f(2 * velocityStd[0])} m/s (2σ), ` +
    `the car's ${f(trueVelocity[0])} m/s. At the end: the estimate ${f(velocity[n])} m/s ± ${f(2 * velocityStd[n])} m/s, ` +
    `the car's ${f(trueVelocity[n])} m/s.`);
  plots.errors.set(overTime('estimate − truth', [
    timeLine('position error (m)', t, positionError, colours.estimate),
    styled(timeLine('velocity error (m/s)', t, velocityError, colours.second, { name: 'velocity error (m/s), dashed' }), dashes.estimate),
  ]));
  const errorWords = (name, unit, ys) => {
    const s = stats(ys, t);
    return `${name} ${f(s.first)} ${unit} at t = 0, ${f(s.last)} ${unit} at the end, largest ${f(s.maxAbs)} ${unit} in size at t = ${f(s.maxAbsAt)} s`;
  };
  plots.errors.describe(`Errors from t = 0 to ${f(end)} s: ${errorWords('position', 'm', positionError)}; ${errorWords('velocity', 'm/s', velocityError)}.`);
  plots.sigmas.set(overTime('standard deviation', [
    timeLine('√P₁₁, position (m)', t, positionStd, colours.estimate),
    styled(timeLine('√P₂₂, velocity (m/s)', t, velocityStd, colours.second, { name: '√P₂₂, velocity (m/s), dashed' }), dashes.estimate),
  ], { type: 'log', scale: false }));
  plots.sigmas.describe(
    `The filter's standard deviations on a log scale: position ${f(positionStd[0])} m at t = 0, ${f(positionStd[n])} m at the end; ` +
    `velocity ${f(velocityStd[0])} m/s at t = 0, ${f(velocityStd[n])} m/s at the end.`);
  const gainPosition = run.gainPosition();
  const gainVelocity = run.gainVelocity();
  plots.gains.set(overTime('Kalman gain', [
    timeLine('K₁, position', updates, gainPosition, colours.estimate),
    styled(timeLine('K₂, velocity', updates, gainVelocity, colours.second, { name: 'K₂, velocity (dashed)' }), dashes.estimate),
  ], {}, { min: 0 }));
  plots.gains.describe(
    `The Kalman gains from the first update (t = ${f(updates[0])} s) to the last: K₁ (position) from ${f(gainPosition[0])} to ${f(gainPosition[n - 1])}, ` +
    `K₂ (velocity) from ${f(gainVelocity[0])} to ${f(gainVelocity[n - 1])}.`);
  const [positionSpread, velocitySpread] = run.errorStd();
  byId('summary').textContent =
    `error std over the second half: position ${fmt(positionSpread)} m, velocity ${fmt(velocitySpread)} m/s`;
}

function drawMonteCarlo(mc, runs, p) {
  const updates = mc.t();
  const n = updates.length;
  // The filter's σ and the mean error start with the prior at t = 0; the actual spread
  // there is 0 (every seed starts from the same μ₀ and the same true state), which a log
  // axis cannot show, so it starts at the first update.
  const t = fromPrior(0, updates);
  const filterStd = (i) => fromPrior(Math.sqrt(p.sigma0[i][i]), mc.filterStd(i));
  const errorMean = (i) => fromPrior(p.mu0[i] - p.x0[i], mc.errorMean(i));
  const [spread0, spread1, sigma0, sigma1] = [mc.errorStd(0), mc.errorStd(1), filterStd(0), filterStd(1)];
  const sigma = (name, ys, colour) => styled(timeLine(name, t, ys, colour, { name: `${name}, dashed` }), dashes.estimate);
  plots.spread.set(overTime(`over ${runs} seeds`, [
    timeLine('actual spread of the position error (m)', updates, spread0, colours.estimate),
    sigma('filter σ, position (m)', sigma0, colours.estimate),
    timeLine('actual spread of the velocity error (m/s)', updates, spread1, colours.second),
    sigma('filter σ, velocity (m/s)', sigma1, colours.second),
  ], { type: 'log', scale: false }));
  plots.spread.describe(
    `Over ${runs} seeds, at the end (t = ${f(updates[n - 1])} s): the position error spreads ${f(spread0[n - 1])} m where the filter's σ says ${f(sigma0[n])} m; ` +
    `the velocity error ${f(spread1[n - 1])} m/s where its σ says ${f(sigma1[n])} m/s.`);
  const [mean0, mean1] = [errorMean(0), errorMean(1)];
  plots.bias.set(overTime(`mean error over ${runs} seeds`, [
    timeLine('position (m)', t, mean0, colours.estimate),
    styled(timeLine('velocity (m/s)', t, mean1, colours.second, { name: 'velocity (m/s), dashed' }), dashes.estimate),
  ]));
  plots.bias.describe(
    `The mean error over ${runs} seeds: position ${f(mean0[0])} m at t = 0 and ${f(mean0[n])} m at the end; ` +
    `velocity ${f(mean1[0])} m/s at t = 0 and ${f(mean1[n])} m/s at the end.`);
}

function update() {
  const start = performance.now();
  try {
    const p = params();
    const json = JSON.stringify(p);
    const run = estlab.runCar(json);
    draw(run, p);
    run.free();
    const monteCarlo = controls.monteCarlo.checked;
    byId('monte-carlo-plots').hidden = !monteCarlo;
    if (monteCarlo) {
      const runs = Number(controls.runs.value);
      const mc = estlab.carMonteCarlo(json, runs);
      drawMonteCarlo(mc, runs, p);
      mc.free();
    }
    showError(byId('error'), null);
  } catch (error) {
    showError(byId('error'), error.message);
  }
  byId('timing').textContent = `re-run and redraw: ${fmt(performance.now() - start, 2)} ms`;
}

for (const input of document.querySelectorAll('#car-controls input')) input.addEventListener('input', update);
update();
document.body.dataset.ready = 'true';
