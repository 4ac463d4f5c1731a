// The 3D page (gjk3d.html): loads cleanly from the site alone (three.js included), draws
// both WebGL canvases, steps through GJK's simplex and EPA's polytope, a shape can be
// dragged, and its distance and depth equal what `quack query` prints for the same 3D lines.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import { serve, launch, open, snapshot, webglColourCount, sleep, QUACK_BIN } from './helpers.mjs';
import { fmt } from '../js/common.js';
import { PRESETS3 } from '../js/shapes3.js';

let server;
let chrome;
let page;
let errors;
let requests;

before(async () => {
  server = await serve();
  chrome = await launch();
  ({ page, errors, requests } = await open(chrome.browser, `${server.url}/gjk3d.html`));
});

after(async () => {
  await chrome?.close();
  await server?.close();
});

const demo = (f, ...args) => page.evaluate(([name, a]) => window.quackDemo3[name](...a), [f, args]);

test('loads with no console errors and no request off the site', async () => {
  await sleep(300);
  assert.deepEqual(errors, []);
  const away = requests.filter((u) => !u.startsWith(`${server.url}/`));
  assert.deepEqual(away, [], 'the page asked for something beyond the site');
  assert.ok(requests.some((u) => u.endsWith('/js/vendor/three/three.module.js')), 'three.js not loaded from the site');
});

test('the 2D page links to the 3D page', async () => {
  const p = await chrome.browser.newPage();
  await p.goto(`${server.url}/index.html`);
  assert.equal(await p.locator('a[href="gjk3d.html"]').count(), 1);
  await p.close();
});

test('both WebGL canvases are drawn (not blank) and the numbers are shown', async () => {
  assert.ok(await webglColourCount(page, 'scene3') > 10, 'shapes canvas is blank');
  assert.ok(await webglColourCount(page, 'minkowski3') > 10, 'B - A canvas is blank');
  assert.match(await page.textContent('#distance'), /^[0-9.e-]+$/);
  assert.equal((await demo('state')).paused, false);
  const a = await snapshot(page, 'scene3');
  await sleep(300);
  assert.notEqual(await snapshot(page, 'scene3'), a, 'the picture does not move while running');
});

test('Space pauses: the picture stops changing', async () => {
  await page.keyboard.press(' ');
  assert.equal((await demo('state')).paused, true);
  await sleep(100);
  const a = await snapshot(page, 'scene3');
  await sleep(300);
  assert.equal(await snapshot(page, 'scene3'), a, 'scene changed while paused');
  assert.equal(await page.textContent('#run-state'), 'paused');
  await page.keyboard.press(' ');
  assert.equal((await demo('state')).paused, false);
});

