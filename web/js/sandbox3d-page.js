// The 3D sandbox (sandbox3d.html): a live World3 drawn with three.js (WebGL). The world is a
// 3D scene, read by the parser `quack run` uses (qk3_world_load in web/glue/glue.cpp:
// parseScene3 and buildWorld3), so a pasted scene's errors are `quack run`'s; the samples
// are the repository's scenes/*-3d.json. Bodies dropped from above at the pointer (World3's
// ray cast finds the point under it) or at a random spot; orbit, zoom, pause, step, reset.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadQuack, fmt } from './common.js';
import { PRESETS3 } from './shapes3.js';
import { shapeObject } from './three-shapes.js';

const $ = (id) => document.getElementById(id);
// What can be dropped: the 3D page's presets (web/js/shapes3.js).
const DROPS = ['box', 'sphere', 'capsule', 'hull'];
// A click drops a body this far above the point under the pointer (metres).
const DROP_HEIGHT = 3;
// How far (pixels) the pointer may move between press and release for a click (a drop);
// further, it turned the view.
const CLICK_PIXELS = 4;
// Dynamic bodies below this height fell off the world and are removed.
const CULL_Y = -20;
const RAIN_SECONDS = 0.5;
const BACKGROUND = 0xfbfaf7;
const STATIC_COLOUR = 0xb8b4a8;
const EDGE_COLOUR = 0x3a3a3a;
const CONTACT_COLOUR = 0xc44e52;
const PALETTE = [0x4c72b0, 0xdd8452, 0x55a868, 0xc44e52, 0x8172b3, 0x937860, 0xda8bc3, 0x8c8c8c];
// Sleeping bodies are drawn this far towards the background colour.
const SLEEPING_FADE = 0.6;

// The built-in scene: a floor and a few bodies, in the 3D scene format.
const SANDBOX_SCENE = {
  world: { dim: 3 },
  bodies: [
    { name: 'floor', type: 'static', pos: [0, -0.5, 0], shapes: [{ type: 'box', half: [10, 0.5, 10] }] },
    { name: 'ramp', type: 'static', pos: [4, 0.6, -3], quat: [0, 0, 0.2588, 0.9659], shapes: [{ type: 'box', half: [2, 0.1, 1.5] }] },
    { name: 'crate1', pos: [-1, 0.5, 0], shapes: [{ type: 'box', half: [0.5, 0.5, 0.5] }] },
    { name: 'crate2', pos: [-1, 1.5, 0], shapes: [{ type: 'box', half: [0.5, 0.5, 0.5] }] },
    { name: 'ball', pos: [1.5, 3, 0.5], shapes: [{ type: 'sphere', radius: 0.5 }] },
    { name: 'pill', pos: [0, 4, -1.5], quat: [0.3827, 0, 0, 0.9239], shapes: [{ type: 'capsule', p1: [0, -0.4, 0], p2: [0, 0.4, 0], radius: 0.3 }] },
    { name: 'rock', pos: [-2.5, 2, 1.5], shapes: [PRESETS3.hull] },
  ],
};

let quack;
const state = {
  paused: false,
  scene: { name: 'sandbox', text: JSON.stringify(SANDBOX_SCENE, null, 1) },
  dt: 1 / 60,
  substeps: 4,
  world: null, // the last qk3_world_state answer
  shapesVersion: -1, // of the meshes drawn
  lastRain: 0,
  error: '',
};

// ---- three.js ---------------------------------------------------------------------------

let renderer;
let scene;
let camera;
let controls;
let bodiesGroup;
let contactsGroup;
const bodyObjects = new Map(); // sandbox body index -> its group

function initView() {
  const canvas = $('world3');
  renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setClearColor(BACKGROUND);
  scene = new THREE.Scene();
  scene.add(new THREE.AmbientLight(0xffffff, 1.1));
  const sun = new THREE.DirectionalLight(0xffffff, 2.2);
  sun.position.set(4, 10, 6);
  scene.add(sun);
  camera = new THREE.PerspectiveCamera(45, canvas.width / canvas.height, 0.05, 500);
  controls = new OrbitControls(camera, canvas);
  bodiesGroup = new THREE.Group();
  contactsGroup = new THREE.Group();
  scene.add(bodiesGroup, contactsGroup);
}

