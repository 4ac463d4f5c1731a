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

// ---- joints: dragging with a mouse joint, the chain, car and ragdoll drop-ins ----------

const pauseSandbox = () => page.evaluate(() => {
  if (!window.quackSandbox.state().paused) window.quackSandbox.togglePause();
});
const resumeSandbox = () => page.evaluate(() => {
  if (window.quackSandbox.state().paused) window.quackSandbox.togglePause();
});
const shapeAt = (s, index) => s.world.shapes.find((x) => x.index === index);
// Page coordinates of the world point p (the canvas's place, its border, then the view).
async function pagePoint(p) {
  const [cx, cy] = await page.evaluate((q) => window.quackSandbox.toCanvas(q), p);
  const box = await page.locator('#world').boundingBox();
  const border = await page.$eval('#world', (c) => [c.clientLeft, c.clientTop]);
  return [box.x + border[0] + cx, box.y + border[1] + cy];
}

test('pressing on a body and dragging pulls it towards the pointer with a mouse joint', async () => {
  await page.click('#reset');
  await pauseSandbox();
  await page.evaluate(() => window.quackSandbox.clear());
  const index = await page.evaluate(() => window.quackSandbox.drop('box', [0, -2.9], 0));
  await page.evaluate(() => window.quackSandbox.run(30));  // settles on the ground
  let s = await sandbox();
  const start = shapeAt(s, index).pos;
  const bodies = s.world.bodies;
  assert.equal(s.world.jointCount, 0);
  assert.equal(s.world.mouse, null);
  // Press on the box's centre and drag 1.5 m right and 1.2 m up (60 pixels a metre), to a
  // place clear of the obstacles.
  const [px, py] = await pagePoint(start);
  await page.mouse.move(px, py);
  await page.mouse.down();
  await page.mouse.move(px + 90, py - 72, { steps: 8 });
  s = await sandbox();
  assert.equal(s.world.jointCount, 1);
  assert.deepEqual(s.world.joints.map((j) => j.type), ['mouse']);
  const target = s.world.mouse.target;
  assert.ok(Math.abs(target[0] - (start[0] + 1.5)) < 0.05 && Math.abs(target[1] - (start[1] + 1.2)) < 0.05,
    `target ${target} is not where the pointer is`);
  // The grabbed point is where the press was: the box's centre, until it moves.
  assert.ok(Math.hypot(s.world.mouse.point[0] - start[0], s.world.mouse.point[1] - start[1]) < 0.05);
  // The mouse joint is drawn (the picture changes when joints are hidden). The box is set
  // directly: a click on it now would go to the canvas, which holds the pointer.
  const showJoints = (on) => page.$eval('#show-joints', (c, v) => { c.checked = v; }, on);
  await sleep(100);
  const withJoint = await snapshot(page, 'world');
  await showJoints(false);
  await sleep(100);
  assert.notEqual(await snapshot(page, 'world'), withJoint, 'the mouse joint did not draw');
  await showJoints(true);
  await page.evaluate(() => window.quackSandbox.run(90));
  s = await sandbox();
  const end = shapeAt(s, index).pos;
  // Pulled towards the pointer: up and to the right, and there within 1.5 s (the 5 Hz
  // spring's sag under the box's weight is g / (2 pi 5 Hz)^2 = 1 cm).
  assert.ok(end[0] > start[0] + 1 && end[1] > start[1] + 0.8,
    `the box went from ${start} to ${end}, not towards ${target}`);
  assert.ok(Math.hypot(end[0] - target[0], end[1] - target[1]) < 0.05, `the box stopped at ${end}`);
  await page.mouse.up();
  s = await sandbox();
  assert.equal(s.world.jointCount, 0, 'releasing did not destroy the mouse joint');
  assert.equal(s.world.mouse, null);
  assert.equal(s.world.bodies, bodies, 'the release dropped a shape');
  // Let go, it falls.
  await page.evaluate(() => window.quackSandbox.run(30));
  assert.ok(shapeAt(await sandbox(), index).pos[1] < end[1] - 0.5);
  // A drag that starts on empty space grabs nothing.
  const [ex, ey] = await pagePoint([-4, 3.5]);
  await page.mouse.move(ex, ey);
  await page.mouse.down();
  await page.mouse.move(ex + 60, ey, { steps: 4 });
  assert.equal((await sandbox()).world.jointCount, 0);
  await page.mouse.up();
  assert.deepEqual(errors, []);
  await resumeSandbox();
});

