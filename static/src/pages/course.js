// A course's page for its staff: the exercises it has opened, its students, staff and
// API tokens, and the staff's actions; for its instructors, the forms that set it up
// (an exercise opened with its dates and policy, the roster previewed then imported, new
// sign-in codes, staff and their one-time links, tokens). Every change goes through the
// course's API, which checks that the asker is an instructor of the course; what is
// shown once (codes, links, tokens) lives in this page only.
import { byId } from '../controls.js';
import { instant, moment as when, percent, zone } from '../results/format.js';
import { getJson, postJson } from '../results/http.js';
import { element, fillTable, link } from '../results/render.js';

/** @typedef {import('../types/CourseView').CourseView} CourseView */
/** @typedef {import('../types/CodesFile').CodesFile} CodesFile */
/** @typedef {import('../types/CodesStarted').CodesStarted} CodesStarted */
/** @typedef {import('../types/CodesProgress').CodesProgress} CodesProgress */

const root = byId('course-setup');
const { course } = root.dataset;
const api = `/api/courses/${encodeURIComponent(course)}`;

/**
 * Says `text` in a status line; `error` marks it as a problem to correct.
 *
 * @param {string} id
 * @param {string} text
 */
function say(id, text, error = false) {
  const line = byId(id);
  line.textContent = text;
  line.classList.toggle('error', error);
}

/**
 * Runs `work` for a form's button, saying its error (the server names the field) in `status`.
 *
 * @param {string} status
 * @param {HTMLButtonElement} button
 * @param {() => Promise<void>} work
 */
async function acting(status, button, work) {
  button.disabled = true;
  say(status, 'Working…');
  try {
    await work();
  } catch (error) {
    say(status, error.message, true);
  } finally {
    button.disabled = false;
  }
}

// ---------------------------------------------------------------------------------------
// Moments: the browser's datetime-local fields hold a wall time without a zone; the
// server takes a moment with its zone, so the reader's zone is added and named.

/**
 * An instant as a datetime-local field's value, in the reader's zone.
 *
 * @param {string} text
 */
function localValue(text) {
  const at = new Date(text);
  const pad = (n) => String(n).padStart(2, '0');
  return `${at.getFullYear()}-${pad(at.getMonth() + 1)}-${pad(at.getDate())}T${pad(at.getHours())}:${pad(at.getMinutes())}`;
}

// ---------------------------------------------------------------------------------------
// Files shown once: the codes of a roster's new students, or of students given new ones.

/** @type {string | null} */
let codesUrl = null;

/**
 * Offers `codes` (the server's codes file) for download, and downloads it at once.
 *
 * @param {CodesFile} codes
 */
function offerCodes(codes) {
  if (codesUrl) URL.revokeObjectURL(codesUrl);
  codesUrl = URL.createObjectURL(new Blob([codes.csv], { type: 'text/csv' }));
  const anchor = byId('codes-link', HTMLAnchorElement);
  anchor.href = codesUrl;
  anchor.download = codes.file_name;
  byId('codes-text').textContent = codes.count === 0
    ? 'Nobody new needs a code.'
    : `${codes.count} sign-in code(s) are in ${codes.file_name}, downloaded now. They are stored hashed and cannot be shown again once you leave this page: send them (a mail merge reads the file), then delete the file.`;
  byId('codes-download').hidden = false;
  if (codes.count > 0) anchor.click();
}

/** How often the making of codes is looked at, in milliseconds. */
const CODES_LOOK_MS = 1000;

/**
 * Follows the making of codes the server started (each is hashed, about 0.1 s: a large
 * class's take minutes), saying how far it got in `status`, then offers the codes file.
 *
 * @param {CodesStarted} started
 * @param {string} status
 */
async function followCodes(started, status) {
  for (;;) {
    /** @type {CodesProgress} */
    const progress = await getJson(started.url);
    if (progress.failed) throw new Error(`The sign-in codes were not all made: ${progress.failed}.`);
    if (progress.file) return offerCodes(progress.file);
    if (progress.fetched) throw new Error('These codes were handed over already (in another tab?): make new ones if they are lost.');
    say(status, `Making sign-in codes: ${progress.done} of ${progress.total}…`);
    await new Promise((resolve) => setTimeout(resolve, CODES_LOOK_MS));
  }
}

