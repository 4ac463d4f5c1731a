// Page 2: a sandbox World. Click to drop shapes, or on a sleeping body to wake it; press on
// a body and drag to pull it with a mouse joint; drop in a chain, a car (driven with the
// arrow keys) or a ragdoll. The page draws the bodies (sleeping ones faded), the joints, the
// fat boxes of the broad phase, the touching contacts and flashes the events of each step.
import { loadQuack, View, drawShape, fmt } from './common.js';
import { PRESETS } from './shapes.js';

const $ = (id) => document.getElementById(id);
const DT = 1 / 60;
// Sleeping bodies are drawn at this opacity (static bodies, never awake, are not faded).
const SLEEPING_ALPHA = 0.35;
// How far from a click (pixels) a sleeping body still counts as clicked.
const PICK_PIXELS = 3;
// How far (pixels) the pointer must move while pressed before a press becomes a drag: a
// press that stays put is a click (drop a shape, or wake a sleeping body).
const DRAG_PIXELS = 4;
// The cars' wheel speed while an arrow key (or drive button) is held, rad/s: 12 rad/s on
// 0.32 m wheels is about 4 m/s.
const DRIVE_SPEED = 12;
// Where the drop-ins land: the chain hangs from the top left (laid level, it swings down
// across the view), the car stands on the ground at the left, the ragdoll falls in the middle.
const DROP_AT = { chain: [-2.5, 4.4], car: [-3.5, -2.7], ragdoll: [0.5, 2.5] };
const JOINT_COLOUR = '#2a9d8f';
const MOUSE_COLOUR = '#e76f51';
const PALETTE = ['#4c72b0', '#dd8452', '#55a868', '#c44e52', '#8172b3', '#937860', '#da8bc3', '#8c8c8c'];

let quack;
let view;
const state = { paused: false, events: [], flashes: [], counts: [0, 0, 0], world: null, lastRain: 0 };
// The pointer: where it was pressed (canvas pixels and world), whether that became a drag
// (and grabbed a body), and whether the click that follows a drag is to be ignored.
const pointer = { down: null, dragging: false, grabbed: null, swallowClick: false };

function reset() {
  const r = quack.worldReset($('broadphase').value);
  if (r.error) throw new Error(r.error);
  // Ground and two walls, and two obstacles (a segment and a capsule), all static.
  quack.worldAdd({ type: 'box', half: [5.5, 0.25] }, 0, [0, -3.8], 0, [0, 0], 0);
  quack.worldAdd({ type: 'box', half: [0.25, 3] }, 0, [-5.5, -1], 0, [0, 0], 0);
  quack.worldAdd({ type: 'box', half: [0.25, 3] }, 0, [5.5, -1], 0, [0, 0], 0);
  quack.worldAdd({ type: 'segment', p1: [-1.5, 0], p2: [1.5, 0] }, 0, [-2, -1.2], -0.25, [0, 0], 0);
  quack.worldAdd({ type: 'capsule', p1: [-1, 0], p2: [1, 0], radius: 0.15 }, 0, [2.2, -0.4], 0.3, [0, 0], 0);
  state.events = [];
  state.flashes = [];
  state.counts = [0, 0, 0];
  $('events').textContent = '';
  // A few shapes to start with.
  const names = Object.keys(PRESETS);
  for (let i = 0; i < 6; ++i) drop(names[i % names.length], [-3 + 1.2 * i, 2 + 0.7 * (i % 2)]);
  state.world = quack.worldState();
}

// Drops a dynamic shape at pos (at a random angle unless given); returns its shape index.
function drop(name, pos, angle = Math.random() * 3) {
  const restitution = Number($('restitution').value) || 0;
  const r = quack.worldAdd(PRESETS[name], 2, pos, angle, [0, 0], restitution);
  if (r.error) console.warn(`drop ${name}: ${r.error}`);
  return r.shape;
}