test('the buttons drop in a chain, a car and a ragdoll, with their joints', async () => {
  await page.click('#reset');
  await pauseSandbox();
  await page.evaluate(() => window.quackSandbox.clear());
  const added = { chain: [21, 20], car: [3, 2], ragdoll: [10, 9] };  // bodies, joints
  for (const [kind, [bodies, joints]] of Object.entries(added)) {
    const before = (await sandbox()).world;
    await page.click(`#drop-${kind}`);
    const after = (await sandbox()).world;
    assert.equal(after.bodies, before.bodies + bodies, kind);
    assert.equal(after.jointCount, before.jointCount + joints, kind);
    assert.equal(after.joints.length, after.jointCount);
    assert.equal(await page.textContent('#joint-count'), String(after.jointCount));
  }
  const kinds = (await sandbox()).world.joints.map((j) => j.type);
  assert.equal(kinds.filter((t) => t === 'revolute').length, 29);
  assert.equal(kinds.filter((t) => t === 'wheel').length, 2);
  // Two seconds on, every joint still holds its bodies together: the revolute joints'
  // two anchors coincide (within their softness), and the chain has swung down.
  await page.evaluate(() => window.quackSandbox.run(120));
  const w = (await sandbox()).world;
  assert.equal(w.jointCount, 31);
  for (const j of w.joints.filter((x) => x.type === 'revolute')) {
    const [a, b] = [j.line[1], j.line[2]];
    assert.ok(Math.hypot(a[0] - b[0], a[1] - b[1]) < 0.05, `a joint came apart: ${a} ${b}`);
  }
  const chainEnd = w.joints[19].line[3];  // the last link's centre
  assert.ok(chainEnd[1] < 4.4 - 2, `the chain did not swing down (its end is at ${chainEnd})`);
  // The joints are drawn.
  await sleep(100);
  const withJoints = await snapshot(page, 'world');
  await page.uncheck('#show-joints');
  await sleep(100);
  assert.notEqual(await snapshot(page, 'world'), withJoints, 'the joints did not draw');
  await page.check('#show-joints');
  assert.deepEqual(errors, []);
  await resumeSandbox();
});

test('a car drives right while the right arrow is held, and left with the button', async () => {
  await page.click('#reset');
  await pauseSandbox();
  await page.evaluate(() => window.quackSandbox.clear());
  const car = await page.evaluate(() => window.quackSandbox.dropJointed('car'));
  const chassis = car.shapes[0];
  await page.evaluate(() => window.quackSandbox.run(60));  // lands on its springs, braked
  const x0 = shapeAt(await sandbox(), chassis).pos[0];
  await page.evaluate(() => window.quackSandbox.run(60));
  assert.ok(Math.abs(shapeAt(await sandbox(), chassis).pos[0] - x0) < 0.05, 'the braked car rolled');
  await page.keyboard.down('ArrowRight');
  assert.equal(await page.textContent('#drive-state'), 'driving right');
  await page.evaluate(() => window.quackSandbox.run(90));
  await page.keyboard.up('ArrowRight');
  assert.equal(await page.textContent('#drive-state'), 'braked');
  const x1 = shapeAt(await sandbox(), chassis).pos[0];
  assert.ok(x1 > x0 + 2, `the car went from x = ${x0} to ${x1} in 1.5 s`);
  await page.click('#drive-left');
  await page.evaluate(() => window.quackSandbox.run(90));
  await page.click('#brake');
  const x2 = shapeAt(await sandbox(), chassis).pos[0];
  assert.ok(x2 < x1 - 1, `the car did not back up (x = ${x1} then ${x2})`);
  assert.deepEqual(errors, []);
  await resumeSandbox();
});