function disposeGroup(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    child.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
  }
}

// Rebuilds every body's meshes from the glue's shape list (after a load, a drop, a cull).
function rebuildMeshes() {
  const r = quack.world3Shapes();
  if (r.error) throw new Error(r.error);
  disposeGroup(bodiesGroup);
  bodyObjects.clear();
  const types = new Map(state.world.bodies.map((b) => [b.index, b.type]));
  for (const s of r.shapes) {
    let group = bodyObjects.get(s.body);
    if (!group) {
      group = new THREE.Group();
      bodyObjects.set(s.body, group);
      bodiesGroup.add(group);
    }
    const colour = types.get(s.body) === 'static' ? STATIC_COLOUR : PALETTE[s.body % PALETTE.length];
    group.add(shapeObject(s, colour, { opacity: 1, edges: EDGE_COLOUR }));
  }
  // Each fill material remembers its colour, for fading sleeping bodies.
  for (const group of bodyObjects.values()) {
    group.traverse((o) => { if (o.isMesh) o.userData.colour = o.material.color.clone(); });
  }
  state.shapesVersion = r.version;
}

const background = new THREE.Color(BACKGROUND);

function placeBodies() {
  for (const b of state.world.bodies) {
    const group = bodyObjects.get(b.index);
    if (!group) continue;
    group.position.set(...b.pos);
    group.quaternion.set(...b.quat);
    const faded = b.type !== 'static' && !b.awake;
    if (group.userData.faded !== faded) {
      group.userData.faded = faded;
      group.traverse((o) => {
        if (o.isMesh) o.material.color.copy(o.userData.colour).lerp(background, faded ? SLEEPING_FADE : 0);
      });
    }
  }
}

function drawContacts() {
  disposeGroup(contactsGroup);
  if (!$('show-contacts').checked) return;
  const points = [];
  const normals = [];
  for (const m of state.world.contacts) {
    for (const p of m.points) {
      points.push(...p.point);
      normals.push(...p.point, ...p.point.map((x, i) => x + 0.3 * m.normal[i]));
    }
  }
  const pg = new THREE.BufferGeometry();
  pg.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  contactsGroup.add(new THREE.Points(pg, new THREE.PointsMaterial({ color: CONTACT_COLOUR, size: 6, sizeAttenuation: false, depthTest: false })));
  const ng = new THREE.BufferGeometry();
  ng.setAttribute('position', new THREE.Float32BufferAttribute(normals, 3));
  contactsGroup.add(new THREE.LineSegments(ng, new THREE.LineBasicMaterial({ color: CONTACT_COLOUR, depthTest: false })));
}

function render() {
  controls.update();
  renderer.render(scene, camera);
}

// Aims the camera at the scene: the boxes of its dynamic bodies and of its static ones but
// floors (a static box under FLOOR_HEIGHT metres high and over FLOOR_WIDTH across: a 40 m
// floor would shrink the rest), so that a ramp is in the picture.
const FLOOR_HEIGHT = 1.5;
const FLOOR_WIDTH = 10;
const isFloor = (size) => size.y < FLOOR_HEIGHT && Math.max(size.x, size.z) > FLOOR_WIDTH;

function frameScene() {
  bodiesGroup.updateMatrixWorld(true);
  const types = new Map(state.world.bodies.map((b) => [b.index, b.type]));
  const box = new THREE.Box3();
  for (const [index, group] of bodyObjects) {
    const b = new THREE.Box3().setFromObject(group);
    if (types.get(index) !== 'static' || !isFloor(b.getSize(new THREE.Vector3()))) box.union(b);
  }
  if (box.isEmpty()) box.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(4, 4, 4));
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length();
  const distance = Math.max(8, size);
  controls.target.copy(centre);
  camera.position.copy(centre).add(new THREE.Vector3(0.55, 0.5, 0.8).normalize().multiplyScalar(distance));
  camera.updateProjectionMatrix();
}

// ---- the world --------------------------------------------------------------------------