// A click wakes the sleeping bodies under it, or, when there is none, drops a shape.
function click(pos) {
  if (pointer.swallowClick) {
    pointer.swallowClick = false;
    return;
  }
  const r = quack.worldWake(pos, PICK_PIXELS / view.scale);
  if (r.error) throw new Error(r.error);
  if (r.woken.length > 0) {
    logEvent(`${state.world.time.toFixed(2)} woke  ${r.woken.join(', ')}`);
    showEvents();
  } else {
    drop($('drop-shape').value, pos);
  }
  state.world = quack.worldState();
}

// Press, drag, release: past DRAG_PIXELS a press grabs the dynamic body under the point it
// was pressed at (a mouse joint there, qk_world_grab) and pulls it towards the pointer
// until the button is released.
function pointerDown(e) {
  if (e.button !== 0) return;
  pointer.down = { x: e.offsetX, y: e.offsetY, world: view.toWorld(e.offsetX, e.offsetY) };
  pointer.dragging = false;
  pointer.grabbed = null;
  view.canvas.setPointerCapture(e.pointerId);
}

function pointerMove(e) {
  if (!pointer.down) return;
  if (!pointer.dragging) {
    if (Math.hypot(e.offsetX - pointer.down.x, e.offsetY - pointer.down.y) < DRAG_PIXELS) return;
    pointer.dragging = true;
    const r = quack.worldGrab(pointer.down.world, PICK_PIXELS / view.scale);
    if (r.error) throw new Error(r.error);
    pointer.grabbed = r.grabbed;
    if (r.grabbed !== null) logEvent(`${state.world.time.toFixed(2)} grab  ${r.grabbed}`);
  }
  if (pointer.grabbed !== null) quack.worldDrag(view.toWorld(e.offsetX, e.offsetY));
  state.world = quack.worldState();
}

function pointerUp() {
  if (!pointer.down) return;
  if (pointer.grabbed !== null) {
    quack.worldRelease();
    state.world = quack.worldState();
    // The click that ends the drag is not a drop.
    pointer.swallowClick = true;
  }
  pointer.down = null;
  pointer.dragging = false;
  pointer.grabbed = null;
}

// Drops in a chain, a car or a ragdoll (qk_world_drop) at its place; returns the answer
// ({joints, shapes, bodies}).
function dropJointed(kind, at = DROP_AT[kind]) {
  const r = quack.worldDrop(kind, at);
  if (r.error) throw new Error(r.error);
  logEvent(`${state.world.time.toFixed(2)} ${kind}: ${r.shapes.length} bodies, ${r.joints} joints`);
  showEvents();
  state.world = quack.worldState();
  return r;
}

// Sets the cars' wheel motors: -1 drives right (clockwise wheels), 1 left, 0 brakes.
function drive(direction) {
  const wheels = quack.worldDrive(-direction * DRIVE_SPEED);
  $('drive-state').textContent = direction === 0 ? 'braked' : direction > 0 ? 'driving right' : 'driving left';
  return wheels;
}

// Removes every dynamic body (the ground, walls and obstacles stay).
function clear() {
  quack.worldCull(Infinity);
  state.world = quack.worldState();
}

function logEvent(text) {
  state.events.push(text);
  if (state.events.length > 200) state.events.splice(0, state.events.length - 200);
}

function showEvents() {
  const box = $('events');
  box.textContent = state.events.slice(-40).join('\n');
  box.style.whiteSpace = 'pre';
  box.scrollTop = box.scrollHeight;
}

function step() {
  const e = quack.worldStep(DT, 1);
  if (e.error) throw new Error(e.error);
  const t = e.time.toFixed(2);
  for (const [a, b] of e.begin) logEvent(`${t} begin ${a}–${b}`);
  for (const [a, b] of e.end) logEvent(`${t} end   ${a}–${b}`);
  for (const h of e.hit) {
    logEvent(`${t} hit   ${h.a}–${h.b} at ${fmt(h.speed, 3)} m/s`);
    state.flashes.push({ point: h.point, age: 0 });
  }
  state.counts[0] += e.begin.length;
  state.counts[1] += e.end.length;
  state.counts[2] += e.hit.length;
  if (e.begin.length + e.end.length + e.hit.length > 0) showEvents();
  quack.worldCull(-20);
  state.world = quack.worldState();
}

