// The warm-up: a car on a line and its Kalman filter, computed in the browser by the
// wasm build of the reference filters. What the filter assumes (R, Q, the initial
// belief) is the reader's; what the simulation draws stays the lab's.
import { LogSlider, byId, showError } from '../controls.js';
import { fmt } from '../format.js';
import { renderMath } from '../math.js';
import { band, colours, line, overTime, pairs, plotsIn, timeLine } from '../plots.js';
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
  mu0Position: byId('mu0-position'),
  mu0Velocity: byId('mu0-velocity'),
  seed: byId('seed'),
  steps: byId('steps'),
  monteCarlo: byId('monte-carlo'),
  runs: byId('runs'),
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
for (const button of document.querySelectorAll('[data-preset]')) {
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

function draw(run) {
  const t = run.t();
  const position = run.position();
  const velocity = run.velocity();
  const positionStd = run.positionStd();
  const velocityStd = run.velocityStd();
  const twoSigma = (mu, std, sign) => mu.map((m, i) => m + sign * 2 * std[i]);

  plots.position.set(overTime('position (m)', [
    ...band('±2σ', t, twoSigma(position, positionStd, -1), twoSigma(position, positionStd, 1), colours.band),
    { name: 'measurement', type: 'scatter', data: pairs(t, run.measurement()), symbolSize: 4, itemStyle: { color: colours.measurement } },
    timeLine('true', t, run.truePosition(), colours.truth),
    timeLine('estimate', t, position, colours.estimate),
  ]));
  plots.velocity.set(overTime('velocity (m/s)', [
    ...band('±2σ', t, twoSigma(velocity, velocityStd, -1), twoSigma(velocity, velocityStd, 1), colours.band),
    timeLine('true', t, run.trueVelocity(), colours.truth),
    timeLine('estimate', t, velocity, colours.estimate),
  ]));
  plots.errors.set(overTime('estimate − truth', [
    timeLine('position error (m)', t, run.positionError(), colours.estimate),
    timeLine('velocity error (m/s)', t, run.velocityError(), colours.second),
  ]));
  plots.sigmas.set(overTime('standard deviation', [
    timeLine('√P₁₁, position (m)', t, positionStd, colours.estimate),
    timeLine('√P₂₂, velocity (m/s)', t, velocityStd, colours.second),
  ], { type: 'log', scale: false }));
  plots.gains.set(overTime('Kalman gain', [
    timeLine('K₁, position', t, run.gainPosition(), colours.estimate),
    timeLine('K₂, velocity', t, run.gainVelocity(), colours.second),
  ]));
  const [positionSpread, velocitySpread] = run.errorStd();
  byId('summary').textContent =
    `error std over the second half: position ${fmt(positionSpread)} m, velocity ${fmt(velocitySpread)} m/s`;
}

function drawMonteCarlo(mc, runs) {
  const t = mc.t();
  plots.spread.set(overTime(`over ${runs} seeds`, [
    timeLine('actual spread of the position error (m)', t, mc.errorStd(0), colours.estimate),
    timeLine('filter σ, position (m)', t, mc.filterStd(0), colours.estimate, { lineStyle: { type: 'dashed', color: colours.estimate } }),
    timeLine('actual spread of the velocity error (m/s)', t, mc.errorStd(1), colours.second),
    timeLine('filter σ, velocity (m/s)', t, mc.filterStd(1), colours.second, { lineStyle: { type: 'dashed', color: colours.second } }),
  ], { type: 'log', scale: false }));
  plots.bias.set(overTime(`mean error over ${runs} seeds`, [
    timeLine('position (m)', t, mc.errorMean(0), colours.estimate),
    timeLine('velocity (m/s)', t, mc.errorMean(1), colours.second),
  ]));
}

function update() {
  const start = performance.now();
  try {
    const json = JSON.stringify(params());
    const run = estlab.runCar(json);
    draw(run);
    run.free();
    const monteCarlo = controls.monteCarlo.checked;
    byId('monte-carlo-plots').hidden = !monteCarlo;
    if (monteCarlo) {
      const runs = Number(controls.runs.value);
      const mc = estlab.carMonteCarlo(json, runs);
      drawMonteCarlo(mc, runs);
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