function refresh() {
  const s = quack.world3State($('show-contacts').checked);
  if (s.error) throw new Error(s.error);
  state.world = s;
  if (s.shapesVersion !== state.shapesVersion) rebuildMeshes();
  placeBodies();
  drawContacts();
  showNumbers();
}

function showNumbers() {
  const w = state.world;
  $('scene-name').textContent = state.scene.name;
  $('time').textContent = `${fmt(w.time)} s / ${w.steps}`;
  $('bodies').textContent = String(w.bodyCount);
  $('awake').textContent = String(w.awakeBodies);
  $('contacts').textContent = `${w.touching} / ${w.contactCount}`;
  $('substeps').textContent = String(w.substeps);
  $('pause').textContent = state.paused ? 'play' : 'pause';
}

/** Loads a scene's text (named `name` in messages, as `quack run` names its file). On an
 * error the world is unchanged and the parser's message is shown; returns the answer. */
function loadText(text, name) {
  const r = quack.world3Load(text, name);
  if (r.error) {
    state.error = r.error;
    $('scene-error').textContent = r.error;
    return r;
  }
  state.error = '';
  $('scene-error').textContent = '';
  state.scene = { name, text };
  state.dt = r.timeStep;
  state.substeps = r.substeps;
  state.shapesVersion = -1;
  refresh();
  frameScene();
  return r;
}

async function sampleText(name) {
  if (name === 'sandbox') return JSON.stringify(SANDBOX_SCENE, null, 1);
  const response = await fetch(`scenes/${name}-3d.json`);
  if (!response.ok) throw new Error(`scenes/${name}-3d.json: HTTP ${response.status}`);
  return response.text();
}

async function loadSample(name) {
  const text = await sampleText(name);
  $('sample').value = name;
  $('scene-text').value = text;
  return loadText(text, name === 'sandbox' ? 'sandbox' : `scenes/${name}-3d.json`);
}

function reset() {
  return loadText(state.scene.text, state.scene.name);
}

// A random rotation, uniform over all rotations (Shoemake's unit quaternion from three
// uniform numbers, Graphics Gems III).
function randomQuat() {
  const [u1, u2, u3] = [Math.random(), Math.random(), Math.random()];
  const a = Math.sqrt(1 - u1);
  const b = Math.sqrt(u1);
  return [a * Math.sin(2 * Math.PI * u2), a * Math.cos(2 * Math.PI * u2), b * Math.sin(2 * Math.PI * u3), b * Math.cos(2 * Math.PI * u3)];
}

/** Drops a dynamic body (a preset of DROPS) at pos, turned by quat (random unless given);
 * returns the answer ({body, shape} or {error}). */
function drop(kind, pos, quat = randomQuat()) {
  const shape = PRESETS3[kind];
  if (!shape) return { error: `drop: no shape "${kind}" (expected ${DROPS.join(', ')})` };
  const restitution = Number($('restitution').value) || 0;
  const r = quack.world3Add({ shape, pos, quat, restitution });
  if (r.error) {
    $('status').textContent = `drop: ${r.error}`;
    return r;
  }
  refresh();
  return r;
}

// The highest point of the bodies' origins (dynamic ones), for drops at a random spot.
function topOfPile() {
  let top = 0;
  for (const b of state.world.bodies) if (b.type !== 'static') top = Math.max(top, b.pos[1]);
  return top;
}

function dropRandom(kind = $('drop-shape').value) {
  const x = (Math.random() - 0.5) * 6;
  const z = (Math.random() - 0.5) * 6;
  return drop(kind, [x, topOfPile() + DROP_HEIGHT + 1, z]);
}

// The world point under canvas pixel (x, y): the first shape World3's ray cast meets along
// the ray from the camera through that pixel, else the plane y = 0; null when neither.
function pointUnder(x, y) {
  const canvas = $('world3');
  const ndc = new THREE.Vector2((x / canvas.clientWidth) * 2 - 1, -(y / canvas.clientHeight) * 2 + 1);
  const ray = new THREE.Raycaster();
  ray.setFromCamera(ndc, camera);
  const o = ray.ray.origin;
  const d = ray.ray.direction.clone().multiplyScalar(1000);
  const r = quack.world3RayCast([o.x, o.y, o.z], [d.x, d.y, d.z]);
  if (r.error) throw new Error(r.error);
  if (r.hit) return r.hit.point;
  if (d.y < 0) {
    const t = -o.y / d.y;
    return [o.x + t * d.x, 0, o.z + t * d.z];
  }
  return null;
}

