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
  markScrolling(root);
}

/**
 * A displayed equation wider than its box scrolls sideways: such a box says so (the
 * class `scrolls` draws a shadow at each edge with more beyond it) and takes the
 * keyboard's focus, so that the arrow keys scroll it. Checked again as the box's width
 * changes (a phone turned, a window resized).
 */
function markScrolling(root) {
  const check = (box) => {
    const scrolls = box.scrollWidth > box.clientWidth + 1;
    box.classList.toggle('scrolls', scrolls);
    if (scrolls) {
      box.tabIndex = 0;
      box.setAttribute('role', 'group');
      box.setAttribute('aria-label', 'equation, scrolls sideways');
    } else {
      box.removeAttribute('tabindex');
      box.removeAttribute('role');
      box.removeAttribute('aria-label');
    }
  };
  const observer = new ResizeObserver((entries) => entries.forEach((entry) => check(entry.target)));
  const boxes = [...root.querySelectorAll('.katex-display')];
  for (const box of boxes) {
    check(box);
    observer.observe(box);
  }
  // The formulas' fonts arrive later and widen them within the same box.
  document.fonts.ready.then(() => boxes.forEach(check));
}
