// Page 1: two shapes, their Minkowski difference B - A, and GJK and EPA at work.
// Every number shown comes from the library (qk_analyze in web/glue/glue.cpp), and so do
// the per-iteration pictures: the library's own GJK and EPA record every pass (GjkTrace,
// EpaTrace); the page shows whether each trace's last pass is the answer, bit for bit.
import { loadQuack, View, drawShape, place, fmt, fmtVec } from './common.js';
import { PRESETS } from './shapes.js';

// Time scales the arrow keys move through (negative runs time backwards).
const SCALES = [-4, -2, -1, -0.5, -0.25, 0, 0.25, 0.5, 1, 2, 4];

const state = {
  paused: false,
  scaleIndex: SCALES.indexOf(1),
  t: 0,
  animate: true,
  // Base poses; with `animate`, B moves along a figure-of-eight through A and both turn.
  base: [{ pos: [-1.3, 0], angle: 0.2 }, { pos: [1.4, 0.2], angle: 0.5 }],
  shapes: [PRESETS['pentagon'], PRESETS['box']],
  pieces: [null, null], // each shape's convex pieces' outlines (one for a convex shape)
  step: null, // null: the final answer; k: the k-th GJK/EPA iteration
  active: 1,
  result: null,
  key: '',
};

function poses() {
  const [a, b] = state.base;
  if (!state.animate) return [a, b];
  const t = state.t;
  return [
    { pos: a.pos, angle: a.angle - 0.15 * t },
    { pos: [b.pos[0] + 2.7 * (Math.cos(0.5 * t) - 1), b.pos[1] + 1.2 * Math.sin(t)], angle: b.angle + 0.4 * t },
  ];
}

let quack;
let scene;
let mink;
const $ = (id) => document.getElementById(id);

function setShape(slot, shape) {
  const r = quack.setShape(slot, shape);
  if (r.error) return r.error;
  state.shapes[slot] = shape;
  state.pieces[slot] = r.pieces;
  state.key = '';
  return null;
}

function steps(result) {
  const list = result.gjk.steps.map((s, i) => ({ kind: 'GJK', i, n: result.gjk.steps.length, s }));
  if (result.epa.ran) {
    result.epa.steps.forEach((s, i) => list.push({ kind: 'EPA', i, n: result.epa.steps.length, s }));
  }
  return list;
}

function analyze(pa, pb) {
  const key = JSON.stringify([pa, pb]);
  if (key !== state.key) {
    state.result = quack.analyze(pa, pb);
    state.key = key;
  }
  return state.result;
}

// ---- drawing -----------------------------------------------------------------------------

const COLOR_A = ['rgba(76,114,176,0.35)', '#4c72b0'];
const COLOR_B = ['rgba(221,132,82,0.35)', '#dd8452'];
const RED = '#c44e52';
const PURPLE = '#8172b3';
const GREEN = '#2ca02c';

function drawScene(r, pa, pb, current) {
  scene.clear();
  scene.grid(1);
  for (const o of r.piecesA) drawShape(scene, o, pa, ...COLOR_A);
  for (const o of r.piecesB) drawShape(scene, o, pb, ...COLOR_B);
  scene.label(pa.pos, 'A', COLOR_A[1], -4, 4);
  scene.label(pb.pos, 'B', COLOR_B[1], -4, 4);
  if (current) {
    // The shape points that make the current simplex or polytope vertices.
    const verts = current.kind === 'GJK' ? current.s.simplex : current.s.polytope;
    for (const v of verts) {
      scene.dot(v.a, COLOR_A[1], 4);
      scene.dot(v.b, COLOR_B[1], 4);
      scene.line(v.a, v.b, current.kind === 'GJK' ? RED : PURPLE, 1, [4, 3]);
    }
    if (current.s.support) {
      scene.dot(current.s.support.a, '#000', 3);
      scene.dot(current.s.support.b, '#000', 3);
    }
    return;
  }
  const p = r.penetration.overlap ? r.penetration : r.distance;
  scene.line(p.pointA, p.pointB, GREEN, 2);
  scene.dot(p.pointA, COLOR_A[1], 4);
  scene.dot(p.pointB, COLOR_B[1], 4);
  const n = p.normal;
  if (n[0] !== 0 || n[1] !== 0) {
    scene.arrow(p.pointA, [p.pointA[0] + 0.6 * n[0], p.pointA[1] + 0.6 * n[1]], GREEN, 2);
  }
  for (const m of r.manifold.points) {
    scene.dot(m.point, '#000', 5);
    scene.label(m.point, fmt(m.separation, 3), '#000', 7, 14);
  }
}