test('S steps GJK simplex by simplex up to the tetrahedron, then EPA polytopes; Esc ends', async () => {
  await demo('setShapes', PRESETS3.hull, PRESETS3.box);
  await demo('setPoses', { pos: [0, 0, 0], quat: [0, 0, 0, 1] }, { pos: [0.7, 0.2, 0.1], quat: [0.1, 0.2, 0.05, 0.97] });
  const result = await demo('result');
  assert.equal(result.penetration.overlap, true);
  assert.ok(result.epa.ran, 'EPA did not run');
  assert.equal(result.gjk.steps.at(-1).simplex.length, 4, 'GJK did not end on a tetrahedron');

  const counts = [];
  const pictures = new Set();
  for (let i = 0; i < result.gjk.steps.length; ++i) {
    await page.keyboard.press('s');
    assert.match(await page.textContent('#stepping'), new RegExp(`^GJK iteration ${i + 1} of ${result.gjk.steps.length}`));
    const drawn = await demo('drawn');
    assert.equal(drawn.simplex, result.gjk.steps[i].simplex.length);
    assert.equal(drawn.polytopeFaces, 0);
    counts.push(drawn.simplex);
    pictures.add(await snapshot(page, 'minkowski3'));
  }
  assert.equal((await demo('state')).paused, true);
  assert.ok(new Set(counts).size > 1, `stepping did not change the simplex drawn: ${counts}`);
  assert.equal(counts[0], 1);
  assert.equal(pictures.size, counts.length, 'a step did not change the picture');

  await page.keyboard.press('s');
  assert.match(await page.textContent('#stepping'), /^EPA iteration 1 of /);
  const first = await demo('drawn');
  assert.equal(first.simplex, 0);
  assert.equal(first.polytopeFaces, result.epa.steps[0].faces.length);
  assert.ok(first.polytopeFaces >= 4);
  if (result.epa.steps.length > 1) {
    await page.keyboard.press('s');
    assert.equal((await demo('drawn')).polytopeFaces, result.epa.steps[1].faces.length);
    assert.ok(result.epa.steps[1].faces.length > first.polytopeFaces, 'the polytope did not grow');
    await page.keyboard.press(',');
  }
  await page.keyboard.press(',');
  assert.match(await page.textContent('#stepping'), /^GJK iteration /);
  assert.equal((await demo('drawn')).simplex, 4);
  await page.keyboard.press('Escape');
  assert.equal(await page.textContent('#stepping'), 'final answer');
  assert.equal(await page.textContent('#trace-check'), 'agrees');
  assert.deepEqual(errors, []);
});

test('dragging a shape moves it; a drag on empty space turns the view instead', async () => {
  await demo('setShapes', PRESETS3.box, PRESETS3.sphere);
  await demo('setPoses', { pos: [-0.8, 0, 0], quat: [0, 0, 0, 1] }, { pos: [0.9, 0, 0], quat: [0, 0, 0, 1] });
  const box = await page.locator('#scene3').boundingBox();
  const [x, y] = await demo('toCanvas', [0.9, 0, 0]);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x - 40, box.y + y, { steps: 5 });
  await page.mouse.up();
  const [, b] = await demo('poses');
  assert.ok(b.pos[0] < 0.8, `B did not move left: ${b.pos}`);
  assert.equal((await demo('state')).selected, 1);
  // Empty space: the shapes stay, the picture turns.
  const before = await demo('poses');
  const picture = await snapshot(page, 'scene3');
  await page.mouse.move(box.x + 20, box.y + 20);
  await page.mouse.down();
  await page.mouse.move(box.x + 80, box.y + 40, { steps: 5 });
  await page.mouse.up();
  await sleep(100);
  assert.deepEqual(await demo('poses'), before);
  assert.notEqual(await snapshot(page, 'scene3'), picture, 'the view did not turn');
});

// ---- agreement with `quack query` ------------------------------------------------------------

function runQuery(lines) {
  const out = spawnSync(QUACK_BIN, ['query', '-'], { input: lines.map((l) => JSON.stringify(l)).join('\n') + '\n' });
  assert.equal(out.error, undefined, `cannot run ${QUACK_BIN}: ${out.error}`);
  assert.equal(out.status, 0, `quack query failed: ${out.stdout}${out.stderr}`);
  return out.stdout.toString().trim().split('\n').map((l) => JSON.parse(l));
}

// Every preset against every preset at a pose apart and one overlapping (the quaternions
// are unit to 6 digits; both the page and quack query normalise them the same way).
function cases() {
  const names = Object.keys(PRESETS3);
  const list = [];
  const q = [0.2, -0.3, 0.1, 0.927362];
  for (const a of names) {
    for (const b of names) {
      list.push({ a: PRESETS3[a], b: PRESETS3[b], pa: { pos: [0.1, -0.2, 0.05], quat: [0, 0, 0, 1] }, pb: { pos: [1.9, 0.4, -0.3], quat: q } });
      list.push({ a: PRESETS3[a], b: PRESETS3[b], pa: { pos: [0.1, -0.2, 0.05], quat: [0, 0, 0, 1] }, pb: { pos: [0.45, -0.1, 0.2], quat: q } });
    }
  }
  return list;
}

