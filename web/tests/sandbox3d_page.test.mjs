// The 3D sandbox (sandbox3d.html): loads from the site alone and draws the World3 with
// WebGL; a dropped body falls as the sub-stepped integrator's closed form says and comes
// to rest on the floor; a click drops a body above the point under the pointer; the samples
// load with their body counts; a bad scene shows `quack run`'s own message, field named.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { serve, launch, open, snapshot, webglColourCount, sleep, SITE, QUACK_BIN } from './helpers.mjs';
import { PRESETS3 } from '../js/shapes3.js';

let server;
let chrome;
let page;
let errors;
let requests;

before(async () => {
  server = await serve();
  chrome = await launch();
  ({ page, errors, requests } = await open(chrome.browser, `${server.url}/sandbox3d.html`));
});

after(async () => {
  await chrome?.close();
  await server?.close();
});

const sandbox = (f, ...args) => page.evaluate(([name, a]) => window.quackSandbox3[name](...a), [f, args]);
const world = async () => (await sandbox('state')).world;
const bodyOf = async (index) => (await world()).bodies.find((b) => b.index === index);

// A floor (top face at y = 0) and nothing else; World3's defaults otherwise.
const FLOOR = JSON.stringify({
  world: { dim: 3 },
  bodies: [{ name: 'floor', type: 'static', pos: [0, -0.5, 0], shapes: [{ type: 'box', half: [5, 0.5, 5] }] }],
});

// `quack run`'s message for a scene's text, as a file: its stderr line without "quack run: "
// and with the file's path where the page has its own name for the text.
function cliMessage(text, nameOnPage) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'quack-scene3-'));
  const file = path.join(dir, 'scene.json');
  fs.writeFileSync(file, text);
  const r = spawnSync(QUACK_BIN, ['run', file, '--steps', '1', '--quiet', '--out', path.join(dir, 'out.json')],
    { encoding: 'utf8' });
  fs.rmSync(dir, { recursive: true, force: true });
  assert.notEqual(r.status, 0, `quack run accepted the bad scene: ${r.stderr}`);
  const line = r.stderr.trim().split('\n')[0];
  assert.ok(line.startsWith('quack run: '), line);
  return line.slice('quack run: '.length).split(file).join(nameOnPage);
}

test('loads with no console errors, nothing off the site, and draws the world', async () => {
  await sleep(300);
  assert.deepEqual(errors, []);
  const away = requests.filter((u) => !u.startsWith(`${server.url}/`));
  assert.deepEqual(away, [], 'the page asked for something beyond the site');
  assert.ok(await webglColourCount(page, 'world3') > 10, 'the WebGL canvas is blank');
  const s = await sandbox('state');
  assert.equal(s.scene, 'sandbox');
  assert.equal(s.world.bodyCount, 7);
  // Running: the picture moves while the built-in scene's bodies fall.
  const a = await snapshot(page, 'world3');
  await sleep(300);
  assert.notEqual(await snapshot(page, 'world3'), a, 'the picture does not move while running');
});

test('the other pages link to it', async () => {
  const p = await chrome.browser.newPage();
  for (const other of ['index.html', 'gjk3d.html', 'sandbox.html']) {
    await p.goto(`${server.url}/${other}`);
    assert.equal(await p.locator('a[href="sandbox3d.html"]').count(), 1, other);
  }
  await p.close();
});

// The world's step: `substeps` sub-steps of h = dt / substeps, each v += g h, then x += v h
// (symplectic Euler, src/world/solver3.cpp). From rest, after N sub-steps the drop is
// g h^2 N (N + 1) / 2: the continuous y0 - g t^2 / 2 plus g h t / 2.
test('a dropped body falls by the sub-stepped closed form, then rests on the floor', async () => {
  assert.equal((await sandbox('loadText', FLOOR, 'floor')).ok, true);
  await sandbox('pause', true);
  const s = await sandbox('state');
  assert.equal(s.world.substeps, 4);
  assert.ok(Math.abs(s.dt - 1 / 60) < 1e-7, `dt ${s.dt}`);
  const y0 = 10;
  const r = await sandbox('drop', 'sphere', [0.5, y0, -0.25], [0, 0, 0, 1]);
  assert.equal(typeof r.body, 'number', JSON.stringify(r));
  const steps = 30;
  await sandbox('run', steps);
  const g = 10;
  const h = s.dt / 4;
  const n = 4 * steps;
  const expected = y0 - g * h * h * n * (n + 1) / 2;
  const continuous = y0 - g * (steps * s.dt) ** 2 / 2;
  const b = await bodyOf(r.body);
  assert.ok(Math.abs(b.pos[1] - expected) < 2e-4, `y ${b.pos[1]}, expected ${expected}`);
  // The tolerance tells the sub-stepped answer from the continuous one (1 cm apart here).
  assert.ok(Math.abs(continuous - expected) > 0.005);
  assert.ok(Math.abs(b.vel[1] + g * n * h) < 1e-3, `vy ${b.vel[1]}`);
  assert.deepEqual([b.pos[0], b.pos[2]], [0.5, -0.25], 'a free fall moved sideways');
  // Two more seconds: on the floor (top at y = 0), the sphere's centre a radius above it.
  await sandbox('run', 120);
  const rest = await bodyOf(r.body);
  const radius = PRESETS3.sphere.radius;
  assert.ok(Math.abs(rest.pos[1] - radius) < 0.02, `resting at y ${rest.pos[1]}, radius ${radius}`);
  assert.ok(Math.hypot(...rest.vel) < 0.05, `still moving at ${rest.vel}`);
  assert.ok((await world()).touching >= 1);
  assert.deepEqual(errors, []);
});