function dropAtPixel(x, y, kind = $('drop-shape').value, quat = randomQuat()) {
  const p = pointUnder(x, y);
  if (!p) return dropRandom(kind);
  return drop(kind, [p[0], p[1] + DROP_HEIGHT, p[2]], quat);
}

/** Steps n times at once (the world's own dt and sub-steps), culls what fell off. */
function run(n) {
  const r = quack.world3Step(state.dt, n);
  if (r.error) throw new Error(r.error);
  quack.world3Cull(CULL_Y);
  refresh();
  return r;
}

// ---- the page ---------------------------------------------------------------------------

function setPaused(paused) {
  state.paused = paused;
  showNumbers();
}

function frame() {
  try {
    if (!state.paused) {
      run(1);
      if ($('rain').checked && state.world.time - state.lastRain >= RAIN_SECONDS) {
        state.lastRain = state.world.time;
        dropRandom();
      }
    }
    render();
  } catch (e) {
    // A failure pauses the world and is shown; the page keeps drawing.
    state.paused = true;
    $('status').textContent = `error: ${e.message}`;
    console.error(e);
  }
  requestAnimationFrame(frame);
}

function installControls() {
  for (const name of DROPS) {
    const o = document.createElement('option');
    o.textContent = name;
    $('drop-shape').append(o);
  }
  $('pause').onclick = () => setPaused(!state.paused);
  $('step').onclick = () => { setPaused(true); run(1); };
  $('reset').onclick = () => reset();
  $('drop-random').onclick = () => dropRandom();
  $('sample').onchange = () => loadSample($('sample').value);
  $('load-text').onclick = () => loadText($('scene-text').value, 'pasted scene');
  $('show-contacts').onchange = () => refresh();
  // A press and release that barely moved is a click: a drop under the pointer. A longer
  // move turned the view (OrbitControls) and drops nothing.
  const canvas = $('world3');
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { if (e.button === 0) down = [e.offsetX, e.offsetY]; });
  canvas.addEventListener('pointerup', (e) => {
    if (e.button !== 0 || !down) return;
    const moved = Math.hypot(e.offsetX - down[0], e.offsetY - down[1]);
    down = null;
    if (moved < CLICK_PIXELS) dropAtPixel(e.offsetX, e.offsetY);
  });
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLTextAreaElement || e.target instanceof HTMLInputElement) return;
    if (e.key === ' ') { e.preventDefault(); setPaused(!state.paused); }
    if (e.key === 's' || e.key === 'S') { setPaused(true); run(1); }
  });
}

async function main() {
  quack = await loadQuack();
  initView();
  installControls();
  const r = await loadSample('sandbox');
  if (r.error) throw new Error(r.error);
  window.quackSandbox3 = {
    state: () => ({ paused: state.paused, scene: state.scene.name, dt: state.dt, error: state.error, world: state.world }),
    /** Loads a sample ('sandbox', 'pyramid', 'hulls', 'ramp', 'cards'). */
    loadSample,
    /** Loads a scene's text as if pasted; returns the answer ({ok, bodies, ...} or {error}). */
    loadText: (text, name = 'pasted scene') => loadText(text, name),
    reset,
    pause: (paused = true) => setPaused(paused),
    run,
    drop,
    dropAtPixel,
    /** Where the world point p is drawn, in canvas pixels (CSS pixels from the top left). */
    project: (p) => {
      const v = new THREE.Vector3(...p).project(camera);
      const canvas = $('world3');
      return [(v.x + 1) / 2 * canvas.clientWidth, (1 - v.y) / 2 * canvas.clientHeight];
    },
  };
  $('status').textContent = 'ready';
  requestAnimationFrame(frame);
}

main().catch((e) => {
  $('status').textContent = `error: ${e.message}`;
  console.error(e);
});
