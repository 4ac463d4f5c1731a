// The 3D page (gjk3d.html): two 3D shapes, the Minkowski difference of their cores, GJK's
// simplex (up to the tetrahedron) and EPA's polytope, drawn with three.js (WebGL). Every
// number shown comes from the library (qk3_analyze in web/glue/glue.cpp: the calls `quack
// query` makes for a 3D line), and so do the per-iteration pictures: the library's own 3D
// GJK and EPA record every pass (Gjk3Trace, Epa3Trace); the page shows whether the traced
// calls returned the same answers as the plain ones, bit for bit.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { ConvexGeometry } from 'three/addons/geometries/ConvexGeometry.js';
import { material, lineMaterial, triangles, shapeObject } from './three-shapes.js';
import { loadQuack, fmt, fmtVec3 } from './common.js';
import { PRESETS3 } from './shapes3.js';

const COLOR_A = 0x4c72b0;
const COLOR_B = 0xdd8452;
const GREY = 0x8c8c8c;
const RED = 0xc44e52;
const PURPLE = 0x8172b3;
const GREEN = 0x2ca02c;
const BLACK = 0x111111;

const state = {
  paused: false,
  t: 0,
  animate: true,
  // Base poses; with `animate`, B runs a small loop through A and turns while time runs.
  base: [
    { pos: [-0.6, 0, 0], quat: [0, 0, 0, 1] },
    { pos: [0.9, 0.25, 0.1], quat: [0.1, 0.25, 0.05, 0.96] },
  ],
  shapes: [PRESETS3.hull, PRESETS3.box],
  outlines: [null, null],
  step: null, // null: the final answer; k: the k-th GJK/EPA iteration
  selected: 1,
  result: null,
  key: '',
  drawnKey: '',
  drawn: { simplex: 0, polytopeFaces: 0 },
};

const $ = (id) => document.getElementById(id);
let quack;

// ---- poses ------------------------------------------------------------------------------

const quatOf = (q) => new THREE.Quaternion(q[0], q[1], q[2], q[3]).normalize();
const arr = (v) => [v.x, v.y, v.z];
const round = (x) => Number(x.toFixed(6));

// The path's offset at time t: a loop through A for B and a turn about a tilted axis.
function offset(t) {
  const turn = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0.3, 1, 0.2).normalize(), 0.4 * t);
  return { pos: [0.9 * (Math.cos(0.5 * t) - 1), 0.35 * Math.sin(t), 0.25 * Math.sin(0.7 * t)], turn };
}

function poses() {
  const [a, b] = state.base;
  if (!state.animate) return [a, b];
  const o = offset(state.t);
  const q = o.turn.multiply(quatOf(b.quat));
  return [a, {
    pos: [round(b.pos[0] + o.pos[0]), round(b.pos[1] + o.pos[1]), round(b.pos[2] + o.pos[2])],
    quat: [round(q.x), round(q.y), round(q.z), round(q.w)],
  }];
}

// Makes the shown poses the base ones (before a drag or a turn while the path runs).
function freezePath() {
  if (!state.animate) return;
  state.base = poses();
  state.animate = false;
  $('animate').checked = false;
}

function setShape(slot, shape) {
  const r = quack.setShape3(slot, shape);
  if (r.error) return r.error;
  state.shapes[slot] = shape;
  state.outlines[slot] = r.shape;
  const preset = Object.keys(PRESETS3).find((n) => PRESETS3[n] === shape);
  if (preset) $(slot === 0 ? 'shape-a' : 'shape-b').value = preset;
  state.key = '';
  buildShapeMesh(slot);
  return null;
}

function analyze(pa, pb) {
  const key = JSON.stringify([pa, pb, state.shapes]);
  if (key !== state.key) {
    state.result = quack.analyze3(pa, pb);
    if (state.result.error) throw new Error(state.result.error);
    state.key = key;
  }
  return state.result;
}

