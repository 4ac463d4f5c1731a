// The 3D replay written by `quack run --html` on a 3D scene: opened from a file in headless
// chromium (WebGL through its software renderer), it draws non-blank frames, makes no
// network request and logs no error; the scrub slider shows the chosen frame, play and
// pause work, dragging orbits the camera and the wheel zooms.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { launch, snapshot, webglColourCount, sleep, QUACK_BIN } from './helpers.mjs';

const ROOT = path.resolve(path.dirname(new URL(import.meta.url).pathname), '../..');
let chrome;
let page;
const errors = [];
const requests = [];
let dir;

before(async () => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'quack-replay3-'));
  const html = path.join(dir, 'ramp.html');
  execFileSync(QUACK_BIN, ['run', path.join(ROOT, 'scenes/ramp-3d.json'), '--steps', '180', '--quiet',
    '--out', path.join(dir, 'state.json'), '--html', html], { stdio: 'pipe' });
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

const replay = () => page.evaluate(() => ({ frame: window.quackReplay.frame, playing: window.quackReplay.playing,
  error: window.quackReplay.error, camera: window.quackReplay.camera }));

test('draws a non-blank frame with WebGL, with no errors and no network', async () => {
  await sleep(300);
  assert.equal((await replay()).error, undefined, 'the page found no WebGL');
  assert.ok(await webglColourCount(page, 'view') > 20, 'the replay canvas is blank');
  assert.deepEqual(errors, []);
  assert.deepEqual(requests, []);
});

test('plays, and the pause button stops it', async () => {
  const a = await replay();
  await sleep(400);
  const b = await replay();
  assert.equal(b.playing, true);
  assert.notEqual(b.frame, a.frame);
  await page.click('#play');
  assert.equal((await replay()).playing, false);
  const f = (await replay()).frame;
  const pic = await snapshot(page, 'view');
  await sleep(300);
  assert.equal((await replay()).frame, f);
  assert.equal(await snapshot(page, 'view'), pic, 'picture changed while paused');
});

test('the scrub slider shows the chosen frame', async () => {
  const scrub = (k) => page.$eval('#scrub', (s, v) => { s.value = String(v); s.dispatchEvent(new Event('input')); }, k);
  await scrub(0);
  assert.equal((await replay()).frame, 0);
  const first = await snapshot(page, 'view');
  const last = await page.evaluate(() => window.quackReplay.frameCount - 1);
  await scrub(last);
  assert.equal((await replay()).frame, last);
  assert.notEqual(await snapshot(page, 'view'), first, 'the balls did not move between frames');
  assert.match(await page.textContent('#clock'), /t = 3\.000 s/);
  await scrub(0);
  assert.equal(await snapshot(page, 'view'), first, 'frame 0 drew differently the second time');
});

test('dragging orbits the camera and the wheel zooms', async () => {
  const box = await page.$eval('#view', (c) => { const r = c.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; });
  const [x, y] = [box[0] + box[2] / 2, box[1] + box[3] / 2];
  const before = await replay();
  const pic = await snapshot(page, 'view');
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x + 120, y + 40, { steps: 5 });
  await page.mouse.up();
  const orbited = await replay();
  assert.ok(orbited.camera.yaw < before.camera.yaw - 0.5, 'the drag did not turn the camera');
  assert.ok(orbited.camera.pitch > before.camera.pitch, 'the drag did not tilt the camera');
  assert.notEqual(await snapshot(page, 'view'), pic);
  await page.mouse.move(x, y);
  await page.mouse.wheel(0, -300);
  await sleep(100);
  assert.ok((await replay()).camera.distance < orbited.camera.distance, 'the wheel did not zoom in');
  assert.ok(await webglColourCount(page, 'view') > 20);
  assert.deepEqual(errors, []);
});
