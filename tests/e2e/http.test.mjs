// The server over plain HTTP: pages, assets, content types, compression, cache headers.
import assert from 'node:assert/strict';
import { readFileSync, readdirSync } from 'node:fs';
import { get } from 'node:http';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { brotliDecompressSync, gunzipSync } from 'node:zlib';
import { bounded, startServer, staticDir } from './harness.mjs';

let server;
before(async () => { server = await startServer(); }, bounded);
after(async () => { await server.stop(); }, bounded);

/**
 * GETs `url` with `headers` and resolves to { status, headers, body }: the body as it came
 * over the wire (fetch would decode it), with nothing decompressed.
 */
function rawGet(url, headers) {
  return new Promise((resolve, reject) => {
    get(url, { headers }, (response) => {
      const chunks = [];
      response.on('data', (chunk) => chunks.push(chunk));
      response.on('end', () => resolve({ status: response.statusCode, headers: response.headers, body: Buffer.concat(chunks) }));
      response.on('error', reject);
    }).on('error', reject);
  });
}

const decode = { br: brotliDecompressSync, gzip: gunzipSync, identity: (bytes) => bytes };

const manifest = JSON.parse(readFileSync(join(staticDir, 'manifest.json'), 'utf8'));

test('every page is HTML that links its script and the style, and is revalidated', bounded, async () => {
  for (const [path, page] of [['/', 'home'], ['/car', 'car'], ['/ekf', 'ekf'], ['/ekf/code', 'code'], ['/odometry/code', 'code'], ['/fusion', 'fusion'], ['/fusion/code', 'code'], ['/mrclam', 'mrclam'], ['/mrclam/code', 'code']]) {
    const response = await fetch(server.url + path);
    assert.equal(response.status, 200, path);
    assert.equal(response.headers.get('content-type'), 'text/html; charset=utf-8');
    assert.equal(response.headers.get('cache-control'), 'no-cache');
    assert.match(response.headers.get('content-security-policy'), /script-src 'self' 'wasm-unsafe-eval'/);
    const html = await response.text();
    assert.ok(html.includes(`/static/${manifest.scripts[page]}`), `${path} links its script`);
    assert.ok(html.includes(`/static/${manifest.style}`), `${path} links the style`);
  }
});

test('an unknown path is a 404 page that says where the exercises are', bounded, async () => {
  const response = await fetch(`${server.url}/no/such/page`);
  assert.equal(response.status, 404);
  const html = await response.text();
  assert.match(html, /There is no page at <code>\/no\/such\/page<\/code>/);
});

test('assets have their content types, are compressed and cached for a year', bounded, async () => {
  const assets = [
    [manifest.scripts.ekf, 'text/javascript'],
    [manifest.style, 'text/css'],
  ];
  const wasm = readdirSync(join(staticDir, 'assets')).find((name) => /^estlab_wasm_bg-\w+\.wasm$/.test(name));
  assert.ok(wasm, 'the wasm module is among the assets');
  assets.push([`assets/${wasm}`, 'application/wasm']);
  for (const [file, type] of assets) {
    const onDisk = readFileSync(join(staticDir, file));
    for (const encoding of ['br', 'gzip', 'identity']) {
      const response = await rawGet(`${server.url}/static/${file}`, { 'accept-encoding': encoding });
      assert.equal(response.status, 200, file);
      assert.equal(response.headers['content-type'], type, file);
      assert.equal(response.headers['content-encoding'], encoding === 'identity' ? undefined : encoding, `${file} with ${encoding}`);
      assert.equal(response.headers['cache-control'], 'public, max-age=31536000, immutable');
      if (encoding !== 'identity') assert.ok(response.body.length < onDisk.length, `${file} as ${encoding} is smaller than the file`);
      assert.ok(decode[encoding](response.body).equals(onDisk), `${file} as ${encoding} is the served file, byte for byte`);
    }
  }
  const missing = await fetch(`${server.url}/static/nothing-ABCDEF.js`);
  assert.equal(missing.status, 404);
  assert.equal(missing.headers.get('cache-control'), null, 'a missing asset is not cached');
});

test('the health check answers', bounded, async () => {
  const response = await fetch(`${server.url}/healthz`);
  assert.equal(await response.text(), 'ok');
});