function draw() {
  const w = state.world;
  view.clear();
  view.grid(1);
  const { ctx } = view;
  for (const s of w.shapes) {
    const colour = s.bodyType === 0 ? '#6b6b6b' : PALETTE[s.index % PALETTE.length];
    ctx.globalAlpha = s.bodyType !== 0 && !s.awake ? SLEEPING_ALPHA : 1;
    drawShape(view, s, { pos: s.pos, angle: s.angle }, `${colour}55`, colour);
  }
  ctx.globalAlpha = 1;
  if ($('show-joints').checked) drawJoints(w);
  if ($('show-boxes').checked) {
    ctx.save();
    ctx.strokeStyle = 'rgba(40,160,60,0.8)';
    ctx.setLineDash([3, 3]);
    ctx.lineWidth = 1;
    for (const [x0, y0, x1, y1] of w.fatBoxes) {
      const [cx0, cy0] = view.toCanvas([x0, y1]);
      const [cx1, cy1] = view.toCanvas([x1, y0]);
      ctx.strokeRect(cx0, cy0, cx1 - cx0, cy1 - cy0);
    }
    ctx.restore();
  }
  if ($('show-tree').checked && w.treeBoxes.length > 0) {
    // The tree's internal nodes, the root darkest.
    ctx.save();
    ctx.lineWidth = 1;
    const deepest = Math.max(...w.treeBoxes.map((b) => b[4]), 1);
    for (const [x0, y0, x1, y1, depth] of w.treeBoxes) {
      ctx.strokeStyle = `rgba(60,60,200,${0.85 - 0.6 * depth / deepest})`;
      const [cx0, cy0] = view.toCanvas([x0, y1]);
      const [cx1, cy1] = view.toCanvas([x1, y0]);
      ctx.strokeRect(cx0, cy0, cx1 - cx0, cy1 - cy0);
    }
    ctx.restore();
  }
  if ($('show-contacts').checked) {
    for (const c of w.contacts) {
      for (const p of c.points) {
        view.dot(p.point, '#c00', 3.5);
        view.arrow(p.point, [p.point[0] + 0.35 * c.normal[0], p.point[1] + 0.35 * c.normal[1]], '#c00', 1.2);
      }
    }
  }
  if ($('show-events').checked) {
    for (const f of state.flashes) {
      const [x, y] = view.toCanvas(f.point);
      ctx.strokeStyle = `rgba(255,140,0,${1 - f.age / 30})`;
      ctx.lineWidth = 2;
      ctx.beginPath(); ctx.arc(x, y, 6 + f.age, 0, 2 * Math.PI); ctx.stroke();
    }
  }
  if (!state.paused) {
    state.flashes.forEach((f) => { f.age += 1; });
    state.flashes = state.flashes.filter((f) => f.age < 30);
  }
  const bp = w.broadPhase;
  $('time').textContent = `${fmt(w.time, 4)} s (${w.steps} steps)${state.paused ? ', paused' : ''}`;
  $('bodies').textContent = String(w.bodies);
  $('awake').textContent = `${w.awakeBodies} / ${w.islands}`;
  $('bp').textContent = `${bp.kind}, ${bp.proxies} proxies` +
    (bp.hasTree ? `, tree height ${bp.height}, area ratio ${fmt(bp.areaRatio, 3)}` : '');
  $('contacts').textContent = `${w.contacts.length} / ${w.contactCount}`;
  $('joint-count').textContent = String(w.jointCount);
  $('event-counts').textContent = state.counts.join(' / ');
}

