// Typesets the formulas of a page: \( inline \) and $$ display $$.
import renderMathInElement from 'katex/contrib/auto-render';

export function renderMath(root = document.body) {
  renderMathInElement(root, {
    delimiters: [
      { left: '$$', right: '$$', display: true },
      { left: '\\(', right: '\\)', display: false },
    ],
    throwOnError: false,
  });
}
