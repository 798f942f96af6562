// The workbench's file: edited in CodeMirror in the language the student chose, saved in
// this browser as it is typed (a file per language), reset to the language's starter
// file, downloaded and uploaded.
import { javascript } from '@codemirror/lang-javascript';
import { python } from '@codemirror/lang-python';
import { StreamLanguage } from '@codemirror/language';
import { octave } from '@codemirror/legacy-modes/mode/octave';
import { Compartment } from '@codemirror/state';
import { EditorView, basicSetup } from 'codemirror';
import { byId, download, showError } from '../controls.js';

const MAX_SOURCE = 256 * 1024;

/**
 * The languages of students' files (`labs::Language`): CodeMirror's mode, the
 * extension and the media type of each.
 *
 * @type {Record<import('../types/Language').Language, { mode: () => import('@codemirror/state').Extension, extension: string, type: string }>}
 */
export const LANGUAGES = {
  javascript: { mode: javascript, extension: 'js', type: 'text/javascript' },
  python: { mode: python, extension: 'py', type: 'text/x-python' },
  matlab: { mode: () => StreamLanguage.define(octave), extension: 'm', type: 'text/x-matlab' },
};

/**
 * The language of a file by its name's extension, or null.
 *
 * @param {string} name
 * @returns {import('../types/Language').Language | null}
 */
export function languageOfFile(name) {
  const extension = name.slice(name.lastIndexOf('.') + 1).toLowerCase();
  const found = Object.entries(LANGUAGES).find(([, language]) => language.extension === extension);
  return found ? /** @type {import('../types/Language').Language} */ (found[0]) : null;
}

/**
 * Why the files chosen to upload cannot be taken, or null: one file, or several MATLAB
 * files (the lab's, a function in each), together within the size a file may have.
 *
 * @param {File[]} uploads
 * @returns {string | null}
 */
function uploadProblem(uploads) {
  if (uploads.length > 1 && !uploads.every((upload) => languageOfFile(upload.name) === 'matlab')) {
    return `${uploads.length} files were chosen: choose one file, or several MATLAB files (.m), which become one.`;
  }
  const size = uploads.reduce((sum, upload) => sum + upload.size, 0);
  if (size > MAX_SOURCE) {
    const name = uploads.length === 1 ? uploads[0].name : `${uploads.length} files`;
    return `${name}: ${size} bytes; a file may have at most ${MAX_SOURCE / 1024} KB.`;
  }
  return null;
}

/**
 * What both editors share (this one and the read-only one of a submission, viewing.js):
 * long lines wrap (a phone shows a third of an 80-column line), and the text area has a
 * name and a place in the keyboard's order, so that a screen reader says what it is and
 * the keyboard reaches (and scrolls) it, editable or not. `mode`: the compartment that
 * holds the language's highlighting, and the language it starts in.
 *
 * @param {string} name
 * @param {Compartment} mode
 * @param {import('../types/Language').Language} language
 */
export const editorBasics = (name, mode, language) => [
  basicSetup,
  mode.of(LANGUAGES[language].mode()),
  EditorView.lineWrapping,
  EditorView.contentAttributes.of({ 'aria-label': name, tabindex: '0' }),
];

/**
 * The student's file in the editor of #editor, with its language's choice (#language) and
 * its Reset, Download and Upload buttons. `key(language)`: where this browser keeps the
 * file in a language (and the choice itself, under `key('choice')`); `starters`: the
 * file each language starts as when nothing is kept, and that Reset puts back; `file`:
 * the name it downloads as, in JavaScript (other languages take their extension);
 * `saved`: the line that says whether it is saved; `error`: the page's error box;
 * `onEdit(text)`: hears of every change, once it is saved.
 */
