// Who submits, and the variant: the signed-in student's own, or, on a server without
// courses, the one the typed student id gives (or a link's `?seed=N`). The server says
// who is signed in (GET /api/me) and, for a student, where their assignment stands, and
// is asked again as that changes.
import { localTime, percent, span } from '../results/format.js';
import { getJson } from '../results/http.js';
import { element, link } from '../results/render.js';
import { site } from '../site.js';

/**
 * What /api/me answered, or why it did not (`problem`, with `courses` null).
 *
 * @typedef {Omit<Partial<import('../types/About').About>, 'courses'> & { courses: boolean | null, problem?: string }} Known
 */

/** The course of a typed student id: its variant's, and its submission's (the server's default). */
export const COURSE = site.course;
/** The seed of the variant graded without a student id, as `estlab grade` without --seed. */
const PUBLIC_VARIANT = 1;
/** Where the student id is saved: once for all exercises. */
const STORAGE = 'estlab:student';
/** How often the standing is asked for again: it reads in minutes. */
const REFRESH_MS = 60_000;

/**
 * Who is signed in and what they have to do (GET /api/me), or why that is not known.
 *
 * @returns {Promise<Known>}
 */
export async function whoAmI() {
  try {
    return await getJson('/api/me');
  } catch (error) {
    return { courses: null, problem: error.message };
  }
}

/** @param {Known} about */
function modeOf(about) {
  if (about.courses === false) return 'open';
  if (about.courses !== true) return 'unknown';
  if (!about.member) return 'anonymous';
  return about.member.role === 'student' ? 'student' : 'staff';
}

/**
 * Who is at the keyboard, as /api/me says: `mode` is 'open' (a server without courses:
 * anyone submits under any id), 'student' (signed in), 'staff', 'anonymous' (a server with
 * courses, nobody signed in) or 'unknown' (the server did not answer); `assignment` is the
 * student's assignment of this exercise, with its `standing` as the server decided it
 * when it answered (open, late with the penalty a submission would lose, or closed).
 *
 * `estlab`: the wasm build (the seed of a student id); `lab`: the exercise; `ui`: the line
 * above the toolbar (`who`), the student id's field (`student`) and its label
 * (`studentField`), and the note on the variant (`seed`); `runsLabel`: what the button
 * that runs the exercise's loop says; `resultsSeed()`: the seed of the results shown, or
 * null while there are none.
 */
export class Identity {
  /**
   * @param {{
   *   estlab: typeof import('estlab-wasm/estlab_wasm.js'),
   *   lab: string,
   *   ui: { who: HTMLElement, studentField: HTMLElement, student: HTMLInputElement, seed: HTMLElement },
   *   runsLabel: string,
   *   resultsSeed: () => number | null,
   * }} parts
   */
  constructor({ estlab, lab, ui, runsLabel, resultsSeed }) {
    this.estlab = estlab;
    this.lab = lab;
    this.ui = ui;
    this.runsLabel = runsLabel;
    this.resultsSeed = resultsSeed;
    /** @type {Known | null} What /api/me last answered, once `know` has it. */
    this.about = null;
    this.mode = 'unknown';
    /** @type {import('../types/StudentAssignment').StudentAssignment | null} */
    this.assignment = null;
    /** @type {ReturnType<typeof setTimeout> | null} */
    this.refreshTimer = null;
    /**
     * A variant named by the link (`?seed=N`), as the results of estlab's Gradescope and
     * PrairieLearn packages name it, or null.
     */
    this.linkedSeed = (() => {
      const text = new URLSearchParams(location.search).get('seed') ?? '';
      return /^\d{1,16}$/.test(text) && Number(text) < 2 ** 53 ? Number(text) : null;
    })();
    document.addEventListener('visibilitychange', () => {
      if (document.visibilityState === 'visible' && this.mode === 'student') this.refresh();
    });
    ui.student.value = localStorage.getItem(STORAGE) ?? '';
    ui.student.addEventListener('input', () => this.showVariant());
    ui.student.addEventListener('change', () => {
      localStorage.setItem(STORAGE, ui.student.value.trim());
      this.showVariant();
    });
  }

  /**
   * Takes in what /api/me answered, and shows it.
   *
   * @param {Known} about
   */
  know(about) {
    this.about = about;
    this.mode = modeOf(about);
    this.assignment = (about.assignments ?? []).find((a) => a.lab === this.lab) ?? null;
    this.showWho();
    this.showVariant();
    this.scheduleRefresh();
  }

  /** Asks the server again who is signed in (after a submission, say), keeping what is known if it does not answer. */
  async refresh() {
    const about = await whoAmI();
    if (about.courses !== null) this.know(about);
  }

