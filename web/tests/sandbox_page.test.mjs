// Page 2 (sandbox.html): the world runs, a click drops a shape, shapes collide (contacts
// and events appear), the broad-phase boxes are drawn, pause stops the picture, every
// broad phase works, and resting bodies fall asleep, are drawn faded and wake on a click.
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
  ({ page, errors } = await open(chrome.browser, `${server.url}/sandbox.html`));
});

after(async () => {
  await chrome?.close();
  await server?.close();
});

const sandbox = () => page.evaluate(() => window.quackSandbox.state());

test('loads with no console errors and draws the world', async () => {
  await sleep(300);
  assert.deepEqual(errors, []);
  assert.ok(await colourCount(page, 'world') > 10, 'world canvas is blank');
});

test('a click drops a shape, and shapes collide: contacts and begin events', async () => {
  const before = (await sandbox()).world.bodies;
  await page.click('#world', { position: { x: 380, y: 80 } });
  assert.equal((await sandbox()).world.bodies, before + 1);
  // Let the dropped shapes land (2 s of simulated time at most).
  await page.waitForFunction(() => {
    const s = window.quackSandbox.state();
    return s.counts[0] > 0 && s.world.contacts.length > 0;
  }, null, { timeout: 20000 });
  const s = await sandbox();
  assert.equal(s.world.fatBoxes.length, s.world.broadPhase.proxies);
  assert.equal(s.world.broadPhase.kind, 'tree');
  assert.ok(s.world.broadPhase.height >= 1);
  // The tree's hierarchy: a binary tree of n leaves has n - 1 internal nodes.
  assert.equal(s.world.treeBoxes.length, s.world.broadPhase.proxies - 1);
  await page.check('#show-tree');
  await page.keyboard.press(' ');  // pause, so only the tree drawing can change the picture
  await sleep(100);
  const withTree = await snapshot(page, 'world');
  await page.uncheck('#show-tree');
  await sleep(100);
  assert.notEqual(await snapshot(page, 'world'), withTree, 'the tree nodes did not draw');
  await page.keyboard.press(' ');
  assert.notEqual(await page.textContent('#events'), '');
});

// One shape vocabulary at every edge: the concave preset becomes one body with a shape per
// convex piece (the CLI and Python split it the same way), and it lands like any other.
test('a concave shape drops as one body of several convex pieces', async () => {
  const before = await sandbox();
  const index = await page.evaluate(() => window.quackSandbox.drop('L (concave)', [0, 3], 0));
  assert.equal(typeof index, 'number');
  const after = await sandbox();
  assert.equal(after.world.bodies, before.world.bodies + 1);
  const pieces = after.world.shapes.filter((s) => s.index >= index);
  assert.ok(pieces.length >= 2, `the L came as ${pieces.length} piece(s)`);
  // All its pieces share the body's pose.
  for (const s of pieces) assert.deepEqual(s.pos, pieces[0].pos);
  assert.deepEqual(errors, []);
});

test('pause stops the picture; resume goes on', async () => {
  await page.keyboard.press(' ');
  assert.equal((await sandbox()).paused, true);
  await sleep(100);
  const a = await snapshot(page, 'world');
  const steps = (await sandbox()).world.steps;
  await sleep(300);
  assert.equal(await snapshot(page, 'world'), a);
  assert.equal((await sandbox()).world.steps, steps);
  await page.keyboard.press(' ');
  await sleep(300);
  assert.ok((await sandbox()).world.steps > steps);
});

test('every broad phase runs the same scene', async () => {
  for (const kind of ['quadtree', 'sap', 'hash', 'brute', 'tree']) {
    await page.selectOption('#broadphase', kind);
    await sleep(250);
    const s = await sandbox();
    assert.equal(s.world.broadPhase.kind, kind);
    assert.ok(s.world.steps > 0);
    assert.equal(s.world.fatBoxes.length, s.world.broadPhase.proxies);
  }
  assert.deepEqual(errors, []);
});

// The colour drawn at canvas pixel (x, y) and the page's background, as [r, g, b].
const pixel = (x, y) => page.evaluate(([px, py]) => {
  const d = document.getElementById('world').getContext('2d').getImageData(Math.round(px), Math.round(py), 1, 1).data;
  return [d[0], d[1], d[2]];
}, [x, y]);
const BACKGROUND = [0xfb, 0xfa, 0xf7];
const fromBackground = (c) => Math.hypot(c[0] - BACKGROUND[0], c[1] - BACKGROUND[1], c[2] - BACKGROUND[2]);

test('resting boxes fall asleep and are drawn faded; a click wakes the one it hits', async () => {
  await page.click('#reset');
  // Paused, so that only the steps the test asks for run.
  await page.evaluate(() => { if (!window.quackSandbox.state().paused) window.quackSandbox.togglePause(); });
  assert.equal((await sandbox()).paused, true);
  await page.evaluate(() => window.quackSandbox.clear());
  // Three boxes just above the ground (top at y = -3.55), apart: three islands.
  const xs = [-3.5, 0.5, 3.5];
  const boxes = await page.evaluate((at) => at.map((x) => window.quackSandbox.drop('box', [x, -2.9], 0)), xs);
  const shapeOf = (s, index) => s.world.shapes.find((x) => x.index === index);
  let s = await sandbox();
  assert.deepEqual(boxes.map((b) => shapeOf(s, b).awake), [true, true, true]);
  assert.equal(s.world.awakeBodies, 3);
  // They settle and sleep within two seconds (kTimeToSleep is half a second of rest).
  await page.evaluate(() => window.quackSandbox.run(120));
  s = await sandbox();
  assert.deepEqual(boxes.map((b) => shapeOf(s, b).awake), [false, false, false]);
  assert.equal(s.world.awakeBodies, 0);
  assert.equal(await page.textContent('#awake'), '0 / 3');
  const bodies = s.world.bodies;
  // Faded: the middle box's centre is drawn much closer to the background than when awake.
  const middle = shapeOf(s, boxes[1]);
  const [cx, cy] = await page.evaluate((p) => window.quackSandbox.toCanvas(p), middle.pos);
  await sleep(100);
  const asleepColour = await pixel(cx, cy);
  // A click at the middle box's centre (playwright's position is from the border's corner).
  const border = await page.$eval('#world', (c) => [c.clientLeft, c.clientTop]);
  await page.click('#world', { position: { x: cx + border[0], y: cy + border[1] } });
  s = await sandbox();
  assert.equal(s.world.bodies, bodies, 'the click dropped a shape instead of waking the box');
  assert.deepEqual(boxes.map((b) => shapeOf(s, b).awake), [false, true, false]);
  assert.equal(s.world.awakeBodies, 1);
  assert.match(await page.textContent('#events'), new RegExp(`woke  ${boxes[1]}$`));
  await sleep(100);
  const awakeColour = await pixel(cx, cy);
  assert.ok(fromBackground(asleepColour) < 0.6 * fromBackground(awakeColour),
    `asleep ${asleepColour} is not fainter than awake ${awakeColour}`);
  // A click on empty space still drops a shape.
  await page.click('#world', { position: { x: 380, y: 80 } });
  assert.equal((await sandbox()).world.bodies, bodies + 1);
  await page.evaluate(() => window.quackSandbox.togglePause());
  assert.deepEqual(errors, []);
});