test('a click drops the selected shape 3 m above the point under the pointer', async () => {
  assert.equal((await sandbox('loadSample', 'sandbox')).ok, true);
  await sandbox('pause', true);
  const before = await world();
  const click = [300, 380];
  await page.click('#world3', { position: { x: click[0], y: click[1] } });
  const after = await world();
  assert.equal(after.bodyCount, before.bodyCount + 1);
  const added = after.bodies.reduce((a, b) => (b.index > a.index ? b : a));
  assert.equal(added.type, 'dynamic');
  // The point 3 m below it is drawn under the pointer (World3's ray cast found it).
  const under = [added.pos[0], added.pos[1] - 3, added.pos[2]];
  const drawn = await sandbox('project', under);
  assert.ok(Math.hypot(drawn[0] - click[0], drawn[1] - click[1]) < 1.5, `drawn at ${drawn}, clicked ${click}`);
  // ... and on a surface: the floor's top (y = 0) or another body, not in the air.
  assert.ok(under[1] > -0.01, `the point under the pointer is at y ${under[1]}`);
  // A drag turns the view and drops nothing.
  await page.mouse.move(400, 300);
  await page.mouse.down();
  await page.mouse.move(460, 320, { steps: 5 });
  await page.mouse.up();
  assert.equal((await world()).bodyCount, after.bodyCount);
  // Stepping moves the new body down.
  await sandbox('run', 20);
  assert.ok((await bodyOf(added.index)).pos[1] < added.pos[1] - 0.1);
  // "drop at random" adds one more, above everything.
  await page.click('#drop-random');
  assert.equal((await world()).bodyCount, after.bodyCount + 1);
  assert.deepEqual(errors, []);
});

test('every sample loads with the body count of its file, and reset loads it again', async () => {
  for (const name of ['pyramid', 'hulls', 'ramp', 'cards']) {
    const text = fs.readFileSync(path.join(SITE, `scenes/${name}-3d.json`), 'utf8');
    const count = JSON.parse(text).bodies.length;
    await page.selectOption('#sample', name);
    await page.waitForFunction((n) => window.quackSandbox3.state().scene === n, `scenes/${name}-3d.json`);
    const w = await world();
    assert.equal(w.bodyCount, count, name);
    assert.equal(await page.textContent('#bodies'), String(count), name);
    assert.equal(await page.inputValue('#scene-text'), text);
  }
  const pyramid = JSON.parse(fs.readFileSync(path.join(SITE, 'scenes/pyramid-3d.json'), 'utf8'));
  assert.equal((await sandbox('loadSample', 'pyramid')).bodies, pyramid.bodies.length);
  assert.equal(pyramid.bodies.length, 56);
  await sandbox('pause', false);
  await sleep(200);
  assert.ok(await webglColourCount(page, 'world3') > 10);
  // Reset: the same scene, from its first step.
  await sandbox('pause', true);
  await sandbox('drop', 'box', [0, 12, 0]);
  await page.click('#reset');
  const w = await world();
  assert.equal(w.bodyCount, 56);
  assert.equal(w.steps, 0);
  assert.deepEqual(errors, []);
});

