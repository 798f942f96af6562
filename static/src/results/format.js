// Results and times in words, as the pages and the server write them: shares, lengths of
// time, a submission's lateness, a result's score, and moments in the reader's time zone.
import { fmt } from '../format.js';

/** @typedef {import('../types/GradeResult').GradeResult} GradeResult */

/** A share as a whole percentage: `85 %`. */
export function percent(share) {
  return `${Math.round(100 * share)} %`;
}

/**
 * A length of time in words, as the server writes it (`deadline::span`): `18 s` under a
 * minute, then `40 min`, `5 h 12 min`, `3 days 4 h`.
 */
export function span(seconds) {
  const whole = Math.floor(Math.max(0, seconds));
  const minutes = Math.floor(whole / 60);
  const days = Math.floor(minutes / 1440);
  const hours = Math.floor(minutes / 60) % 24;
  if (minutes === 0) return `${whole} s`;
  if (days === 0 && hours === 0) return `${minutes} min`;
  if (days === 0) return `${hours} h ${minutes % 60} min`;
  return days === 1 ? `1 day ${hours} h` : `${days} days ${hours} h`;
}

/**
 * A submission's lateness by its student's dates in force, as /me writes it: `on time`,
 * `18 s late (−10 %)`, or `18 s late, penalty waived: REASON`.
 *
 * @param {{ late_seconds: number, penalty: number, waiver: import('../types/Waiver').Waiver | null }} submission
 */
export function lateness(submission) {
  if (!(submission.late_seconds > 0)) return 'on time';
  const late = `${span(submission.late_seconds)} late`;
  return submission.waiver
    ? `${late}, penalty waived: ${submission.waiver.reason}`
    : `${late} (−${percent(submission.penalty)})`;
}

/**
 * A result's score in words: `85 % (93.5 of 110 points)`, or that it was not gradable.
 *
 * @param {GradeResult | null} result
 */
export function scoreOf(result) {
  if (!result?.gradable) return 'not gradable';
  return `${percent(result.score)} (${fmt(result.points, 4)} of ${result.max_points} points)`;
}

/**
 * How a moment is shown: to the minute, with the zone it is shown in (`15 Dec 2026, 23:59 CET`).
 *
 * @type {Intl.DateTimeFormatOptions}
 */
const MOMENT = { year: 'numeric', month: 'short', day: 'numeric', hour: '2-digit', minute: '2-digit', timeZoneName: 'short' };

/**
 * A datetime-local field's value (a wall time, `2026-12-15T23:59`) as the instant it
 * means in the reader's time zone, as the server reads it (UTC, `...Z`); null when it is
 * no time.
 */
export function instant(local) {
  const at = new Date(local);
  return local && !Number.isNaN(at.getTime()) ? at.toISOString() : null;
}

/** The reader's time zone, as the pages name it beside the fields that take a time. */
export const zone = Intl.DateTimeFormat().resolvedOptions().timeZone;

/** A moment in the reader's time zone, as the workbench dates a deadline or a submission. */
export const localTime = (at) => new Date(at).toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });

/** A moment in the reader's time zone, named, or a dash. */
export function moment(text) {
  const at = text ? new Date(text) : null;
  return at && !Number.isNaN(at.getTime()) ? at.toLocaleString(undefined, MOMENT) : '–';
}
