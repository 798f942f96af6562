// Small helpers for the experiment controls.

/**
 * A range input that holds log10 of its value: `<input type=range min=-2 max=2>` spans
 * 1/100 to 100. `label` shows the value as `show(value)` returns it.
 */
export class LogSlider {
  constructor(input, label, show) {
    this.input = input;
    this.label = label;
    this.show = show;
    input.addEventListener('input', () => this.render());
    this.render();
  }

  get value() {
    return 10 ** Number(this.input.value);
  }

  set value(v) {
    this.input.value = String(Math.log10(v));
    this.render();
  }

  render() {
    if (this.label) this.label.textContent = this.show(this.value);
  }
}

/**
 * The element with this id, of the kind given (`HTMLInputElement`; any element without),
 * or an error that says which is missing or is not of that kind.
 *
 * @template {Element} [T=HTMLElement]
 * @param {string} id
 * @param {{ new (): T, prototype: T }} [kind]
 * @returns {T}
 */
export function byId(id, kind) {
  const element = document.getElementById(id);
  if (!element) throw new Error(`the page has no element #${id}`);
  if (kind && !(element instanceof kind)) {
    throw new Error(`the page's element #${id} is not a ${kind.name}`);
  }
  return /** @type {T} */ (/** @type {unknown} */ (element));
}

/** Offers `data` (a Blob, or text of MIME type `type`) as a file download named `name`. */
export function download(name, data, type = 'text/plain') {
  const blob = data instanceof Blob ? data : new Blob([data], { type });
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

/** Shows `message` in the page's error box, or hides the box when it is empty. */
export function showError(box, message) {
  box.textContent = message ?? '';
  box.hidden = !message;
}

/**
 * Sets `element`'s text to `text` unless it has it already: the same text set again
 * still makes the browser lay out and paint the element anew.
 */
export function setText(element, text) {
  if (element.textContent !== text) element.textContent = text;
}

/**
 * Shows `message` beside `input` (null: takes it away): in a note right after the
 * input's label, where the eye looks (a message at the page's top may lie a screen away
 * on a phone), with the input marked invalid and described by the note, so that a screen
 * reader reads the message with the field. `live`: the note is announced as it changes
 * (leave it off where an alert elsewhere says the same).
 */
export function fieldMessage(input, message, { live = true } = {}) {
  const id = `${input.id}-problem`;
  let note = document.getElementById(id);
  if (!note) {
    if (!message) return;
    note = document.createElement('span');
    note.id = id;
    note.className = 'field-problem';
    if (live) note.setAttribute('aria-live', 'polite');
    (input.closest('label') ?? input).after(note);
  }
  setText(note, message ?? '');
  note.hidden = !message;
  const described = new Set((input.getAttribute('aria-describedby') ?? '').split(' ').filter(Boolean));
  if (message) {
    input.setAttribute('aria-invalid', 'true');
    described.add(id);
  } else {
    input.removeAttribute('aria-invalid');
    described.delete(id);
  }
  if (described.size) input.setAttribute('aria-describedby', [...described].join(' '));
  else input.removeAttribute('aria-describedby');
}
