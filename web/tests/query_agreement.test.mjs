// The distance and depth the GJK page shows equal what `quack query` prints for the same
// shapes and poses (the native program, built by scripts/web.sh --test).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import { serve, launch, open, QUACK_BIN } from './helpers.mjs';
import { fmt } from '../js/common.js';
import { PRESETS } from '../js/shapes.js';

// A fixed pseudo-random sequence (so a failure can be replayed).
function random(seed) {
  let s = seed >>> 0;
  return () => {
    s = (Math.imul(s, 1664525) + 1013904223) >>> 0;
    return s / 2 ** 32;
  };
}

// Every preset against every preset, at poses from far apart to deeply overlapping, plus
// hand-picked cases (touching boxes, concentric circles, crossing segments).
function cases() {
  const names = Object.keys(PRESETS);
  const rand = random(9);
  const list = [];
  for (const a of names) {
    for (const b of names) {
      for (let k = 0; k < 2; ++k) {
        const r = 0.2 + 2.8 * rand();
        const phi = 2 * Math.PI * rand();
        list.push({
          a: PRESETS[a], b: PRESETS[b],
          pa: { pos: [+(rand() - 0.5).toFixed(3), +(rand() - 0.5).toFixed(3)], angle: +(6 * rand()).toFixed(3) },
          pb: { pos: [+(r * Math.cos(phi)).toFixed(3), +(r * Math.sin(phi)).toFixed(3)], angle: +(6 * rand()).toFixed(3) },
        });
      }
    }
  }
  const box = { type: 'box', half: [1, 1] };
  list.push({ a: box, pa: { pos: [0, 0], angle: 0 }, b: box, pb: { pos: [2, 0], angle: 0 } });
  list.push({ a: box, pa: { pos: [0, 0], angle: 0 }, b: box, pb: { pos: [0.5, 0.25], angle: 0 } });
  const circle = { type: 'circle', radius: 0.5 };
  list.push({ a: circle, pa: { pos: [1, 1], angle: 0 }, b: circle, pb: { pos: [1, 1], angle: 0 } });
  const seg = { type: 'segment', p1: [-1, 0], p2: [1, 0] };
  list.push({ a: seg, pa: { pos: [0, 0], angle: 0 }, b: seg, pb: { pos: [0, 0], angle: 1.5707964 } });
  return list;
}

function runQuery(lines) {
  const out = spawnSync(QUACK_BIN, ['query', '-'], { input: lines.map((l) => JSON.stringify(l)).join('\n') + '\n' });
  assert.equal(out.error, undefined, `cannot run ${QUACK_BIN}: ${out.error}`);
  assert.equal(out.status, 0, `quack query failed: ${out.stdout}${out.stderr}`);
  return out.stdout.toString().trim().split('\n').map((l) => JSON.parse(l));
}

let server;
let chrome;
let page;
let errors;

before(async () => {
  assert.ok(fs.existsSync(QUACK_BIN), `no quack program at ${QUACK_BIN} (scripts/web.sh --test builds it)`);
  server = await serve();
  chrome = await launch();
  ({ page, errors } = await open(chrome.browser, `${server.url}/index.html`));
});

after(async () => {
  await chrome?.close();
  await server?.close();
});

test('distance and depth on the page equal quack query', async () => {
  const all = cases();
  const lines = [];
  all.forEach((c, i) => {
    lines.push({ id: 2 * i, op: 'distance', a: c.a, pa: c.pa, b: c.b, pb: c.pb });
    lines.push({ id: 2 * i + 1, op: 'penetration', a: c.a, pa: c.pa, b: c.b, pb: c.pb });
  });
  const answers = runQuery(lines);
  let overlapping = 0;
  let sameText = 0;
  for (let i = 0; i < all.length; ++i) {
    const c = all[i];
    const shown = await page.evaluate((q) => {
      const error = window.quackDemo.setShapes(q.a, q.b);
      window.quackDemo.setPoses(q.pa, q.pb);
      const text = (id) => document.getElementById(id).textContent;
      const value = (id) => Number(document.getElementById(id).dataset.value);
      return { error, distance: text('distance'), depth: text('depth'), distanceValue: value('distance'),
        depthValue: value('depth'), iterations: value('gjk-iterations'), trace: text('trace-check') };
    }, c);
    const where = `case ${i}: ${JSON.stringify(c)}`;
    assert.equal(shown.error, null, where);
    const d = answers[2 * i];
    const p = answers[2 * i + 1];
    // The numbers shown (six significant digits) and the full floats behind them. The
    // WebAssembly and x86-64 builds run the same code, but the C libraries' sinf and cosf
    // (musl in emscripten, glibc natively) may differ in the last bit, which moves a pose,
    // and so an answer, by a few float ulps of the scene's size (a few metres here).
    const close = (x, y) => Math.abs(x - y) <= 2e-5 + 1e-5 * Math.abs(y);
    assert.ok(close(Number(shown.distance), d.distance), `distance shown ${shown.distance} vs ${d.distance}, ${where}`);
    assert.ok(close(Number(shown.depth), p.depth), `depth shown ${shown.depth} vs ${p.depth}, ${where}`);
    assert.ok(close(shown.distanceValue, d.distance), `distance ${shown.distanceValue} vs ${d.distance}, ${where}`);
    assert.ok(close(shown.depthValue, p.depth), `depth ${shown.depthValue} vs ${p.depth}, ${where}`);
    if (shown.distance === fmt(d.distance) && shown.depth === fmt(p.depth)) ++sameText;
    assert.equal(shown.iterations, d.iterations, `GJK iterations, ${where}`);
    assert.equal(shown.trace, 'agrees', `the iteration trace differs from the library, ${where}`);
    if (p.overlap) ++overlapping;
  }
  // The set covers both outcomes.
  assert.ok(overlapping > 10 && overlapping < all.length - 10, `${overlapping} of ${all.length} overlap`);
  // Most answers are the same to the last digit shown.
  assert.ok(sameText >= 0.9 * all.length, `only ${sameText} of ${all.length} agree in every digit shown`);
  console.log(`# ${all.length} poses: ${overlapping} overlapping, ${sameText} identical in every digit shown`);
  assert.deepEqual(errors, []);
});
