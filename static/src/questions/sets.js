// The assignment's question sets as their instructors write them: each set's TOML in a
// field of its own (the format is in the README, "The written questions"), sets added,
// removed or loaded from files (several at once, in order, as `estlab course questions`
// takes them), saved together; a problem comes back naming its set, line, question and
// field, and nothing is changed. "The exercise's own sets" goes back to those its folder
// ships. Assistants read the sets here without changing them.
import { postJson } from '../results/http.js';
import { element } from '../results/render.js';

/** @typedef {import('../types/Written').Written} Written */

/**
 * A field of one set's TOML, with its label and a button that removes it.
 *
 * @param {string} text
 * @param {boolean} editable
 */
function setField(text, editable) {
  const box = element('div', 'set-source');
  const label = element('label', null, 'Set');
  const field = document.createElement('textarea');
  field.rows = 12;
  field.spellcheck = false;
  field.value = text;
  field.readOnly = !editable;
  label.append(field);
  box.append(label);
  if (editable) {
    const remove = element('button', null, 'Remove the set');
    remove.type = 'button';
    remove.addEventListener('click', () => {
      const list = box.parentElement;
      box.remove();
      if (list) number(list);
    });
    box.append(remove);
  }
  return box;
}

/**
 * Names each set's field by its place ("Set 1 (TOML)").
 *
 * @param {HTMLElement} list
 */
function number(list) {
  [...list.querySelectorAll('.set-source')].forEach((box, i) => {
    const label = box.querySelector('label');
    if (label?.firstChild) label.firstChild.textContent = `Set ${i + 1} (TOML) `;
    const remove = box.querySelector('button');
    if (remove) remove.textContent = `Remove set ${i + 1}`;
  });
}

/**
 * The editor of the sets in `section`; `saved(written)` redraws the page with the sets as
 * the server took them.
 *
 * @param {HTMLElement} section
 * @param {string} api
 * @param {Written} written
 * @param {(written: Written) => void} saved
 */
export function showSets(section, api, written, saved) {
  const heading = element('h2', null, 'The question sets');
  heading.id = 'sets-title';
  section.setAttribute('aria-labelledby', heading.id);
  const editable = written.instructor;
  const note = element('p', 'note', (written.own ? 'The exercise’s own sets. ' : 'Sets given to this assignment. ') +
    (editable
      ? 'Edit a set’s TOML, add or remove sets, or load .toml files (several at once, in order), then save: a problem names its set, line, question and field, and nothing changes until every set reads. Answers are kept by question id.'
      : 'Only the course’s instructors change them.'));
  const list = element('div', 'set-sources');
  list.append(...written.sources.map((text) => setField(text, editable)));
  number(list);
  const said = element('p', 'status');
  said.setAttribute('role', 'status');
  section.replaceChildren(heading, note, list);
  if (!editable) return;

  const add = element('button', null, 'Add a set');
  add.type = 'button';
  add.addEventListener('click', () => {
    list.append(setField('title = ""\n\n[[question]]\nid = ""\nkind = "text"\nprompt = ""\nmodel = ""\n', true));
    number(list);
  });
  const filesLabel = element('label', null, 'Load .toml files ');
  const files = document.createElement('input');
  files.type = 'file';
  files.accept = '.toml,text/plain';
  files.multiple = true;
  filesLabel.append(files);
  /** The sets as the fields hold them. */
  const fields = () => [...list.querySelectorAll('textarea')].map((field) => field.value);
  /** What the fields held when last loaded or saved. */
  let kept = fields().join('\u0000');
  files.addEventListener('change', async () => {
    const texts = await Promise.all([...(files.files ?? [])].map((file) => file.text()));
    files.value = '';
    if (texts.length === 0) return;
    if (fields().join('\u0000') !== kept && !confirm('Replace the sets in the fields, edited and not saved, with the files?')) return;
    list.replaceChildren(...texts.map((text) => setField(text, true)));
    number(list);
    kept = fields().join('\u0000');
    said.textContent = `${texts.length} file${texts.length === 1 ? '' : 's'} loaded: save to give them to the assignment.`;
  });
  const send = async (/** @type {string[] | null} */ sets, /** @type {string} */ done) => {
    try {
      /** @type {Written} */
      const written = await postJson(`${api}/questions`, { sets });
      list.replaceChildren(...written.sources.map((text) => setField(text, true)));
      number(list);
      kept = fields().join('\u0000');
      saved(written);
      said.textContent = done;
    } catch (error) {
      said.textContent = `Not saved: ${error instanceof Error ? error.message : error}`;
    }
  };
  const save = element('button', 'primary', 'Save the sets');
  save.type = 'button';
  save.addEventListener('click', () => {
    const sets = fields();
    send(sets, `Saved: ${sets.length} set${sets.length === 1 ? '' : 's'}.`);
  });
  const own = element('button', null, 'The exercise’s own sets');
  own.type = 'button';
  own.addEventListener('click', () => send(null, 'The exercise’s own sets again.'));
  const tools = element('div', 'set-tools');
  tools.append(add, filesLabel, save, own);
  section.append(tools, said);
}
