// What the end-to-end tests share: the real estlab binary, started on a free loopback
// port, the estlab command line, and headless Chromium (Debian's) driven by Playwright.
import { spawn, execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const estlabBinary = process.env.ESTLAB_BIN ?? join(root, 'target', 'debug', 'estlab');
export const staticDir = join(root, 'target', 'web', 'dist');
export const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';

/** The estlab command line: its standard output, or a thrown error with its stderr. */
export function estlab(...args) {
  return execFileSync(estlabBinary, args, { encoding: 'utf8', maxBuffer: 1 << 28 });
}

/** A fresh temporary directory. */
export function tempDir() {
  return mkdtempSync(join(tmpdir(), 'estlab-e2e-'));
}

/**
 * Starts `estlab serve` on a free port, its submissions in `dataDir` (a fresh directory
 * unless given); resolves to { url, dataDir, stop() }.
 */
export function startServer({ dataDir = tempDir(), args = [] } = {}) {
  if (!existsSync(estlabBinary)) throw new Error(`${estlabBinary} is not built (cargo build -p estlab)`);
  const child = spawn(estlabBinary, ['serve', '--addr', '127.0.0.1:0', '--static', staticDir, '--data', dataDir, ...args], {
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let stderr = '';
  child.stderr.on('data', (chunk) => { stderr += chunk; });
  return new Promise((resolve, reject) => {
    let stdout = '';
    child.stdout.on('data', (chunk) => {
      stdout += chunk;
      const match = stdout.match(/serving on (http:\/\/\S+)\//);
      if (match) {
        resolve({
          url: match[1],
          dataDir,
          process: child,
          stop: () => new Promise((done) => { child.once('exit', done); child.kill('SIGINT'); }),
        });
      }
    });
    child.once('exit', (code) => reject(new Error(`estlab serve exited with ${code}: ${stderr}`)));
  });
}

/** Headless Chromium with the flags this machine needs. */
export function launchBrowser() {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: [
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
  });
}

/**
 * A new page that records every console error and uncaught exception into
 * `page.problems`, and has opened `url` and waited until its script says it is ready.
 */
export async function openPage(browser, url) {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 }, acceptDownloads: true });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') page.problems.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught: ${error.message}`));
  page.on('requestfailed', (request) => page.problems.push(`request failed: ${request.url()}`));
  await page.goto(url);
  try {
    await page.waitForSelector('body[data-ready=true]', { timeout: 20000 });
  } catch (error) {
    throw new Error(`${url} never got ready: ${error.message}\nwhat went wrong on the page: ${page.problems.join('\n')}`);
  }
  return page;
}