function fitMinkowski(r) {
  // Fit B - A and the origin, with the scale on steps of 1.25x so that it does not jitter.
  let m = 1;
  for (const p of r.minkowski.points) m = Math.max(m, Math.abs(p[0]), Math.abs(p[1]) * 2);
  m += r.minkowski.radius + 0.3;
  const fit = (0.5 * mink.canvas.width) / m;
  mink.scale = Math.min(80, Math.pow(1.25, Math.floor(Math.log(fit) / Math.log(1.25))));
}

function drawMinkowski(r, current) {
  fitMinkowski(r);
  mink.clear();
  mink.grid(1);
  const hull = r.minkowski.points;
  mink.roundedHull(hull, r.minkowski.radius, 'rgba(140,140,140,0.25)', '#8c8c8c');
  if (r.minkowski.radius > 0 && hull.length > 1) {
    mink.ctx.save();
    mink.ctx.setLineDash([4, 4]);
    mink.path(hull, true);
    mink.ctx.strokeStyle = '#8c8c8c';
    mink.ctx.stroke();
    mink.ctx.restore();
  }
  mink.line([-0.25, 0], [0.25, 0], '#000', 1.5);
  mink.line([0, -0.25], [0, 0.25], '#000', 1.5);
  mink.label([0, 0], 'O', '#000', 4, 14);
  mink.label([0, 0], 'B − A', '#666', -mink.canvas.width / 2 + 12, -mink.canvas.height / 2 + 20);

  const gjkSteps = r.gjk.steps;
  if (current && current.kind === 'GJK') {
    drawSimplex(current.s, RED, true);
    if (current.s.support) {
      const d = current.s.direction;
      mink.arrow([0, 0], [-0.8 * d[0], -0.8 * d[1]], RED, 1.5);
      mink.ctx.strokeStyle = RED;
      const [x, y] = mink.toCanvas(current.s.support.w);
      mink.ctx.beginPath(); mink.ctx.arc(x, y, 7, 0, 2 * Math.PI); mink.ctx.stroke();
      mink.label(current.s.support.w, 'new support', RED, 9, 4);
    }
    return;
  }
  if (current && current.kind === 'EPA') {
    drawSimplex(gjkSteps[gjkSteps.length - 1], 'rgba(196,78,82,0.4)', false);
    drawPolytope(current.s, true);
    return;
  }
  // Final answer: GJK's last simplex, EPA's last polytope, the separation vector.
  drawSimplex(gjkSteps[gjkSteps.length - 1], RED, false);
  if (r.epa.ran) drawPolytope(r.epa.steps[r.epa.steps.length - 1], false);
  const p = r.penetration.overlap ? r.penetration : r.distance;
  const sep = [p.pointB[0] - p.pointA[0], p.pointB[1] - p.pointA[1]];
  if (Math.hypot(sep[0], sep[1]) > 1e-6) mink.arrow([0, 0], sep, GREEN, 2.5);
  mink.dot(sep, GREEN, 4);
}

function drawSimplex(s, color, detailed) {
  const pts = s.simplex.map((v) => v.w);
  mink.ctx.save();
  mink.path(pts, pts.length > 2);
  mink.ctx.strokeStyle = color;
  mink.ctx.lineWidth = 2.5;
  mink.ctx.stroke();
  if (pts.length === 3) { mink.ctx.fillStyle = 'rgba(196,78,82,0.12)'; mink.ctx.fill(); }
  mink.ctx.restore();
  pts.forEach((p, i) => {
    mink.dot(p, color, 4);
    if (detailed) mink.label(p, `w${i} (λ=${fmt(s.simplex[i].weight, 2)})`, color);
  });
  if (Math.hypot(s.closest[0], s.closest[1]) > 1e-9) {
    mink.line([0, 0], s.closest, color, 1, [3, 3]);
    mink.dot(s.closest, color, 3);
    if (detailed) mink.label(s.closest, 'v', color, 6, 14);
  }
}

