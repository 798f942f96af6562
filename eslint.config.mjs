// The linter of the browser's scripts (static/) and the exercises' (labs/src/exercises/*/web/):
// ESLint's recommended rules, with the globals each kind of script has. scripts/test runs
// it from here with the packages of static/ (`static/node_modules/.bin/eslint`).
import { createRequire } from 'node:module';

const require = createRequire(new URL('static/package.json', import.meta.url));
const js = require('@eslint/js');
const globals = require('globals');

export default [
  { ignores: ['**/node_modules/', 'static/src/types/', 'target/', 'tests/'] },
  {
    files: ['static/**/*.js', 'static/**/*.mjs', 'labs/src/exercises/*/web/*.js'],
    ...js.configs.recommended,
    languageOptions: { ecmaVersion: 2022, sourceType: 'module', globals: { ...globals.browser } },
  },
  {
    // The harness and the loops run in the browser's worker and in the server's sandbox
    // alike: classic scripts, with the harness's global.
    files: ['static/src/harness.js', 'labs/src/exercises/*/web/loop.js'],
    languageOptions: { sourceType: 'script', globals: { estlabHarness: 'readonly' } },
  },
  {
    // A starter file declares the functions the student writes, which the harness calls.
    files: ['labs/src/exercises/*/web/starter.js'],
    languageOptions: { sourceType: 'script' },
    rules: { 'no-unused-vars': 'off' },
  },
  {
    files: ['static/build.mjs', 'eslint.config.mjs'],
    languageOptions: { globals: { ...globals.node } },
  },
];