  /**
   * Asks the server again in a minute, or sooner when the standing changes before then (the
   * due date or the cutoff passes): the server alone says whether a submission is late and
   * what it costs. A page out of sight asks again when it is seen.
   */
  scheduleRefresh() {
    clearTimeout(this.refreshTimer);
    if (this.mode !== 'student') return;
    const standing = this.assignment?.standing;
    const next = standing?.state === 'open' ? standing.seconds_left
      : standing?.state === 'late' ? standing.seconds_to_cutoff : Infinity;
    const wait = Math.min(REFRESH_MS, 1000 * (next + 1));
    this.refreshTimer = setTimeout(() => {
      if (document.visibilityState === 'visible') this.refresh();
    }, wait);
  }

  /** The assignment's due date and what a submission now would be (as the server last said): on time, late and its penalty, or refused. */
  deadline() {
    const a = this.assignment;
    if (!a) return 'Your course has not opened this exercise yet: submissions are not taken.';
    const { standing } = a;
    const due = `Due ${localTime(a.due)}`;
    if (standing.state === 'open') return `${due}: ${span(standing.seconds_left)} left.`;
    if (standing.state === 'closed') {
      return `${due}: closed, no more submissions are taken (the last were taken until ${localTime(a.cutoff)}).`;
    }
    const cost = standing.penalty > 0 ? `loses ${percent(standing.penalty)} of its score` : 'has no late penalty';
    return `${due}: a submission now is ${span(standing.late_seconds)} late and ${cost}; ` +
      `the last are taken until ${localTime(a.cutoff)}, ${span(standing.seconds_to_cutoff)} from now.`;
  }

  /** The line above the toolbar: who submits, and the deadline. */
  showWho() {
    const { about, mode, ui, runsLabel } = this;
    const member = about.member;
    const name = member ? member.name || member.login : '';
    ui.studentField.hidden = !(mode === 'open' || mode === 'unknown');
    ui.who.hidden = false;
    ui.who.dataset.mode = mode;
    if (mode === 'open') {
      ui.who.replaceChildren('This server runs no course: anyone may submit under any student id, and results are open to all.');
    } else if (mode === 'unknown') {
      ui.who.replaceChildren(`The server did not say who is signed in (${about.problem}): a submission may be refused.`);
    } else if (mode === 'anonymous') {
      ui.who.replaceChildren('This server runs a course: ', link('/signin', 'sign in'),
        ` with your code to submit. Run tests and ${runsLabel} need no sign-in (on the public variant).`);
    } else if (mode === 'staff') {
      ui.who.replaceChildren(`Signed in as ${name} (${member.role} of ${member.course}): staff do not submit. ` +
        `Run tests and ${runsLabel} work, on the public variant.`);
    } else {
      const who = element('span', 'signed-in', `Signed in as ${name} (${member.login}), ${member.course}`);
      const when = element('span', 'deadline', member.dropped
        ? `You are no longer on the roster of ${member.course}: new submissions are not taken.`
        : this.deadline());
      when.id = 'deadline';
      ui.who.replaceChildren(who, ' (', link('/me', 'your submissions'), '). ', when);
    }
  }

  /** Whether the student id typed in the field says who submits (a server without courses). */
  typedId() {
    return this.mode === 'open' || this.mode === 'unknown';
  }

  /** The seed of the variant the browser runs. */
  seed() {
    if (this.mode === 'student') return this.about.seed;
    if (this.linkedSeed !== null) return this.linkedSeed;
    const student = this.typedId() ? this.ui.student.value.trim() : '';
    return student ? this.estlab.studentSeed(COURSE, student) : PUBLIC_VARIANT;
  }

  /**
   * Says which variant the id gives, as it is typed; results of another variant stay until
   * the next run, and the note says whose they are.
   */
  showVariant() {
    const current = this.seed();
    let note;
    if (this.mode === 'student') note = `your own variant: seed ${current}`;
    else if (this.linkedSeed !== null) {
      note = `the variant of your link: seed ${current}`;
      if (this.typedId()) note += ' (Submit sends your file to this server, which grades the variant of your student id)';
    }
    else if (!this.typedId()) note = `the public variant, seed ${current}`;
    else if (this.ui.student.value.trim()) note = `your own variant: seed ${current}`;
    else note = `no id yet: the public variant, seed ${current}`;
    const shown = this.resultsSeed();
    if (shown !== null && shown !== current) {
      note += `. The results below are for seed ${shown}: run again for this variant.`;
    }
    this.ui.seed.textContent = note;
  }
}