function drawPolytope(s, detailed) {
  const pts = s.polytope.map((v) => v.w);
  mink.ctx.save();
  mink.path(pts, true);
  mink.ctx.strokeStyle = PURPLE;
  mink.ctx.lineWidth = 2;
  mink.ctx.stroke();
  mink.ctx.fillStyle = 'rgba(129,114,179,0.10)';
  mink.ctx.fill();
  mink.ctx.restore();
  for (const p of pts) mink.dot(p, PURPLE, 3.5);
  const e0 = pts[s.edge];
  const e1 = pts[(s.edge + 1) % pts.length];
  mink.line(e0, e1, PURPLE, 5);
  const foot = [s.normal[0] * s.distance, s.normal[1] * s.distance];
  mink.arrow(foot, [foot[0] + 0.5 * s.normal[0], foot[1] + 0.5 * s.normal[1]], PURPLE, 1.5);
  if (detailed) {
    mink.label(foot, `nearest edge, d=${fmt(s.distance, 4)}`, PURPLE, 8, 16);
    if (s.support) {
      const [x, y] = mink.toCanvas(s.support.w);
      mink.ctx.strokeStyle = PURPLE;
      mink.ctx.beginPath(); mink.ctx.arc(x, y, 7, 0, 2 * Math.PI); mink.ctx.stroke();
      mink.label(s.support.w, 'new support', PURPLE, 9, 4);
    }
  }
}

// ---- numbers -----------------------------------------------------------------------------

function show(id, text, value) {
  const el = $(id);
  if (el.textContent !== text) el.textContent = text;
  if (value !== undefined) el.dataset.value = String(value);
}

function showNumbers(r, current, list) {
  const scale = SCALES[state.scaleIndex];
  show('run-state', state.paused ? 'paused' : 'running');
  show('time-scale', `${scale}×`, scale);
  show('overlap', String(r.penetration.overlap));
  show('distance', fmt(r.distance.distance), r.distance.distance);
  show('depth', fmt(r.penetration.depth), r.penetration.depth);
  const p = r.penetration.overlap ? r.penetration : r.distance;
  show('normal', fmtVec(p.normal));
  show('point-a', fmtVec(p.pointA));
  show('point-b', fmtVec(p.pointB));
  show('gjk-iterations', `${r.distance.iterations} (${r.distance.status})`, r.distance.iterations);
  const epaIterations = r.penetration.iterations - r.distance.iterations;
  show('epa-iterations', `${r.epa.ran ? epaIterations : 0} (${r.penetration.status})`, epaIterations);
  show('contacts', r.manifold.points.length === 0 ? 'none' :
    r.manifold.points.map((m) => `${fmtVec(m.point, 3)} sep ${fmt(m.separation, 3)}`).join('; '));
  show('stepping', current ? `${current.kind} iteration ${current.i + 1} of ${current.n}` +
    ` (${state.step + 1}/${list.length})` : 'final answer');
  const ok = r.traceAgrees.gjk && r.traceAgrees.epa;
  show('trace-check', ok ? 'agrees' : `differs (gjk ${r.traceAgrees.gjk}, epa ${r.traceAgrees.epa})`);
  $('trace-check').className = `num ${ok ? 'ok' : 'err'}`;
}

// ---- the loop ----------------------------------------------------------------------------

let last = null;
function frame(now) {
  const dt = last === null ? 0 : Math.min(0.1, (now - last) / 1000);
  last = now;
  if (!state.paused) state.t += dt * SCALES[state.scaleIndex];
  render();
  requestAnimationFrame(frame);
}

function render() {
  const [pa, pb] = poses();
  const r = analyze(pa, pb);
  const list = steps(r);
  if (state.step !== null) state.step = Math.min(state.step, list.length - 1);
  const current = state.step === null ? null : list[state.step];
  drawScene(r, pa, pb, current);
  drawMinkowski(r, current);
  showNumbers(r, current, list);
}

// ---- input -------------------------------------------------------------------------------

function hullDistance(pts, radius, p) {
  // Distance from p to the rounded hull of pts (0 inside).
  let inside = pts.length >= 3;
  let best = Infinity;
  for (let i = 0; i < pts.length; ++i) {
    const a = pts[i];
    const b = pts[(i + 1) % pts.length];
    const e = [b[0] - a[0], b[1] - a[1]];
    const ee = e[0] * e[0] + e[1] * e[1];
    const t = ee > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / ee)) : 0;
    best = Math.min(best, Math.hypot(p[0] - a[0] - t * e[0], p[1] - a[1] - t * e[1]));
    if (e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0]) < 0) inside = false;
  }
  return inside ? 0 : Math.max(0, best - radius);
}

function shapeAt(p) {
  const ps = poses();
  for (const slot of [1, 0]) {
    for (const o of state.pieces[slot]) {
      if (hullDistance(o.points.map((q) => place(ps[slot], q)), o.radius, p) < 0.15) return slot;
    }
  }
  return -1;
}