function steps(result) {
  const list = result.gjk.steps.map((s, i) => ({ kind: 'GJK', i, n: result.gjk.steps.length, s }));
  if (result.epa.ran) {
    result.epa.steps.forEach((s, i) => list.push({ kind: 'EPA', i, n: result.epa.steps.length, s }));
  }
  return list;
}

// ---- three.js scenes ----------------------------------------------------------------------

function makeView(canvas, cameraPos) {
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setClearColor(0xfbfaf7);
  const scene = new THREE.Scene();
  scene.add(new THREE.AmbientLight(0xffffff, 1.2));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(3, 5, 4);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(45, canvas.width / canvas.height, 0.01, 100);
  camera.position.set(...cameraPos);
  const dynamic = new THREE.Group();
  scene.add(dynamic);
  return { canvas, renderer, scene, camera, dynamic, controls: null };
}

function dot(group, p, color, size = 0.035) {
  const m = new THREE.Mesh(new THREE.SphereGeometry(size, 12, 8), material(color, 1));
  m.position.set(...p);
  group.add(m);
}

function segment(group, p, q, color) {
  const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(...p), new THREE.Vector3(...q)]);
  group.add(new THREE.Line(g, lineMaterial(color)));
}

function arrow(group, from, vec, color) {
  const v = new THREE.Vector3(...vec);
  const len = v.length();
  if (!(len > 1e-9)) return;
  const head = Math.min(0.12, 0.4 * len);
  group.add(new THREE.ArrowHelper(v.normalize(), new THREE.Vector3(...from), len, color, head, 0.5 * head));
}

let view; // the shapes
let mink; // B - A
const shapeMeshes = [null, null];

function buildShapeMesh(slot) {
  if (!view) return;
  if (shapeMeshes[slot]) view.scene.remove(shapeMeshes[slot]);
  shapeMeshes[slot] = shapeObject(state.outlines[slot], slot === 0 ? COLOR_A : COLOR_B);
  shapeMeshes[slot].userData.slot = slot;
  view.scene.add(shapeMeshes[slot]);
}

function clearGroup(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    child.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
  }
}

// A point of a shape frame placed by a pose, world frame.
function place(pose, p) {
  return arr(new THREE.Vector3(...p).applyQuaternion(quatOf(pose.quat)).add(new THREE.Vector3(...pose.pos)));
}