export class Editor {
  /**
   * @param {{
   *   key: (language: string) => string,
   *   starters: Record<string, string>,
   *   file: string,
   *   saved: HTMLElement,
   *   error: HTMLElement,
   *   onEdit: (text: string) => void,
   * }} parts
   */
  constructor({ key, starters, file, saved, error, onEdit }) {
    this.key = key;
    this.starters = starters;
    this.file = file;
    this.saved = saved;
    this.onEdit = onEdit;
    this.choice = byId('language', HTMLSelectElement);
    const kept = localStorage.getItem(key('choice'));
    /** @type {import('../types/Language').Language} */
    this.language = kept in LANGUAGES && kept in starters ? /** @type {any} */ (kept) : 'javascript';
    this.choice.value = this.language;
    this.mode = new Compartment();
    /** Whether the editor is switching files (a change that is no edit). */
    this.switching = false;
    this.view = new EditorView({
      doc: this.kept(this.language),
      extensions: [
        ...editorBasics('your code', this.mode, this.language),
        EditorView.updateListener.of((update) => {
          if (update.docChanged && !this.switching) this.edited();
        }),
      ],
      parent: byId('editor'),
    });
    this.choice.addEventListener('change', () => this.use(/** @type {any} */ (this.choice.value)));
    byId('reset').addEventListener('click', () => {
      const starter = this.starters[this.language];
      if (this.source() === starter) return;
      if (confirm('Replace your code with the starter file? Your current code will be lost (download it first to keep it).')) {
        this.replace(starter);
      }
    });
    byId('download').addEventListener('click', () => download(this.fileName(), this.source(), LANGUAGES[this.language].type));
    // A real button, reachable with the keyboard, opens the file chooser.
    byId('upload-button').addEventListener('click', () => byId('upload').click());
    const chooser = byId('upload', HTMLInputElement);
    chooser.addEventListener('change', async () => {
      const uploads = [...(chooser.files ?? [])];
      chooser.value = '';
      if (uploads.length === 0) return;
      const problem = uploadProblem(uploads);
      showError(error, problem);
      if (problem) return;
      // A file in another language switches the editor to it.
      const language = languageOfFile(uploads[0].name);
      if (language && language !== this.language && language in this.starters) this.use(language);
      // The lab's MATLAB files, a function each, become one file, in the order chosen.
      const texts = await Promise.all(uploads.map((upload) => upload.text()));
      this.replace(texts.map((text) => text.replace(/\n*$/, '\n')).join('\n'));
    });
  }

  /**
   * Offers only the `languages` a course takes for this exercise (all when null), moving
   * to the first of them when the file's language is not one.
   *
   * @param {import('../types/Language').Language[] | null} languages
   */
  restrict(languages) {
    for (const option of this.choice.options) {
      option.disabled = languages !== null && !languages.includes(/** @type {any} */ (option.value));
    }
    this.choice.title = languages === null ? '' : 'Your course takes files in these languages only';
    if (languages !== null && languages.length > 0 && !languages.includes(this.language)) this.use(languages[0]);
  }

  /** The file kept in this browser in `language`, or its starter. */
  kept(language) {
    return localStorage.getItem(this.key(language)) ?? this.starters[language];
  }

  /** The file's name in the language chosen: `ekf_localization.py`. */
  fileName() {
    return this.file.replace(/\.[^.]*$/, `.${LANGUAGES[this.language].extension}`);
  }

  /**
   * Switches to the file in `language`: its highlighting, and the file kept in it (the
   * one left stays kept in its own).
   *
   * @param {import('../types/Language').Language} language
   */
  use(language) {
    if (language === this.language) return;
    this.language = language;
    this.choice.value = language;
    try {
      localStorage.setItem(this.key('choice'), language);
    } catch {
      // The choice is only a convenience; the files are what must be kept.
    }
    this.switching = true;
    this.view.dispatch({
      changes: { from: 0, to: this.view.state.doc.length, insert: this.kept(language) },
      effects: this.mode.reconfigure(LANGUAGES[language].mode()),
    });
    this.switching = false;
    this.saved.textContent = `Your ${this.choice.selectedOptions[0].textContent} file, as saved in this browser.`;
    this.onEdit(this.source());
  }

  source() {
    return this.view.state.doc.toString();
  }

  replace(text) {
    this.view.dispatch({ changes: { from: 0, to: this.view.state.doc.length, insert: text } });
  }

  edited() {
    try {
      localStorage.setItem(this.key(this.language), this.source());
      this.saved.textContent = 'Saved in this browser.';
    } catch (error) {
      this.saved.textContent = `Not saved in this browser (${error.message}): download your file to keep it.`;
    }
    this.onEdit(this.source());
  }
}