/**
 * Puts `text` in a read-only field with a copy button, and selects it.
 *
 * @param {string} box
 * @param {string} field
 * @param {string} copy
 * @param {string} text
 */
function showSecret(box, field, copy, text) {
  const shown = byId(field, HTMLInputElement);
  shown.value = text;
  byId(box).hidden = false;
  byId(copy).onclick = () => navigator.clipboard?.writeText(text);
  shown.select();
}

// ---------------------------------------------------------------------------------------
// The course as set up.

/** @type {CourseView} The course as the server last said. */
let view = null;

function showAssignments() {
  const titles = new Map(view.exercises.map((e) => [e.name, e.title]));
  fillTable(byId('assignments'), ['Exercise', 'Due', 'Cutoff', 'Late penalty', 'Counts'],
    view.assignments.map((a) => [
      link(`/courses/${encodeURIComponent(course)}/${encodeURIComponent(a.lab)}`, titles.get(a.lab) ?? a.lab),
      when(a.due), when(a.cutoff), `${percent(a.penalty_per_day)} / day`, a.counts,
    ]));
  if (view.assignments.length === 0) {
    byId('assignments').replaceChildren(element('caption', null, 'No exercise is open yet.'));
  }
  const select = byId('assign-lab', HTMLSelectElement);
  const chosen = select.value;
  select.replaceChildren(...view.exercises.map((e) => {
    const option = element('option', null, e.title);
    option.value = e.name;
    return option;
  }));
  if (chosen) select.value = chosen;
  fillAssignForm();
}

/** The form holds the chosen exercise's dates and policy when it is open already. */
function fillAssignForm() {
  const open = view.assignments.find((a) => a.lab === byId('assign-lab', HTMLSelectElement).value);
  byId('assign-form').querySelector('button[type=submit]').textContent = open ? 'Change its dates and policy' : 'Open the exercise';
  if (!open) return;
  byId('assign-due', HTMLInputElement).value = localValue(open.due);
  byId('assign-cutoff', HTMLInputElement).value = open.cutoff === open.due ? '' : localValue(open.cutoff);
  byId('assign-penalty', HTMLInputElement).value = String(Math.round(open.penalty_per_day * 10000) / 100);
  byId('assign-counts', HTMLSelectElement).value = open.counts;
}

function showStudents() {
  const students = view.members.filter((m) => m.role === 'student');
  const dropped = students.filter((m) => m.dropped).length;
  byId('roster-facts').textContent = students.length === 0
    ? 'No student yet: import the roster.'
    : `${students.length - dropped} on the roster${dropped ? `, ${dropped} dropped (their submissions stay)` : ''}.`;
  const rows = students.map((m) => {
    const box = element('input');
    box.type = 'checkbox';
    box.value = m.login;
    box.className = 'pick';
    box.setAttribute('aria-label', `select ${m.name || m.login}`);
    box.disabled = !view.may_set_up;
    return [box, m.login, m.name, m.email, m.dropped ? 'dropped' : 'on the roster'];
  });
  fillTable(byId('students'), ['Select', 'Id', 'Name', 'Email', 'Status'], rows);
  byId('reissue').hidden = !view.may_set_up || students.length === 0;
  updateReissue();
}

function picked() {
  return [...byId('students').querySelectorAll('input.pick:checked')].map((box) => /** @type {HTMLInputElement} */ (box).value);
}

function updateReissue() {
  const count = picked().length;
  const button = byId('reissue-button', HTMLButtonElement);
  button.disabled = count === 0;
  button.textContent = count ? `New codes for the ${count} selected student(s)` : 'New codes for the selected students';
}

function showStaff() {
  fillTable(byId('staff'), ['Email', 'Name', 'Role'],
    view.members.filter((m) => m.role !== 'student').map((m) => [m.email || m.login, m.name || '–', m.role]));
}

