// Shared by the browser tests: a static server over the staged site, headless Debian
// chromium through playwright-core, and a page that records console errors.
import http from 'node:http';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

export const SITE = process.env.QUACK_WEB_SITE ?? path.resolve('../build/web-site');
export const QUACK_BIN = process.env.QUACK_BIN ?? path.resolve('../build/web-native/apps/quack/quack');

const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm',
  '.json': 'application/json' };

/** Serves SITE on a free localhost port; returns {url, close}. */
export async function serve() {
  const server = http.createServer((req, res) => {
    const rel = decodeURIComponent(new URL(req.url, 'http://x').pathname).replace(/^\/+/, '') || 'index.html';
    const file = path.join(SITE, rel);
    if (!file.startsWith(SITE) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
      res.writeHead(404); res.end('not found'); return;
    }
    res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] ?? 'application/octet-stream' });
    fs.createReadStream(file).pipe(res);
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  return { url: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((r) => server.close(r)) };
}

/** Headless chromium with the flags these machines need and a fresh profile (a context). */
export async function launch() {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'quack-chromium-'));
  // playwright passes the fresh profile as --user-data-dir itself.
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.QUACK_CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    viewport: { width: 1200, height: 900 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  return {
    browser,
    close: async () => { await browser.close(); fs.rmSync(profile, { recursive: true, force: true }); },
  };
}

/** Opens `url` and records console errors, page errors and failed requests in `errors`,
 * and the address of every request the page makes in `requests`. */
export async function open(browser, url) {
  const page = await browser.newPage();
  const errors = [];
  const requests = [];
  page.on('request', (r) => requests.push(r.url()));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`); });
  await page.goto(url);
  await page.waitForFunction(() => document.getElementById('status')?.textContent === 'ready',
    null, { timeout: 30000 });
  return { page, errors, requests };
}

/** A picture of a canvas, for comparing frames. */
export function snapshot(page, id) {
  return page.evaluate((i) => document.getElementById(i).toDataURL(), id);
}

/** How many distinct colours a canvas holds (1 for a blank one). */
export function colourCount(page, id) {
  return page.evaluate((i) => {
    const c = document.getElementById(i);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let k = 0; k < d.length; k += 4 * 7) seen.add((d[k] << 16) | (d[k + 1] << 8) | d[k + 2]);
    return seen.size;
  }, id);
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** How many distinct colours a WebGL canvas holds (1 for a blank one): copied onto a 2D
 * canvas first (the page renders with preserveDrawingBuffer, so the picture is kept). */
export function webglColourCount(page, id) {
  return page.evaluate((i) => {
    const src = document.getElementById(i);
    const c = document.createElement('canvas');
    c.width = src.width;
    c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let k = 0; k < d.length; k += 4 * 7) seen.add((d[k] << 16) | (d[k + 1] << 8) | d[k + 2]);
    return seen.size;
  }, id);
}
