// Markdown with math, as question sets and students' answers are written: markdown-it
// without raw HTML (escaped, never run) and its links checked, and `$...$` and
// `$$...$$` typeset by KaTeX through markdown-it-texmath (no size beyond 10 em, so that a
// classmate's `\rule` cannot cover a reviewer's page).
import katex from 'katex';
import MarkdownIt from 'markdown-it';
import texmath from 'markdown-it-texmath';
import { element } from './results/render.js';

const markdown = new MarkdownIt({ html: false, linkify: false, typographer: false })
  .use(texmath, { engine: katex, delimiters: 'dollars', katexOptions: { throwOnError: false, trust: false, maxSize: 10, maxExpand: 1000 } });

/**
 * `text` as HTML, safe to insert: raw HTML is escaped, and KaTeX builds the formulas.
 *
 * @param {string} text
 * @returns {string}
 */
export function toHtml(text) {
  return markdown.render(text);
}

/**
 * Fills `node` with `text` rendered.
 *
 * @param {HTMLElement} node
 * @param {string} text
 */
export function renderInto(node, text) {
  node.innerHTML = toHtml(text);
}

/**
 * A block of Markdown: a `div.markdown` of `className` holding `text` rendered.
 *
 * @param {string} className
 * @param {string} text
 */
export function markdownBlock(className, text) {
  const node = element('div', `markdown ${className}`);
  renderInto(node, text);
  return node;
}