// The core of B - A: every difference of B's core points and A's, as a hull when it has
// volume (else the points and segments).
function drawCoreDifference(group, pa, pb) {
  const a = state.outlines[0].points.map((p) => place(pa, p));
  const b = state.outlines[1].points.map((p) => place(pb, p));
  const diff = [];
  for (const q of b) for (const p of a) diff.push([q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
  let solid = false;
  if (diff.length >= 4) {
    try {
      const g = new ConvexGeometry(diff.map((p) => new THREE.Vector3(...p)));
      if (g.getAttribute('position').count >= 12) {
        group.add(new THREE.Mesh(g, material(GREY, 0.15)));
        group.add(new THREE.LineSegments(new THREE.EdgesGeometry(g, 1), lineMaterial(0xb0b0b0)));
        solid = true;
      }
    } catch {
      solid = false; // flat: drawn as points below
    }
  }
  if (!solid) {
    for (const p of diff) dot(group, p, GREY, 0.02);
    for (let i = 0; i + 1 < diff.length; ++i) segment(group, diff[i], diff[i + 1], GREY);
  }
}

// GJK's simplex (1 to 4 points of B - A) with its closest point and the next support point.
function drawSimplex(s, showSupport) {
  const g = mink.dynamic;
  const w = s.simplex.map((v) => v.w);
  for (const p of w) dot(g, p, RED, 0.04);
  if (w.length === 2) segment(g, w[0], w[1], RED);
  if (w.length === 3) triangles(g, w, [[0, 1, 2]], RED, 0.35);
  if (w.length === 4) triangles(g, w, [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]], RED, 0.3);
  dot(g, s.closest, RED, 0.025);
  segment(g, [0, 0, 0], s.closest, RED);
  if (showSupport && s.support) {
    arrow(g, [0, 0, 0], s.direction.map((x) => -0.5 * x), BLACK);
    dot(g, s.support.w, BLACK, 0.045);
  }
  // The points of A and B that make each simplex vertex.
  for (const v of s.simplex) {
    dot(view.dynamic, v.a, RED, 0.03);
    dot(view.dynamic, v.b, RED, 0.03);
    segment(view.dynamic, v.a, v.b, RED);
  }
  return w.length;
}

// EPA's polytope, its nearest face (darker), that face's normal at its distance, and the
// support point along it.
function drawPolytope(s, showSupport) {
  const g = mink.dynamic;
  triangles(g, s.vertices, s.faces, PURPLE, 0.2);
  triangles(g, s.vertices, [s.faces[s.nearest]], PURPLE, 0.6);
  for (const p of s.vertices) dot(g, p, PURPLE, 0.025);
  arrow(g, [0, 0, 0], s.normal.map((x) => x * s.distance), GREEN);
  if (showSupport && s.support) dot(g, s.support.w, BLACK, 0.045);
  return s.faces.length;
}

function drawDynamic(r, pa, pb, current) {
  clearGroup(view.dynamic);
  clearGroup(mink.dynamic);
  mink.dynamic.add(new THREE.AxesHelper(0.4));
  dot(mink.dynamic, [0, 0, 0], BLACK, 0.03);
  drawCoreDifference(mink.dynamic, pa, pb);
  const drawn = { simplex: 0, polytopeFaces: 0 };
  if (current && current.kind === 'GJK') {
    drawn.simplex = drawSimplex(current.s, true);
  } else if (current) {
    drawn.polytopeFaces = drawPolytope(current.s, true);
  } else {
    const last = r.gjk.steps[r.gjk.steps.length - 1];
    if (last) drawn.simplex = drawSimplex(last, false);
    if (r.epa.ran) drawn.polytopeFaces = drawPolytope(r.epa.steps[r.epa.steps.length - 1], false);
    // The separation vector (pointB - pointA: the distance when apart, the depth when
    // overlapping), and the two points on the shapes.
    const p = r.penetration.overlap ? r.penetration : r.distance;
    const sep = [0, 1, 2].map((k) => p.pointB[k] - p.pointA[k]);
    arrow(mink.dynamic, [0, 0, 0], sep, GREEN);
    dot(view.dynamic, p.pointA, GREEN, 0.04);
    dot(view.dynamic, p.pointB, GREEN, 0.04);
    segment(view.dynamic, p.pointA, p.pointB, GREEN);
  }
  state.drawn = drawn;
}

// ---- the panel ------------------------------------------------------------------------------

function show(id, text) {
  $(id).textContent = text;
}

function updatePanel(r, list, current) {
  show('run-state', state.paused ? 'paused' : 'running');
  show('selected', state.selected === 0 ? 'A' : 'B');
  show('overlap', String(r.penetration.overlap));
  show('distance', fmt(r.distance.distance));
  show('depth', fmt(r.penetration.depth));
  const p = r.penetration.overlap ? r.penetration : r.distance;
  show('normal', fmtVec3(p.normal));
  show('point-a', fmtVec3(p.pointA));
  show('point-b', fmtVec3(p.pointB));
  show('gjk-iterations', `${r.distance.iterations} (${r.distance.status})`);
  show('epa-iterations', `${r.epa.ran ? r.epa.steps.length : 0} (${r.penetration.status})`);
  show('stepping', current ? `${current.kind} iteration ${current.i + 1} of ${current.n}` +
    ` (${state.step + 1}/${list.length})` : 'final answer');
  show('drawn', `simplex ${state.drawn.simplex} vertices, polytope ${state.drawn.polytopeFaces} faces`);
  const ok = r.traceAgrees.gjk && r.traceAgrees.epa;
  show('trace-check', ok ? 'agrees' : `differs (gjk ${r.traceAgrees.gjk}, epa ${r.traceAgrees.epa})`);
  $('trace-check').className = ok ? 'num ok' : 'num err';
}

// ---- the frame --------------------------------------------------------------------------

function render() {
  const [pa, pb] = poses();
  const r = analyze(pa, pb);
  const list = steps(r);
  if (state.step !== null) state.step = Math.min(state.step, list.length - 1);
  const current = state.step === null ? null : list[state.step];
  const drawnKey = JSON.stringify([state.key, state.step]);
  if (drawnKey !== state.drawnKey) {
    drawDynamic(r, pa, pb, current);
    state.drawnKey = drawnKey;
  }
  [pa, pb].forEach((pose, slot) => {
    shapeMeshes[slot].position.set(...pose.pos);
    shapeMeshes[slot].quaternion.copy(quatOf(pose.quat));
  });
  updatePanel(r, list, current);
  view.controls.update();
  mink.controls.update();
  view.renderer.render(view.scene, view.camera);
  mink.renderer.render(mink.scene, mink.camera);
}

let last = null;
function frame(now) {
  const dt = last === null ? 0 : Math.min(0.1, (now - last) / 1000);
  last = now;
  if (!state.paused && state.step === null && state.animate) state.t += dt;
  render();
  requestAnimationFrame(frame);
}

// ---- input ----------------------------------------------------------------------------------

// Picking and dragging: a press on a shape selects it and drags it in the plane through its
// position facing the camera; a press elsewhere turns the view (OrbitControls). Installed
// before the controls, so a press on a shape never reaches them.
function installDrag() {
  const canvas = view.canvas;
  const ray = new THREE.Raycaster();
  let drag = null;
  const hit = (e) => {
    const box = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - box.left) / box.width) * 2 - 1, -((e.clientY - box.top) / box.height) * 2 + 1);
    ray.setFromCamera(ndc, view.camera);
  };
  canvas.addEventListener('pointerdown', (e) => {
    hit(e);
    const meshes = shapeMeshes.filter(Boolean);
    const found = ray.intersectObjects(meshes, true).find((x) => x.object.type === 'Mesh');
    if (!found) return;
    let o = found.object;
    while (o.userData.slot === undefined) o = o.parent;
    state.selected = o.userData.slot;
    freezePath();
    const pos = new THREE.Vector3(...state.base[state.selected].pos);
    const normal = view.camera.getWorldDirection(new THREE.Vector3());
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, pos);
    const at = ray.ray.intersectPlane(plane, new THREE.Vector3());
    drag = { plane, grab: at ? pos.clone().sub(at) : new THREE.Vector3() };
    canvas.setPointerCapture(e.pointerId);
    e.stopImmediatePropagation();
    e.preventDefault();
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    hit(e);
    const at = ray.ray.intersectPlane(drag.plane, new THREE.Vector3());
    if (!at) return;
    state.base[state.selected].pos = arr(at.add(drag.grab)).map(round);
    e.stopImmediatePropagation();
  });
  const end = (e) => {
    if (!drag) return;
    drag = null;
    e.stopImmediatePropagation();
  };
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
}

