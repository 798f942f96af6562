// What the workbenches of the exercises whose runs record a belief at every step (the
// sensor fusion's, the UKF and particle filter's) show alike: how far the student's
// belief is from the reference's at each step, drawn on a log scale against the grader's
// tolerance and said in words, and the table of the step where the run departs.
import { wrap } from '../angles.js';
import { setText } from '../controls.js';
import { fmt } from '../format.js';
import { colours, dashes, styled, timeLine } from '../plots.js';
import { fillHeadedRows } from '../results/render.js';

const degrees = Math.PI / 180;
/** The grader's tolerance on a pose (`grading::STEP_BY_STEP` in labs), drawn on the plot of the differences. */
export const POSE_TOLERANCE = 1e-6;
/** Where the plot of the differences (a log scale) draws differences smaller than this, exact agreement included. */
const FLOOR = 1e-16;
/** A number with `digits` significant digits, and 0 for what is zero but for rounding. */
export const f = (v, digits = 3) => fmt(Math.abs(v) < 1e-12 ? 0 : v, digits);

/**
 * A belief along a run: its pose's three components and their standard deviations, a
 * series each, and how many steps it holds.
 *
 * @typedef {{ pose: Float64Array[], std: Float64Array[], steps: number }} Belief
 */

/**
 * What the belief views read of a run: the times of its steps, the reference's belief and
 * the student's (as far as their run reported), how far apart they are, and the step
 * (from 1) where the student's first leaves the reference's (null where it does not).
 *
 * @typedef {{
 *   t: Float64Array, reference: Belief, student: Belief,
 *   difference: ReturnType<typeof differences>, departure: number | null,
 * }} Compared
 */

/** The pose at step `k` (from 0) of a belief: [x, y, theta]. */
export const poseAt = (belief, k) => belief.pose.map((component) => component[k]);

/**
 * How far the student's belief is from the reference's at each step the run reported:
 * the position's distance (m), the heading's (rad), and the largest relative
 * difference of the standard deviations.
 *
 * @param {Belief} student
 * @param {Belief} reference
 */
export function differences(student, reference) {
  const [s, r] = [student.pose, reference.pose];
  const steps = student.steps;
  const out = { position: new Float64Array(steps), heading: new Float64Array(steps), std: new Float64Array(steps) };
  for (let k = 0; k < steps; k++) {
    out.position[k] = Math.hypot(s[0][k] - r[0][k], s[1][k] - r[1][k]);
    out.heading[k] = Math.abs(wrap(s[2][k] - r[2][k]));
    out.std[k] = Math.max(...[0, 1, 2].map((i) => Math.abs(student.std[i][k] / reference.std[i][k] - 1)));
  }
  return out;
}

/**
 * The difference plot's summary line: the largest differences, and the grader's tolerance.
 *
 * @param {Compared} v
 */
export function describeDifferences(v) {
  const largest = (values, unit) => {
    let at = 0;
    for (let k = 1; k < values.length; k++) if (values[k] > values[at]) at = k;
    return `${fmt(values[at], 3)}${unit} (at step ${at + 1})`;
  };
  const { position, heading, std } = v.difference;
  return `How far your belief is from the reference filter's at each of the ${v.student.steps} steps your run reported, on a log scale ` +
    `(differences under ${fmt(FLOOR)} drawn at it): at most ${largest(position, ' m')} between the positions, ` +
    `${largest(heading, ' rad')} between the headings, and ${largest(std, '')} of the reference's standard deviations between ` +
    `the standard deviations. Grading allows ${fmt(POSE_TOLERANCE)} on the pose.`;
}

/**
 * The series of the difference plot, floored for its log scale, and the grader's tolerance.
 *
 * @param {Compared} v
 */
export function differenceSeries(v) {
  const { t, difference } = v;
  const steps = v.student.steps;
  const shown = (values) => values.map((d) => Math.max(d, FLOOR));
  const times = t.subarray(0, steps);
  return [
    styled(timeLine('position (m)', times, shown(difference.position), colours.estimate), dashes.truth),
    styled(timeLine('heading (rad)', times, shown(difference.heading), colours.second), dashes.estimate),
    styled(timeLine('standard deviations (relative)', times, shown(difference.std), colours.third), dashes.odometry),
    styled(timeLine('the pose\'s tolerance', [times[0], times[steps - 1]], [POSE_TOLERANCE, POSE_TOLERANCE], colours.measurement), 'dashed', 1),
  ];
}

/**
 * The step where the run departs (or else the last it reported), the student's belief
 * beside the reference's.
 *
 * @param {HTMLTableElement} table
 * @param {Compared} v
 */
export function fillBeliefTable(table, v) {
  const { t, reference: r, student: s, departure } = v;
  const step = departure ?? s.steps;
  const k = step - 1;
  setText(table.caption, departure !== null
    ? `At step ${step} of ${r.steps} (t = ${f(t[k], 4)} s), where your run first departs from the reference's`
    : `After step ${step} of ${r.steps}, the last your run reported`);
  const [sp, rp] = [poseAt(s, k), poseAt(r, k)];
  const rows = [
    ['x (m)', f(sp[0], 8), f(rp[0], 8)],
    ['y (m)', f(sp[1], 8), f(rp[1], 8)],
    ['θ (°)', f(sp[2] / degrees, 8), f(rp[2] / degrees, 8)],
    ['σx (m)', fmt(s.std[0][k], 6), fmt(r.std[0][k], 6)],
    ['σy (m)', fmt(s.std[1][k], 6), fmt(r.std[1][k], 6)],
    ['σθ (°)', fmt(s.std[2][k] / degrees, 6), fmt(r.std[2][k] / degrees, 6)],
  ];
  fillHeadedRows(table, rows);
}