test('distance and depth on the page equal quack query for the same 3D lines', async () => {
  assert.ok(fs.existsSync(QUACK_BIN), `no quack program at ${QUACK_BIN} (scripts/web.sh --test builds it)`);
  const all = cases();
  const lines = [];
  all.forEach((c, i) => {
    lines.push({ id: 2 * i, op: 'distance', a: c.a, pa: c.pa, b: c.b, pb: c.pb });
    lines.push({ id: 2 * i + 1, op: 'penetration', a: c.a, pa: c.pa, b: c.b, pb: c.pb });
  });
  const answers = runQuery(lines);
  assert.equal(answers.length, lines.length);
  let overlapping = 0;
  let identical = 0;
  for (let i = 0; i < all.length; ++i) {
    const c = all[i];
    await demo('setShapes', c.a, c.b);
    await demo('setPoses', c.pa, c.pb);
    const r = await demo('result');
    const shown = { distance: await page.textContent('#distance'), depth: await page.textContent('#depth') };
    const d = answers[2 * i];
    const p = answers[2 * i + 1];
    const what = `case ${i}: ${JSON.stringify(c)}`;
    assert.equal(d.id, 2 * i);
    assert.equal(p.id, 2 * i + 1);
    assert.equal(r.distance.iterations, d.iterations, `GJK iterations, ${what}`);
    assert.equal(r.penetration.overlap, p.overlap, `overlap, ${what}`);
    assert.equal(r.penetration.status, p.status, `EPA status, ${what}`);
    assert.ok(r.traceAgrees.gjk && r.traceAgrees.epa, `trace differs from the answer, ${what}`);
    const near = (x, y) => Math.abs(x - y) <= 2e-5 + 1e-5 * Math.abs(y);
    assert.ok(near(r.distance.distance, d.distance), `distance ${r.distance.distance} vs ${d.distance}, ${what}`);
    assert.ok(near(r.penetration.depth, p.depth), `depth ${r.penetration.depth} vs ${p.depth}, ${what}`);
    for (const k of [0, 1, 2]) {
      assert.ok(near(r.penetration.normal[k], p.normal[k]), `normal ${r.penetration.normal} vs ${p.normal}, ${what}`);
    }
    if (shown.distance === fmt(d.distance) && shown.depth === fmt(p.depth)) ++identical;
    if (p.overlap) ++overlapping;
  }
  console.log(`# 3D agreement: ${identical} of ${all.length} identical in every digit shown, ${overlapping} overlapping`);
  assert.ok(overlapping >= all.length / 3, `only ${overlapping} overlapping cases`);
  assert.ok(identical >= 0.9 * all.length, `only ${identical} of ${all.length} identical as shown`);
});

test('a preset pose: the panel shows exactly what quack query prints', async () => {
  const c = { a: PRESETS3.box, pa: { pos: [0, 0, 0], quat: [0, 0, 0, 1] }, b: PRESETS3.hull, pb: { pos: [0.9, 0.3, 0.2], quat: [0.1, 0.2, 0.3, 0.927362] } };
  const [d, p] = runQuery([
    { id: 'd', op: 'distance', ...c },
    { id: 'p', op: 'penetration', ...c },
  ]);
  await demo('setShapes', c.a, c.b);
  await demo('setPoses', c.pa, c.pb);
  assert.equal(await page.textContent('#distance'), fmt(d.distance));
  assert.equal(await page.textContent('#depth'), fmt(p.depth));
  assert.equal(await page.textContent('#overlap'), String(p.overlap));
  const far = { ...c, pb: { pos: [2.5, 0.3, 0.2], quat: c.pb.quat } };
  const [d2] = runQuery([{ id: 'd2', op: 'distance', ...far }]);
  assert.ok(d2.distance > 0);
  await demo('setPoses', far.pa, far.pb);
  assert.equal(await page.textContent('#distance'), fmt(d2.distance));
  assert.deepEqual(errors, []);
});