const TURN_KEYS = { q: [1, 0, 0, 1], e: [1, 0, 0, -1], r: [0, 1, 0, 1], f: [0, 1, 0, -1], t: [0, 0, 1, 1], g: [0, 0, 1, -1] };

function turnSelected(key) {
  freezePath();
  const [x, y, z, sign] = TURN_KEYS[key];
  const turn = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(x, y, z), sign * 0.1);
  const q = turn.multiply(quatOf(state.base[state.selected].quat));
  state.base[state.selected].quat = [q.x, q.y, q.z, q.w].map(round);
}

function installKeys() {
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLTextAreaElement || e.target instanceof HTMLSelectElement) return;
    const key = e.key.length === 1 ? e.key.toLowerCase() : e.key;
    switch (key) {
      case ' ': state.paused = !state.paused; break;
      case 's':
      case '.':
        state.paused = true;
        state.step = state.step === null ? 0 : state.step + 1;
        break;
      case ',': state.paused = true; state.step = Math.max(0, (state.step ?? 1) - 1); break;
      case 'Escape': state.step = null; break;
      default:
        if (TURN_KEYS[key]) turnSelected(key);
        else return;
    }
    e.preventDefault();
    // Draw now rather than at the next frame, so that the panel shows the step as soon as
    // the key is handled (as the 2D page does); a reader of #stepping never sees the old one.
    render();
  });
}

