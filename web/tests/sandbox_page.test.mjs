// Page 2 (sandbox.html): the world runs, a click drops a shape, shapes collide (contacts
// and events appear), the broad-phase boxes are drawn, pause stops the picture, and every
// broad phase works.
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
