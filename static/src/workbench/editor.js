// The workbench's file: edited in CodeMirror, saved in this browser as it is typed, reset
// to the starter file, downloaded and uploaded.
import { javascript } from '@codemirror/lang-javascript';
import { EditorView, basicSetup } from 'codemirror';
import { byId, download, showError } from '../controls.js';

const MAX_SOURCE = 256 * 1024;

/**
 * What both editors share (this one and the read-only one of a submission, viewing.js):
 * long lines wrap (a phone shows a third of an 80-column line), and the text area has a
 * name and a place in the keyboard's order, so that a screen reader says what it is and
 * the keyboard reaches (and scrolls) it, editable or not.
 */
export const editorBasics = (name) => [
  basicSetup,
  javascript(),
  EditorView.lineWrapping,
  EditorView.contentAttributes.of({ 'aria-label': name, tabindex: '0' }),
];

/**
 * The student's file in the editor of #editor, with its Reset, Download and Upload
 * buttons. `key`: where this browser keeps it; `starter`: the file it starts as when
 * nothing is kept there, and that Reset puts back; `file`: the name it downloads as;
 * `saved`: the line that says whether it is saved; `error`: the page's error box;
 * `onEdit(text)`: hears of every change, once it is saved.
 */
export class Editor {
  constructor({ key, starter, file, saved, error, onEdit }) {
    this.key = key;
    this.saved = saved;
    this.onEdit = onEdit;
    this.view = new EditorView({
      doc: localStorage.getItem(key) ?? starter,
      extensions: [
        ...editorBasics('your code'),
        EditorView.updateListener.of((update) => {
          if (update.docChanged) this.edited();
        }),
      ],
      parent: byId('editor'),
    });
    byId('reset').addEventListener('click', () => {
      if (this.source() === starter) return;
      if (confirm('Replace your code with the starter file? Your current code will be lost (download it first to keep it).')) {
        this.replace(starter);
      }
    });
    byId('download').addEventListener('click', () => download(file, this.source(), 'text/javascript'));
    // A real button, reachable with the keyboard, opens the file chooser.
    byId('upload-button').addEventListener('click', () => byId('upload').click());
    const chooser = byId('upload', HTMLInputElement);
    chooser.addEventListener('change', async () => {
      const upload = chooser.files[0];
      chooser.value = '';
      if (!upload) return;
      if (upload.size > MAX_SOURCE) {
        showError(error, `${upload.name}: ${upload.size} bytes; a file may have at most ${MAX_SOURCE / 1024} KB.`);
        return;
      }
      showError(error, null);
      this.replace(await upload.text());
    });
  }

  source() {
    return this.view.state.doc.toString();
  }

  replace(text) {
    this.view.dispatch({ changes: { from: 0, to: this.view.state.doc.length, insert: text } });
  }

  edited() {
    try {
      localStorage.setItem(this.key, this.source());
      this.saved.textContent = 'Saved in this browser.';
    } catch (error) {
      this.saved.textContent = `Not saved in this browser (${error.message}): download your file to keep it.`;
    }
    this.onEdit(this.source());
  }
}