function rotateActive(delta) {
  state.base[state.active].angle += delta;
}

function installInput() {
  let drag = null;
  scene.canvas.addEventListener('mousedown', (e) => {
    const p = scene.toWorld(e.offsetX, e.offsetY);
    const slot = shapeAt(p);
    drag = { slot, x: e.offsetX, y: e.offsetY, moved: false, last: p };
    if (slot >= 0) state.active = slot;
  });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const rect = scene.canvas.getBoundingClientRect();
    const x = e.clientX - rect.left;
    const y = e.clientY - rect.top;
    if (Math.hypot(x - drag.x, y - drag.y) > 4) drag.moved = true;
    if (drag.moved && drag.slot >= 0) {
      const p = scene.toWorld(x, y);
      const b = state.base[drag.slot];
      b.pos = [b.pos[0] + p[0] - drag.last[0], b.pos[1] + p[1] - drag.last[1]];
      drag.last = p;
    }
  });
  window.addEventListener('mouseup', () => {
    if (drag && !drag.moved) togglePause();
    drag = null;
  });
  mink.canvas.addEventListener('click', togglePause);
  scene.canvas.addEventListener('wheel', (e) => {
    const slot = shapeAt(scene.toWorld(e.offsetX, e.offsetY));
    if (slot < 0) return;
    e.preventDefault();
    state.active = slot;
    rotateActive(e.deltaY > 0 ? 0.05 : -0.05);
  }, { passive: false });
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLTextAreaElement || e.target instanceof HTMLInputElement) return;
    const handled = true;
    switch (e.key) {
      case 'ArrowRight': state.scaleIndex = Math.min(SCALES.length - 1, state.scaleIndex + 1); break;
      case 'ArrowLeft': state.scaleIndex = Math.max(0, state.scaleIndex - 1); break;
      case ' ': togglePause(); break;
      case 's': case 'S': case '.':
        state.paused = true;
        state.step = state.step === null ? 0 : state.step + 1;
        break;
      case ',': state.paused = true; state.step = Math.max(0, (state.step ?? 1) - 1); break;
      case 'Escape': state.step = null; break;
      case 'q': case 'Q': rotateActive(0.05); break;
      case 'e': case 'E': rotateActive(-0.05); break;
      default: return;
    }
    if (handled) e.preventDefault();
    render();
  });
  for (const slot of [0, 1]) {
    const select = $(slot === 0 ? 'shape-a' : 'shape-b');
    for (const name of Object.keys(PRESETS)) select.add(new Option(name, name));
    select.value = slot === 0 ? 'pentagon' : 'box';
    select.addEventListener('change', () => setShape(slot, PRESETS[select.value]));
    $(slot === 0 ? 'set-a' : 'set-b').addEventListener('click', () => {
      let error;
      try {
        error = setShape(slot, JSON.parse($('custom').value));
      } catch (ex) {
        error = `not JSON: ${ex.message}`;
      }
      $('custom-error').textContent = error ?? '';
    });
  }
  $('animate').addEventListener('change', (e) => {
    // Keep the shapes where they are when the path stops.
    if (!e.target.checked) state.base = poses();
    else state.t = 0;
    state.animate = e.target.checked;
  });
}

function togglePause() {
  state.paused = !state.paused;
  render();
}

async function main() {
  quack = await loadQuack();
  scene = new View($('scene'), 70);
  mink = new View($('minkowski'), 50);
  setShape(0, state.shapes[0]);
  setShape(1, state.shapes[1]);
  installInput();
  $('status').textContent = 'ready';
  // For the browser tests and the curious: read the state, place the shapes exactly.
  window.quackDemo = {
    state: () => ({ paused: state.paused, timeScale: SCALES[state.scaleIndex], t: state.t,
      step: state.step, animate: state.animate }),
    result: () => state.result,
    poses: () => poses(),
    toCanvas: (p) => scene.toCanvas(p),
    setShapes: (a, b) => setShape(0, a) ?? setShape(1, b),
    setAnimate: (on) => { if (!on) state.base = poses(); state.animate = on; $('animate').checked = on; },
    setPoses: (pa, pb) => { state.base = [pa, pb]; state.animate = false; $('animate').checked = false; render(); },
    render,
  };
  requestAnimationFrame(frame);
}

main().catch((e) => {
  $('status').textContent = `failed: ${e}`;
  $('status').className = 'err';
  console.error(e);
});
