// Page 1 (index.html): loads cleanly, draws, pauses and resumes on a click, the arrow keys
// change the time scale, and a key steps through GJK and EPA one iteration at a time.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { serve, launch, open, snapshot, colourCount, sleep } from './helpers.mjs';

let server;
let chrome;
let page;
let errors;

before(async () => {
  server = await serve();
  chrome = await launch();
  ({ page, errors } = await open(chrome.browser, `${server.url}/index.html`));
});

after(async () => {
  await chrome?.close();
  await server?.close();
});

const demoState = () => page.evaluate(() => window.quackDemo.state());

test('loads with no console errors', async () => {
  await sleep(300);
  assert.deepEqual(errors, []);
});

test('both canvases are drawn (not blank)', async () => {
  assert.ok(await colourCount(page, 'scene') > 10, 'scene canvas is blank');
  assert.ok(await colourCount(page, 'minkowski') > 10, 'Minkowski canvas is blank');
  const distance = await page.textContent('#distance');
  assert.match(distance, /^[0-9.e-]+$/);
});

test('the picture moves while running', async () => {
  assert.equal((await demoState()).paused, false);
  const a = await snapshot(page, 'scene');
  await sleep(300);
  assert.notEqual(await snapshot(page, 'scene'), a);
});

test('a click pauses (the picture stops changing) and a second click resumes', async () => {
  // Click an empty corner of the scene (a click that does not drag a shape).
  await page.click('#scene', { position: { x: 15, y: 15 } });
  assert.equal((await demoState()).paused, true);
  await sleep(100);
  const a = await snapshot(page, 'scene');
  const m = await snapshot(page, 'minkowski');
  const t = (await demoState()).t;
  await sleep(400);
  assert.equal(await snapshot(page, 'scene'), a, 'scene changed while paused');
  assert.equal(await snapshot(page, 'minkowski'), m, 'Minkowski view changed while paused');
  assert.equal((await demoState()).t, t);
  assert.equal(await page.textContent('#run-state'), 'paused');

  await page.click('#scene', { position: { x: 15, y: 15 } });
  assert.equal((await demoState()).paused, false);
  await sleep(300);
  assert.notEqual(await snapshot(page, 'scene'), a, 'scene did not move after resuming');
});

test('the arrow keys change the time scale, down to reversed time', async () => {
  assert.equal((await demoState()).timeScale, 1);
  await page.keyboard.press('ArrowRight');
  assert.equal((await demoState()).timeScale, 2);
  assert.equal(await page.textContent('#time-scale'), '2×');
  await page.keyboard.press('ArrowLeft');
  await page.keyboard.press('ArrowLeft');
  assert.equal((await demoState()).timeScale, 0.5);
  for (let i = 0; i < 5; ++i) await page.keyboard.press('ArrowLeft');
  assert.ok((await demoState()).timeScale < 0, 'time does not run backwards');
  // Time really runs backwards.
  const t0 = (await demoState()).t;
  await sleep(300);
  assert.ok((await demoState()).t < t0);
  while ((await demoState()).timeScale !== 1) await page.keyboard.press('ArrowRight');
});

test('dragging a shape moves it without pausing; the wheel turns it', async () => {
  await page.evaluate(() => window.quackDemo.setPoses({ pos: [-1.3, 0], angle: 0 }, { pos: [1.4, 0.2], angle: 0.5 }));
  const [x, y] = await page.evaluate(() => window.quackDemo.toCanvas(window.quackDemo.poses()[1].pos));
  const box = await page.locator('#scene').boundingBox();
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x - 35, box.y + y + 14, { steps: 5 });
  await page.mouse.up();
  const [, b] = await page.evaluate(() => window.quackDemo.poses());
  assert.ok(Math.abs(b.pos[0] - 0.9) < 0.05 && Math.abs(b.pos[1]) < 0.05, `B is at ${b.pos}`);
  assert.equal((await demoState()).paused, false, 'a drag must not toggle the pause');
  await page.mouse.move(box.x + x - 35, box.y + y + 14);
  await page.mouse.wheel(0, 100);
  await page.waitForFunction(() => window.quackDemo.poses()[1].angle > 0.52);
});

test('S steps one GJK iteration at a time, then EPA, and Esc shows the answer', async () => {
  // Two overlapping boxes, so that both GJK and EPA run.
  await page.evaluate(() => {
    window.quackDemo.setShapes({ type: 'box', half: [1, 1] }, { type: 'box', half: [0.8, 0.5] });
    window.quackDemo.setPoses({ pos: [0, 0], angle: 0.1 }, { pos: [1.2, 0.4], angle: 0.5 });
  });
  const result = await page.evaluate(() => window.quackDemo.result());
  assert.equal(result.penetration.overlap, true);
  assert.ok(result.epa.ran, 'EPA did not run');
  await page.keyboard.press('s');
  assert.equal((await demoState()).paused, true);
  assert.match(await page.textContent('#stepping'), /^GJK iteration 1 of /);
  const first = await snapshot(page, 'minkowski');
  await page.keyboard.press('s');
  assert.match(await page.textContent('#stepping'), /^GJK iteration 2 of /);
  assert.notEqual(await snapshot(page, 'minkowski'), first);
  for (let i = 0; i < result.gjk.steps.length - 1; ++i) await page.keyboard.press('s');
  assert.match(await page.textContent('#stepping'), /^EPA iteration 1 of /);
  await page.keyboard.press(',');
  assert.match(await page.textContent('#stepping'), /^GJK iteration /);
  await page.keyboard.press('Escape');
  assert.equal(await page.textContent('#stepping'), 'final answer');
  assert.equal(await page.textContent('#trace-check'), 'agrees');
  assert.deepEqual(errors, []);
});