test('a bad scene shows the parser\'s message, field named, as quack run says it', async () => {
  await sandbox('pause', true);
  const before = await world();
  const cases = [
    // A rotation that is not one.
    JSON.stringify({ world: { dim: 3 }, bodies: [{ pos: [0, 1, 0], shapes: [{ type: 'sphere', radius: 1 }] },
      { quat: [0, 0, 0, 0], shapes: [{ type: 'sphere', radius: 1 }] }] }),
    // A 2D box in a 3D scene.
    JSON.stringify({ world: { dim: 3 }, bodies: [{ shapes: [{ type: 'box', half: [1, 2] }] }] }),
    // A radius that is not a number.
    JSON.stringify({ world: { dim: 3 }, bodies: [{ type: 'static' }, { shapes: [{ type: 'sphere', radius: 'big' }] }] }),
    // An unknown world key.
    JSON.stringify({ world: { dim: 3, gravty: [0, -10, 0] } }),
    // Not JSON at all (the page's module has no exception catching: this must not abort it),
    // and a number beyond a double (nlohmann's out_of_range error, not a parse error).
    '{"world": {"dim": 3}, "bodies": [}',
    '{"world": {"dim": 3, "gravity": [0, -1e400, 0]}}',
  ];
  const fields = ['bodies[1].quat', 'bodies[0].shapes[0].type', 'bodies[1].shapes[0].radius', 'world.gravty',
    'not valid JSON', 'number overflow'];
  for (let i = 0; i < cases.length; ++i) {
    await page.fill('#scene-text', cases[i]);
    await page.click('#load-text');
    const shown = await page.textContent('#scene-error');
    assert.ok(shown.includes(fields[i]), `${fields[i]} not named in: ${shown}`);
    assert.ok(shown.startsWith('pasted scene: '), shown);
    assert.equal(shown, cliMessage(cases[i], 'pasted scene'));
    // The world is as it was.
    assert.equal((await world()).bodyCount, before.bodyCount);
  }
  // And the module still works: a step, then a good scene clears the message.
  await sandbox('run', 1);
  await page.fill('#scene-text', FLOOR);
  await page.click('#load-text');
  assert.equal(await page.textContent('#scene-error'), '');
  assert.equal((await world()).bodyCount, 1);
  assert.deepEqual(errors, []);
});

test('bad input to the binding is refused with a message, not a crash', async () => {
  const answers = await page.evaluate(async () => {
    const q = await globalThis.createQuack();
    const call = (name, types, args) => JSON.parse(q.ccall(name, 'string', types, args));
    const out = {};
    out.noWorld = call('qk3_world_step', ['number', 'number'], [1 / 60, 1]);
    out.load = call('qk3_world_load', ['string', 'string'],
      ['{"world": {"dim": 3}, "bodies": [{"type": "static", "shapes": [{"type": "box", "half": [5, 0.5, 5]}]}]}', 'x']);
    out.badShape = call('qk3_world_add', ['string'], ['{"shape": {"type": "sphere", "radius": -1}, "pos": [0, 1, 0]}']);
    out.badKey = call('qk3_world_add', ['string'], ['{"shape": {"type": "sphere", "radius": 1}, "spin": 1}']);
    out.badPos = call('qk3_world_add', ['string'], ['{"shape": {"type": "sphere", "radius": 1}, "pos": [0, 1]}']);
    out.badJson = call('qk3_world_add', ['string'], ['{"shape": ']);
    out.badDt = call('qk3_world_step', ['number', 'number'], [-1, 1]);
    out.badSteps = call('qk3_world_step', ['number', 'number'], [1 / 60, 0]);
    out.badRay = call('qk3_world_raycast', Array(6).fill('number'), [NaN, 0, 0, 0, -1, 0]);
    out.ray = call('qk3_world_raycast', Array(6).fill('number'), [0, 5, 0, 0, -10, 0]);
    out.state = call('qk3_world_state', ['number'], [0]);
    return out;
  });
  assert.match(answers.noWorld.error, /no 3D world/);
  assert.equal(answers.load.ok, true);
  assert.match(answers.badShape.error, /^body\.shape\.radius/);
  assert.match(answers.badKey.error, /^body\.spin/);
  assert.match(answers.badPos.error, /^body\.pos/);
  assert.match(answers.badJson.error, /^body: not valid JSON/);
  assert.ok(answers.badDt.error, 'a negative dt was accepted');
  assert.match(answers.badSteps.error, /^steps/);
  assert.match(answers.badRay.error, /ray origin/);
  // The floor, a box of half height 0.5 about its body's origin (0, 0, 0), has its top at
  // y = 0.5: the ray from y = 5 down by 10 meets it at fraction 0.45.
  assert.ok(Math.abs(answers.ray.hit.point[1] - 0.5) < 1e-5, JSON.stringify(answers.ray));
  assert.ok(Math.abs(answers.ray.hit.fraction - 0.45) < 1e-6);
  assert.deepEqual(answers.ray.hit.normal, [0, 1, 0]);
  assert.equal(answers.state.bodyCount, 1);
  assert.deepEqual(errors, []);
});
