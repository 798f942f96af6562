// The server over plain HTTP: pages, assets, content types, compression, cache headers.
import assert from 'node:assert/strict';
import { readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { startServer, staticDir } from './harness.mjs';

let server;
before(async () => { server = await startServer(); });
after(async () => { await server.stop(); });

const manifest = JSON.parse(readFileSync(join(staticDir, 'manifest.json'), 'utf8'));

test('every page is HTML that links its script and the style, and is revalidated', async () => {
  for (const [path, page] of [['/', 'home'], ['/car', 'car'], ['/ekf', 'ekf'], ['/ekf/code', 'code']]) {
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

test('an unknown path is a 404 page that says where the exercises are', async () => {
  const response = await fetch(`${server.url}/no/such/page`);
  assert.equal(response.status, 404);
  const html = await response.text();
  assert.match(html, /There is no page at <code>\/no\/such\/page<\/code>/);
});

test('assets have their content types, are compressed and cached for a year', async () => {
  const assets = [
    [manifest.scripts.ekf, 'text/javascript'],
    [manifest.style, 'text/css'],
  ];
  const wasm = readdirSync(join(staticDir, 'assets')).find((name) => /^estlab_wasm_bg-\w+\.wasm$/.test(name));
  assert.ok(wasm, 'the wasm module is among the assets');
  assets.push([`assets/${wasm}`, 'application/wasm']);
  for (const [file, type] of assets) {
    for (const [encoding, expected] of [['br', 'br'], ['gzip', 'gzip'], ['identity', null]]) {
      const response = await fetch(`${server.url}/static/${file}`, { headers: { 'accept-encoding': encoding } });
      assert.equal(response.status, 200, file);
      assert.equal(response.headers.get('content-type'), type, file);
      assert.equal(response.headers.get('content-encoding'), expected, `${file} with ${encoding}`);
      assert.equal(response.headers.get('cache-control'), 'public, max-age=31536000, immutable');
      await response.arrayBuffer();
    }
  }
  const missing = await fetch(`${server.url}/static/nothing-ABCDEF.js`);
  assert.equal(missing.status, 404);
  assert.equal(missing.headers.get('cache-control'), null, 'a missing asset is not cached');
});

test('the health check answers', async () => {
  const response = await fetch(`${server.url}/healthz`);
  assert.equal(await response.text(), 'ok');
});
