// The HTML replay written by `quack run --html`: opened from a file in headless
// chromium, it draws non-blank frames, plays, pauses on its button and resumes, scrubs,
// makes no network request and logs no error; sleeping bodies are drawn faded.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { launch, snapshot, colourCount, sleep, QUACK_BIN } from './helpers.mjs';

const ROOT = path.resolve(path.dirname(new URL(import.meta.url).pathname), '../..');
let chrome;
let page;
const errors = [];
const requests = [];
let dir;

before(async () => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'quack-replay-'));
  const html = path.join(dir, 'rain.html');
  execFileSync(QUACK_BIN, ['run', path.join(ROOT, 'scenes/rain.json'), '--steps', '240', '--quiet',
    '--out', path.join(dir, 'state.json'), '--html', html, '--html-boxes'], { stdio: 'pipe' });
  chrome = await launch();
  page = await chrome.browser.newPage();
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('request', (r) => { if (!r.url().startsWith('file:')) requests.push(r.url()); });
  await page.goto(pathToFileURL(html).href);
  await page.waitForFunction(() => window.quackReplay && window.quackReplay.frameCount > 1, null, { timeout: 30000 });
});

after(async () => {
  await chrome?.close();
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

const replay = () => page.evaluate(() => ({ frame: window.quackReplay.frame, playing: window.quackReplay.playing }));

test('draws a non-blank frame, with no errors and no network', async () => {
  await sleep(300);
  assert.ok(await colourCount(page, 'view') > 5, 'the replay canvas is blank');
  assert.deepEqual(errors, []);
  assert.deepEqual(requests, []);
});

test('plays: the frame advances and the picture changes', async () => {
  const a = await replay();
  const pic = await snapshot(page, 'view');
  await sleep(600);
  const b = await replay();
  assert.equal(b.playing, true);
  assert.notEqual(b.frame, a.frame);
  assert.notEqual(await snapshot(page, 'view'), pic);
});

test('the pause button stops it and a second press resumes', async () => {
  await page.click('#play');
  assert.equal((await replay()).playing, false);
  await sleep(100);
  const f = (await replay()).frame;
  const pic = await snapshot(page, 'view');
  await sleep(500);
  assert.equal((await replay()).frame, f);
  assert.equal(await snapshot(page, 'view'), pic, 'picture changed while paused');
  await page.click('#play');
  await sleep(500);
  assert.notEqual((await replay()).frame, f);
});

test('scrubbing shows the chosen frame; broad-phase boxes and zoom redraw', async () => {
  await page.click('#play');  // pause
  await page.$eval('#scrub', (s) => { s.value = '3'; s.dispatchEvent(new Event('input')); });
  assert.equal((await replay()).frame, 3);
  const plain = await snapshot(page, 'view');
  await page.check('#boxes');
  assert.notEqual(await snapshot(page, 'view'), plain, 'boxes did not draw');
  await page.click('#zoomIn');
  assert.ok(await colourCount(page, 'view') > 5);
  assert.deepEqual(errors, []);
});

// Issue 16: a 20-row pyramid sleeps within a second of simulated time. At the first frame
// every box is awake and drawn opaque; at the last every box sleeps and is drawn at the
// page's sleeping opacity, which the pixel at a box's centre shows.
test('sleeping bodies are drawn faded', async () => {
  const html = path.join(dir, 'pyramid.html');
  execFileSync(QUACK_BIN, ['run', path.join(ROOT, 'scenes/pyramid.json'), '--steps', '180', '--quiet',
    '--out', path.join(dir, 'pyramid.json'), '--html', html], { stdio: 'pipe' });
  const p = await chrome.browser.newPage();
  const pageErrors = [];
  p.on('pageerror', (e) => pageErrors.push(`page error: ${e.message}`));
  p.on('console', (m) => { if (m.type() === 'error') pageErrors.push(`console: ${m.text()}`); });
  await p.goto(pathToFileURL(html).href);
  await p.waitForFunction(() => window.quackReplay && window.quackReplay.frameCount > 1, null, { timeout: 30000 });
  await p.uncheck('#contacts');  // contact normals could cross a box's centre
  const last = await p.evaluate(() => window.quackReplay.frameCount - 1);
  assert.deepEqual(await p.evaluate(() => window.quackReplay.asleep(0)), []);
  const asleep = await p.evaluate((k) => window.quackReplay.asleep(k), last);
  assert.equal(asleep.length, 210, 'the pyramid did not sleep');
  // How opaque the fill at moving body b's centre is drawn in frame k, from the blue channel:
  // the dynamic fill #f2b45a over the background #fbfaf7.
  const opacity = (k, b) => p.evaluate(([frame, body]) => {
    window.quackReplay.seek(frame);
    const [x, y] = window.quackReplay.screenOf(frame, body);
    const d = document.getElementById('view').getContext('2d').getImageData(Math.round(x), Math.round(y), 1, 1).data;
    return (0xf7 - d[2]) / (0xf7 - 0x5a);
  }, [k, b]);
  const alpha = await p.evaluate(() => window.quackReplay.sleepingAlpha);
  assert.ok(alpha < 0.6);
  for (const b of [0, 105, 209]) {
    const awake = await opacity(0, b), sleeping = await opacity(last, b);
    assert.ok(Math.abs(awake - 1) < 0.05, `box ${b} awake drawn at opacity ${awake}`);
    assert.ok(Math.abs(sleeping - alpha) < 0.05, `box ${b} asleep drawn at opacity ${sleeping}, not ${alpha}`);
  }
  assert.equal(await p.textContent('#awake'), 'awake 0 of 210');
  await p.evaluate(() => window.quackReplay.seek(0));
  assert.equal(await p.textContent('#awake'), 'awake 210 of 210');
  assert.deepEqual(pageErrors, []);
  await p.close();
});
