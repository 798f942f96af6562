// Tuning on one trial and testing on another: the process noise that does best on the
// trial it is tuned on, beside the round settings, on that trial and on one it never saw.
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { row } from '../odometry/view.js';
import { meanError } from './run.js';
import { describeRest } from './settings.js';

/** @typedef {import('../types/FusionSettings').FusionSettings} FusionSettings */
/** @typedef {import('./trials.js').LoadedTrial} LoadedTrial */

/**
 * A tuning and its test.
 *
 * @typedef {object} Tuning
 * @property {string} trained the trial tuned on, in a table's words
 * @property {string} tested the trial tested on
 * @property {FusionSettings} base the settings tuned from
 * @property {FusionSettings} round `base` with the round process noise
 * @property {FusionSettings} tuned `base` with the tuned process noise
 * @property {{ round: number, tuned: number }} onTrained the mean errors on the trial tuned on
 * @property {{ round: number, tuned: number }} onTested and on the other
 */

/**
 * Tunes the process noise on `train` from `base` and tests it on `test`, beside the
 * round process noise of `defaults` on both.
 *
 * @param {LoadedTrial} train
 * @param {LoadedTrial} test
 * @param {FusionSettings} base
 * @param {FusionSettings} defaults
 * @returns {Tuning}
 */
export function tuneAndTest(train, test, base, defaults) {
  /** @type {{ settings: FusionSettings, mean: number }} */
  const found = JSON.parse(train.trial.tune(JSON.stringify(base)));
  const round = { ...base, process_xy: defaults.process_xy, process_theta: defaults.process_theta };
  return {
    trained: train.short,
    tested: test.short,
    base,
    round,
    tuned: found.settings,
    onTrained: { round: meanError(train.trial, round), tuned: found.mean },
    onTested: { round: meanError(test.trial, round), tuned: meanError(test.trial, found.settings) },
  };
}

/** Shows `tuning` in the tuning table, with a line that says what it found. */
export function showTuning(tuning) {
  const table = byId('tuning-table', HTMLTableElement);
  table.hidden = false;
  setText(byId('tuning-caption'), `Tuned on ${tuning.trained}, tested on ${tuning.tested}, with ${describeRest(tuning.base)}: mean position error`);
  setText(byId('trained-heading'), `on ${tuning.trained}, tuned on (m)`);
  setText(byId('tested-heading'), `on ${tuning.tested}, not seen (m)`);
  const cells = (settings, key) => [
    [fmt(settings.process_xy), settings.process_xy],
    [fmt(settings.process_theta), settings.process_theta],
    [fmt(tuning.onTrained[key], 3), tuning.onTrained[key]],
    [fmt(tuning.onTested[key], 3), tuning.onTested[key]],
  ];
  table.tBodies[0].replaceChildren(
    row('the round settings', cells(tuning.round, 'round'), 'round'),
    row(`tuned on ${tuning.trained}`, cells(tuning.tuned, 'tuned'), 'tuned'),
  );
  const [tuned, round] = [tuning.onTested.tuned, tuning.onTested.round];
  const compared = tuned < round ? 'better than' : tuned > round ? 'worse than' : 'the same as';
  setText(byId('tune-note'),
    `Tuned on ${tuning.trained}: k_xy = ${fmt(tuning.tuned.process_xy)}, k_θ = ${fmt(tuning.tuned.process_theta)}, ` +
    `${fmt(tuning.onTrained.tuned, 3)} m on ${tuning.trained} (the round settings: ${fmt(tuning.onTrained.round, 3)} m). ` +
    `On ${tuning.tested}, which the tuning never saw, ${fmt(tuned, 3)} m: ${compared} the round settings' ${fmt(round, 3)} m` +
    (tuned > round ? `: the tuning fitted the chance errors of ${tuning.trained} too.` : '.') +
    ` The tuned settings are applied, and ${tuning.tested} is shown.`);
}