function showTokens() {
  const rows = view.tokens.map((t) => {
    if (t.revoked) return [String(t.id), t.role, when(t.created_at), 'revoked'];
    const revoke = element('button', null, 'Revoke');
    revoke.type = 'button';
    revoke.disabled = !view.may_set_up;
    revoke.setAttribute('aria-label', `revoke token ${t.id}`);
    revoke.addEventListener('click', () => acting('token-status', revoke, async () => {
      await postJson(`${api}/tokens/${t.id}/revoke`, null);
      say('token-status', `Token ${t.id} is revoked: it no longer works.`);
      await load();
    }));
    return [String(t.id), t.role, when(t.created_at), revoke];
  });
  fillTable(byId('tokens'), ['Token', 'Role', 'Made', 'State'], rows);
  if (view.tokens.length === 0) byId('tokens').replaceChildren(element('caption', null, 'No token yet.'));
}

async function showAudit() {
  /** @type {import('../types/AuditEntry').AuditEntry[]} */
  const log = await getJson(`${api}/audit`);
  fillTable(byId('course-audit'), ['When', 'Who', 'What', 'Detail'],
    log.map((entry) => [when(entry.at), entry.actor, entry.action, entry.detail]));
}

async function load() {
  view = await getJson(api);
  byId('course-title').textContent = `${view.course.title} (${view.course.name})`;
  byId('read-only').hidden = view.may_set_up;
  for (const form of ['assign-form', 'roster-form', 'staff-form', 'token-form']) byId(form).hidden = !view.may_set_up;
  showAssignments();
  showStudents();
  showStaff();
  showTokens();
  await showAudit();
}

// ---------------------------------------------------------------------------------------
// The forms.

byId('assign-zone').textContent = `Dates are in your time zone, ${zone}; the server keeps them as instants, and everyone sees them in their own zone.`;
byId('assign-lab').addEventListener('change', fillAssignForm);

/**
 * The button that sent a form: the one pressed, or the form's first.
 *
 * @param {SubmitEvent} event
 * @param {string} form
 */
function sender(event, form) {
  return /** @type {HTMLButtonElement} */ (event.submitter ?? byId(form).querySelector('button'));
}

byId('assign-form').addEventListener('submit', (event) => {
  event.preventDefault();
  const button = sender(event, 'assign-form');
  const due = instant(byId('assign-due', HTMLInputElement).value);
  const cutoffField = byId('assign-cutoff', HTMLInputElement).value;
  const penalty = Number(byId('assign-penalty', HTMLInputElement).value);
  if (!due) return say('assign-status', 'Due: give the date and time the exercise is due.', true);
  if (cutoffField && !instant(cutoffField)) return say('assign-status', 'Cutoff: a date and time, or nothing.', true);
  if (byId('assign-penalty', HTMLInputElement).value === '' || !Number.isFinite(penalty) || penalty < 0 || penalty > 100) {
    return say('assign-status', 'Late penalty: a share between 0 and 100 % per day.', true);
  }
  acting('assign-status', button, async () => {
    const lab = byId('assign-lab', HTMLSelectElement).value;
    /** @type {import('../types/Assignment').Assignment} */
    const assignment = await postJson(`${api}/assignments`, {
      lab,
      due,
      cutoff: cutoffField ? instant(cutoffField) : null,
      late_penalty: `${penalty}%/day`,
      counts: byId('assign-counts', HTMLSelectElement).value,
    });
    await load();
    say('assign-status', `${byId('assign-lab', HTMLSelectElement).selectedOptions[0].textContent} is open: due ${when(assignment.due)}, taken until ${when(assignment.cutoff)}.`);
  });
});

/** @type {{ file_name: string, csv: string } | null} The roster file previewed, as the API takes it. */
let rosterFile = null;

/** The chosen roster file's name and text, as the API takes them. */
async function rosterBody() {
  const file = byId('roster-file', HTMLInputElement).files[0];
  if (!file) throw new Error('Choose the roster file (CSV) first.');
  return { file_name: file.name, csv: await file.text() };
}

/**
 * A list of ids under a heading, for the preview.
 *
 * @param {string} title
 * @param {string[]} items
 */