// Every joint as the replays draw it (src/io/replay_page.hpp): body A's centre, its
// anchor, B's anchor, B's centre, in teal, with dots at the anchors. The mouse joint of a
// drag is drawn apart: a line from the pointer's target to the grabbed point.
function drawJoints(w) {
  const { ctx } = view;
  ctx.save();
  ctx.lineWidth = 1.5;
  for (const j of w.joints) {
    if (j.type === 'mouse') continue;
    view.path(j.line, false);
    ctx.strokeStyle = JOINT_COLOUR;
    ctx.stroke();
    view.dot(j.line[1], JOINT_COLOUR, 2.5);
    view.dot(j.line[2], JOINT_COLOUR, 2.5);
  }
  if (w.mouse) {
    view.line(w.mouse.target, w.mouse.point, MOUSE_COLOUR, 2, [5, 3]);
    view.dot(w.mouse.point, MOUSE_COLOUR, 3.5);
    view.dot(w.mouse.target, MOUSE_COLOUR, 2);
  }
  ctx.restore();
}

function frame(now) {
  if (!state.paused) {
    if ($('rain').checked && now - state.lastRain > 400) {
      const names = Object.keys(PRESETS);
      drop(names[Math.floor(Math.random() * names.length)], [-4 + 8 * Math.random(), 4.5]);
      state.lastRain = now;
    }
    step();
  }
  draw();
  requestAnimationFrame(frame);
}

function togglePause() {
  state.paused = !state.paused;
  $('pause').textContent = state.paused ? 'resume' : 'pause';
}

async function main() {
  quack = await loadQuack();
  view = new View($('world'), 60, [0, 0]);
  for (const name of Object.keys(PRESETS)) $('drop-shape').add(new Option(name, name));
  reset();
  view.canvas.addEventListener('click', (e) => click(view.toWorld(e.offsetX, e.offsetY)));
  view.canvas.addEventListener('pointerdown', pointerDown);
  view.canvas.addEventListener('pointermove', pointerMove);
  view.canvas.addEventListener('pointerup', pointerUp);
  view.canvas.addEventListener('pointercancel', pointerUp);
  for (const kind of Object.keys(DROP_AT)) $(`drop-${kind}`).addEventListener('click', () => dropJointed(kind));
  $('drive-left').addEventListener('click', () => drive(-1));
  $('brake').addEventListener('click', () => drive(0));
  $('drive-right').addEventListener('click', () => drive(1));
  $('pause').addEventListener('click', togglePause);
  $('step').addEventListener('click', () => { if (!state.paused) togglePause(); step(); });
  $('reset').addEventListener('click', reset);
  $('clear').addEventListener('click', clear);
  $('broadphase').addEventListener('change', reset);
  window.addEventListener('keydown', (e) => {
    if (e.key === ' ') { e.preventDefault(); togglePause(); }
    // Held arrows drive the cars (a key repeat sets the same speed again), unless they
    // are moving a caret in a number field.
    if ((e.key === 'ArrowRight' || e.key === 'ArrowLeft') && !(e.target instanceof HTMLInputElement)) {
      e.preventDefault();
      drive(e.key === 'ArrowRight' ? 1 : -1);
    }
  });
  window.addEventListener('keyup', (e) => {
    if (e.key === 'ArrowRight' || e.key === 'ArrowLeft') drive(0);
  });
  $('status').textContent = 'ready';
  window.quackSandbox = {
    state: () => ({ paused: state.paused, counts: [...state.counts], world: state.world }),
    drop: (name, pos, angle) => {
      const shape = drop(name, pos, angle);
      state.world = quack.worldState();
      return shape;
    },
    /** Steps n times at once (pause first, so that only these steps run). */
    run: (n) => { for (let i = 0; i < n; ++i) step(); },
    clear,
    /** Drops in a 'chain', 'car' or 'ragdoll' (at its usual place, or at `at`). */
    dropJointed,
    /** Drives the cars: 1 right, -1 left, 0 brake; returns the wheel joints set. */
    drive,
    /** Where the world point p is drawn, in canvas pixels. */
    toCanvas: (p) => view.toCanvas(p),
    togglePause,
  };
  requestAnimationFrame(frame);
}

main().catch((e) => {
  $('status').textContent = `failed: ${e}`;
  $('status').className = 'err';
  console.error(e);
});
