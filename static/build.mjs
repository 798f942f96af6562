// Bundles the page scripts (each page's of static/pages.json) and the styles with esbuild into content-hashed files, and the
// Web Worker that runs students' code as a classic script of its own; writes manifest.json
// (the style, each page's script and what it preloads, the worker) for the server, and precompresses every text
// asset with brotli and gzip so that the server can send the smaller one.
//
//   node build.mjs PKG_DIR OUT_DIR
import * as esbuild from 'esbuild';
import { existsSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { join, relative } from 'node:path';
import { brotliCompressSync, constants, gzipSync } from 'node:zlib';

const [pkg, out] = process.argv.slice(2);
// The scripts of the site's pages, from the registry the server reads too, and the
// workbench's, which every exercise's workbench page runs.
const registry = JSON.parse(readFileSync(new URL('pages.json', import.meta.url), 'utf8'));
const pages = [...new Set([...registry.pages.map((page) => page.script), 'code'])];

rmSync(out, { recursive: true, force: true });
const result = await esbuild.build({
  entryPoints: { ...Object.fromEntries(pages.map((page) => [page, `src/pages/${page}.js`])), style: 'src/style.css' },
  bundle: true,
  splitting: true,
  format: 'esm',
  target: 'es2022',
  minify: process.env.ESTLAB_MINIFY !== '0',
  sourcemap: false,
  legalComments: 'linked',
  outdir: out,
  entryNames: '[name]-[hash]',
  chunkNames: 'chunks/[name]-[hash]',
  assetNames: 'assets/[name]-[hash]',
  publicPath: '/static/',
  alias: { 'estlab-wasm': pkg },
  loader: { '.wasm': 'file', '.woff2': 'file', '.woff': 'file', '.ttf': 'file' },
  metafile: true,
  logLevel: 'warning',
});

// A classic script, so that it starts in every browser, with the harness and every
// exercise's loop (`labs/src/exercises/*/web/loop.js`) the very files the server's
// sandbox runs.
const exercises = new URL('../labs/src/exercises/', import.meta.url);
const loops = readdirSync(exercises, { withFileTypes: true })
  .filter((entry) => entry.isDirectory())
  .map((entry) => join(exercises.pathname, entry.name, 'web', 'loop.js'))
  .filter((file) => existsSync(file))
  .sort();
const worker = await esbuild.build({
  stdin: {
    contents: ['./src/sandbox/worker.js', ...loops].map((file) => `import ${JSON.stringify(file)};`).join('\n'),
    resolveDir: new URL('.', import.meta.url).pathname,
    sourcefile: 'student-worker.js',
  },
  bundle: true,
  format: 'iife',
  target: 'es2022',
  minify: process.env.ESTLAB_MINIFY !== '0',
  outdir: out,
  // The server gives the worker its own content security policy by this name
  // (server/src/web/assets.rs, WORKER_PREFIX).
  entryNames: 'student-worker-[hash]',
  metafile: true,
  logLevel: 'warning',
});

/**
 * What a page's script needs before it can draw, for the page to ask for at once instead
 * of after its script has arrived and run: the chunks it imports (`module`, for
 * `<link rel=modulepreload>`) and the wasm module its code fetches (`wasm`, for
 * `<link rel=preload as=fetch>`), found by following the entry's static imports.
 */
function preloads(entry) {
  const found = [];
  const seen = new Set();
  const walk = (file) => {
    for (const { path, kind } of result.metafile.outputs[file].imports) {
      if (seen.has(path)) continue;
      seen.add(path);
      if (kind === 'import-statement') {
        found.push({ kind: 'module', path: relative(out, path) });
        walk(path);
      } else if (kind === 'file-loader' && path.endsWith('.wasm')) {
        found.push({ kind: 'wasm', path: relative(out, path) });
      }
    }
  };
  walk(entry);
  return found;
}

const manifest = { style: null, worker: null, scripts: {}, preloads: {} };
manifest.worker = relative(out, Object.keys(worker.metafile.outputs).find((file) => file.endsWith('.js')));
for (const [file, output] of Object.entries(result.metafile.outputs)) {
  const page = pages.find((p) => output.entryPoint === `src/pages/${p}.js`);
  if (page) {
    manifest.scripts[page] = relative(out, file);
    manifest.preloads[page] = preloads(file);
  }
  if (output.entryPoint === 'src/style.css') manifest.style = relative(out, file);
}
writeFileSync(join(out, 'manifest.json'), JSON.stringify(manifest, null, 2));

const compressible = /\.(js|css|wasm|svg|json|ttf|txt)$/;
function compress(dir) {
  for (const name of readdirSync(dir)) {
    const path = join(dir, name);
    if (statSync(path).isDirectory()) {
      compress(path);
    } else if (compressible.test(name)) {
      const data = readFileSync(path);
      writeFileSync(`${path}.br`, brotliCompressSync(data, { params: { [constants.BROTLI_PARAM_QUALITY]: 11 } }));
      writeFileSync(`${path}.gz`, gzipSync(data, { level: 9 }));
    }
  }
}
compress(out);
console.log(`built ${Object.keys(manifest.scripts).length} pages into ${out}`);