function planList(title, items) {
  const box = element('div', 'plan-part');
  box.append(element('h4', null, `${title}: ${items.length}`));
  if (items.length) {
    const list = element('ul');
    for (const item of items.slice(0, 200)) list.append(element('li', null, item));
    if (items.length > 200) list.append(element('li', null, `and ${items.length - 200} more`));
    box.append(list);
  }
  return box;
}

byId('roster-form').addEventListener('submit', (event) => {
  event.preventDefault();
  acting('roster-status', sender(event, 'roster-form'), async () => {
    byId('roster-preview').hidden = true;
    rosterFile = await rosterBody();
    /** @type {import('../types/RosterAnswer').RosterAnswer} */
    const plan = await postJson(`${api}/roster/preview`, rosterFile);
    byId('roster-plan').replaceChildren(
      element('p', null, `${rosterFile.file_name}: ${plan.summary}. Nothing has changed yet.`),
      planList('New', plan.added.map((s) => `${s.id}: ${s.name}${s.email ? ` <${s.email}>` : ''}`)),
      planList('Updated (name or email, or back on the roster)', plan.updated),
      planList('Marked dropped (not in the file)', plan.dropped),
    );
    byId('roster-preview').hidden = false;
    say('roster-status', 'Check the changes below, then import them.');
    byId('roster-apply').focus();
  });
});

byId('roster-apply').addEventListener('click', () => {
  acting('roster-status', byId('roster-apply', HTMLButtonElement), async () => {
    /** @type {import('../types/RosterAnswer').RosterAnswer} */
    const answer = await postJson(`${api}/roster`, rosterFile);
    byId('roster-preview').hidden = true;
    byId('roster-form', HTMLFormElement).reset();
    await load();
    if (answer.codes) await followCodes(answer.codes, 'roster-status');
    else offerCodes({ file_name: '', count: 0, csv: '' });
    say('roster-status', `Imported ${rosterFile.file_name}: ${answer.summary}.`);
  });
});

byId('roster-cancel').addEventListener('click', () => {
  byId('roster-preview').hidden = true;
  say('roster-status', 'Nothing was imported.');
});

byId('students').addEventListener('change', updateReissue);

byId('reissue-button').addEventListener('click', () => {
  const students = picked();
  acting('reissue-status', byId('reissue-button', HTMLButtonElement), async () => {
    /** @type {CodesStarted} */
    const started = await postJson(`${api}/codes`, { students });
    await followCodes(started, 'reissue-status');
    await load();
    say('reissue-status', `New codes for ${students.join(', ')}: their old codes no longer work.`);
  });
});

byId('staff-form').addEventListener('submit', (event) => {
  event.preventDefault();
  const email = byId('staff-email', HTMLInputElement).value.trim();
  if (!email) return say('staff-status', 'Email: the address they sign in with.', true);
  acting('staff-status', sender(event, 'staff-form'), async () => {
    /** @type {import('../types/StaffAdded').StaffAdded} */
    const added = await postJson(`${api}/staff`, { email, name: byId('staff-name', HTMLInputElement).value.trim(), role: byId('staff-role', HTMLSelectElement).value });
    byId('staff-link-who').textContent = `${added.email} (${added.role})`;
    showSecret('staff-link', 'staff-link-text', 'staff-link-copy', added.link);
    byId('staff-form', HTMLFormElement).reset();
    await load();
    say('staff-status', `${added.email} is ${added.role} of ${course}.`);
  });
});

byId('token-form').addEventListener('submit', (event) => {
  event.preventDefault();
  acting('token-status', sender(event, 'token-form'), async () => {
    /** @type {import('../types/TokenMade').TokenMade} */
    const made = await postJson(`${api}/tokens`, { role: byId('token-role', HTMLSelectElement).value });
    byId('token-made-id').textContent = `${made.id} (${made.role})`;
    showSecret('token-made', 'token-text', 'token-copy', made.token);
    await load();
    say('token-status', `Token ${made.id} is made.`);
  });
});

load()
  .catch((error) => say('course-status', `The course could not be read: ${error.message}`, true))
  .finally(() => { document.body.dataset.ready = 'true'; });
