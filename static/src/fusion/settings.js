// What the fusion page's controls say, as the library's types read them, the flags of
// `estlab fusion` that run the same filter (and the page's address, by the same names),
// and the exercise's `tuning()` that does.
import { decimal, fmt } from '../format.js';

/** @typedef {import('../types/FusionSettings').FusionSettings} FusionSettings */

/** The probabilities the gate's slider steps through; at 1 the gate rejects nothing. */
const gateSteps = [0.5, 0.9, 0.95, 0.99, 0.999, 0.9999, 1];

/**
 * A log slider's value to two significant digits (10^-1.3 is 0.05): the numbers the
 * tuning grid and the command line write, so that what the page runs is what they say.
 */
export const twoDigits = (value) => Number(Number(value).toPrecision(2));

/**
 * The controls of the filter's settings.
 *
 * @typedef {object} SettingsControls
 * @property {{ value: number }} processXy k_xy, a log slider
 * @property {{ value: number }} processTheta k_theta, a log slider
 * @property {HTMLInputElement} cXy
 * @property {HTMLInputElement} cTheta
 * @property {HTMLInputElement} fieldOfView
 * @property {HTMLInputElement} gate the index of its probability in `gateSteps`
 */

/**
 * The filter's settings the controls `ui` say; what no control sets (the start's
 * standard deviations) is `defaults`'.
 *
 * @param {SettingsControls} ui
 * @param {FusionSettings} defaults
 * @returns {FusionSettings}
 */
export function filterSettings(ui, defaults) {
  return {
    process_xy: twoDigits(ui.processXy.value),
    process_theta: twoDigits(ui.processTheta.value),
    noise: { c_xy: decimal(Number(ui.cXy.value)), c_theta: decimal(Number(ui.cTheta.value)) },
    field_of_view: decimal(Number(ui.fieldOfView.value)),
    gate: gateSteps[Number(ui.gate.value)],
    start_sigma: defaults.start_sigma,
  };
}

/**
 * Sets the controls `ui` to `settings` (a gate between the slider's steps takes the
 * nearest step).
 *
 * @param {SettingsControls} ui
 * @param {FusionSettings} settings
 */
export function showSettings(ui, settings) {
  ui.processXy.value = settings.process_xy;
  ui.processTheta.value = settings.process_theta;
  ui.cXy.value = String(settings.noise.c_xy);
  ui.cTheta.value = String(settings.noise.c_theta);
  ui.fieldOfView.value = String(settings.field_of_view);
  const nearest = gateSteps.reduce((best, p, i) => (Math.abs(p - settings.gate) < Math.abs(gateSteps[best] - settings.gate) ? i : best), 0);
  ui.gate.value = String(nearest);
}

/**
 * The flags of `estlab fusion` for the filter's `settings` (every number in its
 * shortest form, which reads back as the same double).
 *
 * @param {FusionSettings} settings
 */
export function settingsFlags(settings) {
  return [
    '--process-xy', String(settings.process_xy),
    '--process-theta', String(settings.process_theta),
    '--c-xy', String(settings.noise.c_xy),
    '--c-theta', String(settings.noise.c_theta),
    '--field-of-view', String(settings.field_of_view),
    '--gate', String(settings.gate),
  ];
}

/**
 * The settings a page's address asks for, by the names of `settingsFlags` without their
 * dashes (`?process-xy=0.1&gate=0.99`); what it does not name, or names with no number,
 * is `defaults`'. The controls then keep each within its range.
 *
 * @param {URLSearchParams} address
 * @param {FusionSettings} defaults
 * @returns {FusionSettings}
 */
export function settingsFromAddress(address, defaults) {
  const asked = (name, fallback) => {
    const value = Number(address.get(name) ?? '');
    return address.has(name) && address.get(name) !== '' && Number.isFinite(value) ? value : fallback;
  };
  return {
    process_xy: asked('process-xy', defaults.process_xy),
    process_theta: asked('process-theta', defaults.process_theta),
    noise: { c_xy: asked('c-xy', defaults.noise.c_xy), c_theta: asked('c-theta', defaults.noise.c_theta) },
    field_of_view: asked('field-of-view', defaults.field_of_view),
    gate: asked('gate', defaults.gate),
    start_sigma: defaults.start_sigma,
  };
}

/**
 * The sensor-fusion exercise's `tuning()` in `language` that returns `settings` (`lambda`,
 * the gate on the squared Mahalanobis distance, is `threshold`: chi2inv(gate, 3)). The
 * heading's noise comes from the platforms' there, so c_θ has no place in it.
 *
 * @param {FusionSettings} settings
 * @param {number} threshold
 * @param {import('../types/Language').Language} language
 */
export function tuningFunction(settings, threshold, language) {
  const finite = Number.isFinite(threshold);
  const values = [
    ['k_xy', settings.process_xy], ['k_theta', settings.process_theta], ['c_xy', settings.noise.c_xy],
    ['field_of_view', settings.field_of_view],
  ];
  switch (language) {
    case 'python': {
      const lambda = finite ? String(threshold) : 'float("inf")';
      const fields = [...values.map(([name, value]) => `"${name}": ${value}`), `"lambda": ${lambda}`];
      return `def tuning(): return {${fields.join(', ')}}`;
    }
    case 'matlab': {
      const lambda = finite ? String(threshold) : 'Inf';
      const fields = [...values.map(([name, value]) => `'${name}', ${value}`), `'lambda', ${lambda}`];
      return `function settings = tuning(), settings = struct(${fields.join(', ')}); end`;
    }
    default: {
      const lambda = finite ? String(threshold) : 'Infinity';
      const fields = [...values.map(([name, value]) => `${name}: ${value}`), `lambda: ${lambda}`];
      return `function tuning() { return { ${fields.join(', ')} }; }`;
    }
  }
}

/** The settings other than the process noise, in words (what a tuning kept). */
export function describeRest(settings) {
  const gate = settings.gate === 1 ? 'the gate off' : `the gate at ${settings.gate}`;
  return `c_xy = ${fmt(settings.noise.c_xy)}, c_θ = ${fmt(settings.noise.c_theta)}, a field of view of ${fmt(settings.field_of_view)} m and ${gate}`;
}