function installControls() {
  for (const [slot, id] of [[0, 'shape-a'], [1, 'shape-b']]) {
    const select = $(id);
    for (const name of Object.keys(PRESETS3)) select.add(new Option(name, name));
    select.value = Object.keys(PRESETS3).find((n) => PRESETS3[n] === state.shapes[slot]);
    select.addEventListener('change', () => setShape(slot, PRESETS3[select.value]));
  }
  $('animate').addEventListener('change', () => {
    if ($('animate').checked) {
      state.animate = true;
      state.t = 0;
    } else {
      freezePath();
    }
  });
  for (const [slot, id] of [[0, 'set-a'], [1, 'set-b']]) {
    $(id).addEventListener('click', () => {
      let shape;
      try {
        shape = JSON.parse($('custom').value);
      } catch (e) {
        $('custom-error').textContent = `not JSON: ${e.message}`;
        return;
      }
      $('custom-error').textContent = setShape(slot, shape) ?? '';
    });
  }
}

async function main() {
  quack = await loadQuack();
  view = makeView($('scene3'), [1.8, 1.6, 3.4]);
  mink = makeView($('minkowski3'), [1.6, 1.4, 3.0]);
  installDrag();
  view.controls = new OrbitControls(view.camera, view.canvas);
  mink.controls = new OrbitControls(mink.camera, mink.canvas);
  // B - A lies around pB - pA: look at the middle of it and the origin, from far enough.
  mink.controls.target.set(0.7, 0.1, 0.05);
  mink.camera.position.set(0.7 + 2.4, 0.1 + 2.2, 0.05 + 4.6);
  for (const slot of [0, 1]) {
    const err = setShape(slot, state.shapes[slot]);
    if (err) throw new Error(err);
  }
  installKeys();
  installControls();
  render();
  $('status').textContent = 'ready';
  requestAnimationFrame(frame);

  // For the browser tests (web/tests/gjk3d_page.test.mjs).
  window.quackDemo3 = {
    state: () => ({ paused: state.paused, t: state.t, step: state.step, animate: state.animate, selected: state.selected }),
    result: () => state.result,
    poses,
    drawn: () => ({ ...state.drawn }),
    setShapes: (a, b) => {
      for (const [slot, s] of [[0, a], [1, b]]) {
        const err = setShape(slot, s);
        if (err) throw new Error(err);
      }
      render();
    },
    // Fixed poses: the path stops, so the page analyses exactly these.
    setPoses: (pa, pb) => {
      state.animate = false;
      $('animate').checked = false;
      state.base = [structuredClone(pa), structuredClone(pb)];
      render();
    },
    // Where a world point lands on the scene canvas, in CSS pixels.
    toCanvas: (p) => {
      const v = new THREE.Vector3(...p).project(view.camera);
      const box = view.canvas.getBoundingClientRect();
      return [(v.x + 1) / 2 * box.width, (1 - v.y) / 2 * box.height];
    },
  };
}

main().catch((e) => {
  $('status').textContent = `failed: ${e}`;
  $('status').className = 'err';
  console.error(e);
});
