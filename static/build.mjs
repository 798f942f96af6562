// Bundles the page scripts (each page's of static/pages.json) and the styles with esbuild
// into content-hashed files, with what every exercise's folder (labs/src/exercises/*/web/)
// holds for the browser: its view of a run for the workbench, and its loop for the Web
// Worker that runs students' code as a classic script of its own. Writes manifest.json
// (the style, each page's script and what it preloads, the worker) for the server, and
// precompresses every text asset with brotli and gzip so that the server can send the
// smaller one.
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

// Every exercise's folder, by its name (`labs::Exercise::folder`), with the file of it
// that `name` is (`workbench.js`, `loop.js`) where it has one.
const exercises = new URL('../labs/src/exercises/', import.meta.url).pathname;
function exerciseFiles(name) {
  return readdirSync(exercises, { withFileTypes: true })
    .filter((entry) => entry.isDirectory())
    .map((entry) => [entry.name, join(exercises, entry.name, 'web', name)])
    .filter(([, file]) => existsSync(file))
    .sort(([a], [b]) => a.localeCompare(b));
}

/**
 * `estlab:workbenches`, the workbench's way to every exercise's view of its runs: a
 * function per folder that loads the folder's `web/workbench.js` (a chunk of its own).
 */
const workbenches = {
  name: 'workbenches',
  setup(build) {
    build.onResolve({ filter: /^estlab:workbenches$/ }, (args) => ({ path: args.path, namespace: 'workbenches' }));
    build.onLoad({ filter: /.*/, namespace: 'workbenches' }, () => ({
      contents: 'export default {\n' + exerciseFiles('workbench.js')
        .map(([folder, file]) => `  ${JSON.stringify(folder)}: () => import(${JSON.stringify(file)}),\n`)
        .join('') + '};\n',
      resolveDir: exercises,
    }));
  },
};

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
  // The exercises' scripts name the site's modules as `estlab/...` (`static/src/...`).
  alias: { 'estlab-wasm': pkg, estlab: new URL('src', import.meta.url).pathname },
  nodePaths: [new URL('node_modules', import.meta.url).pathname],
  plugins: [workbenches],
  loader: { '.wasm': 'file', '.woff2': 'file', '.woff': 'file', '.ttf': 'file' },
  metafile: true,
  logLevel: 'warning',
});

// A classic script, so that it starts in every browser, with the harness and every
// exercise's loop (`web/loop.js`) the very files the server's sandbox runs.
const loops = exerciseFiles('loop.js').map(([, file]) => file);
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
