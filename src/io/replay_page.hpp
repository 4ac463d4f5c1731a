#pragma once
// The replay page's HTML, CSS and JavaScript (internal to the io layer). @TITLE@ and @DATA@
// are replaced by the title and the recording (JSON). One file, no network access.

namespace quack {

inline constexpr const char* kReplayPage = R"QUACKPAGE(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>quack replay: @TITLE@</title>
<style>
  html, body { margin: 0; height: 100%; font: 14px system-ui, sans-serif; background: #fbfaf7; color: #222; }
  #bar { display: flex; gap: 10px; align-items: center; padding: 6px 10px; background: #efece4; flex-wrap: wrap; }
  #bar input[type=range] { flex: 1; min-width: 200px; }
  #view { display: block; width: 100%; height: calc(100% - 44px); cursor: grab; }
  button { font: inherit; padding: 2px 10px; }
  #clock { font-variant-numeric: tabular-nums; min-width: 11em; }
</style>
</head>
<body>
<div id="bar">
  <button id="play" title="play / pause (space)">Pause</button>
  <input id="scrub" type="range" min="0" max="0" value="0" aria-label="time">
  <span id="clock"></span>
  <span id="awake" title="bodies simulated in this frame; sleeping bodies are drawn faded"></span>
  <label>speed <select id="speed"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>4</option></select></label>
  <label><input type="checkbox" id="contacts" checked> contacts</label>
  <label><input type="checkbox" id="joints" checked> joints</label>
  <label><input type="checkbox" id="boxes"> broad-phase boxes</label>
  <button id="zoomIn" title="zoom in (+, wheel)">+</button>
  <button id="zoomOut" title="zoom out (-, wheel)">&minus;</button>
  <button id="fit" title="fit (f)">fit</button>
  <span id="note"></span>
</div>
<canvas id="view"></canvas>
<script type="application/json" id="quack-data">@DATA@</script>
<script>
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("quack-data").textContent);
  const canvas = document.getElementById("view");
  const ctx = canvas.getContext("2d");
  const ui = {};
  for (const id of ["play", "scrub", "clock", "awake", "speed", "contacts", "joints", "boxes", "zoomIn", "zoomOut", "fit"]) ui[id] = document.getElementById(id);
  const frames = data.frames;
  const state = { frame: 0, playing: true, position: 0, cx: 0, cy: 0, scale: 1, last: null };
  ui.scrub.max = String(Math.max(0, frames.length - 1));
  if (!data.boxes) ui.boxes.disabled = true;
  // What the size budget left out (docs/scenes.md, "Size budgets").
  const notes = [];
  if (data.drawn < data.total) notes.push("showing " + data.drawn + " of " + data.total + " shapes");
  if (data.capped) notes.push("contacts and boxes capped per frame");
  if (notes.length) document.getElementById("note").textContent = notes.join("; ") + " (size budget)";

  const colors = { static: "#b9b4a8", kinematic: "#9cc3e6", dynamic: "#f2b45a" };
  // Sleeping bodies are drawn at this opacity (static bodies, never awake, are not faded).
  const SLEEPING_ALPHA = 0.35;

  // Per moving body of frame f: 1 when it sleeps. f.w holds run lengths, awake first.
  function sleeping(f) {
    if (f.z) return f.z;
    const n = f.p.length / 3;
    f.z = new Uint8Array(n);
    let at = 0;
    (f.w || []).forEach((run, k) => {
      if (k % 2 === 1) f.z.fill(1, at, Math.min(n, at + run));
      at += run;
    });
    return f.z;
  }

  function fit() {
    const [lx, ly, ux, uy] = data.bounds;
    const w = Math.max(ux - lx, 1e-3), h = Math.max(uy - ly, 1e-3);
    state.cx = (lx + ux) / 2;
    state.cy = (ly + uy) / 2;
    state.scale = 0.9 * Math.min(canvas.width / w, canvas.height / h);
  }
  function resize() {
    const r = canvas.getBoundingClientRect();
    canvas.width = Math.max(1, Math.floor(r.width * devicePixelRatio));
    canvas.height = Math.max(1, Math.floor(r.height * devicePixelRatio));
  }
  function toScreen(x, y) {
    return [canvas.width / 2 + (x - state.cx) * state.scale, canvas.height / 2 - (y - state.cy) * state.scale];
  }

  function draw() {
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#fbfaf7";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const f = frames[state.frame];
    if (!f) return;
    ctx.lineWidth = Math.max(1, devicePixelRatio);
    ctx.lineJoin = "round";
    const asleep = sleeping(f);
    for (const s of data.shapes) {
      let x, y, a;
      if (s.b < 0) { [x, y, a] = s.x; } else {
        x = f.p[3 * s.b]; y = f.p[3 * s.b + 1]; a = f.p[3 * s.b + 2];
        if (x === null) continue;
      }
      ctx.globalAlpha = s.b >= 0 && asleep[s.b] ? SLEEPING_ALPHA : 1;
      const c = Math.cos(a), sn = Math.sin(a);
      ctx.beginPath();
      for (let k = 0; k < s.o.length; k += 2) {
        const px = x + c * s.o[k] - sn * s.o[k + 1], py = y + sn * s.o[k] + c * s.o[k + 1];
        const [X, Y] = toScreen(px, py);
        if (k === 0) ctx.moveTo(X, Y); else ctx.lineTo(X, Y);
      }
      if (s.c) {
        ctx.closePath();
        ctx.fillStyle = s.s ? "rgba(127,184,255,0.2)" : colors[s.k];
        ctx.fill();
      }
      ctx.setLineDash(s.s ? [6, 4] : []);
      ctx.strokeStyle = s.s ? "#3b82f6" : "#4a4536";
      ctx.stroke();
      ctx.setLineDash([]);
    }
    ctx.globalAlpha = 1;
    if (ui.boxes.checked && f.a) {
      ctx.strokeStyle = "rgba(40,120,60,0.7)";
      for (let k = 0; k < f.a.length; k += 4) {
        const [X0, Y0] = toScreen(f.a[k], f.a[k + 1]), [X1, Y1] = toScreen(f.a[k + 2], f.a[k + 3]);
        ctx.strokeRect(X0, Y1, X1 - X0, Y0 - Y1);
      }
    }
    // Joints: from body A's centre to its anchor, across to B's anchor, to B's centre.
    if (ui.joints.checked && f.j) {
      ctx.strokeStyle = "#2a9d8f";
      ctx.fillStyle = "#2a9d8f";
      ctx.lineWidth = 1.5 * devicePixelRatio;
      for (let k = 0; k < f.j.length; k += 8) {
        const pts = [];
        for (let m = 0; m < 8; m += 2) pts.push(toScreen(f.j[k + m], f.j[k + m + 1]));
        ctx.beginPath();
        ctx.moveTo(pts[0][0], pts[0][1]);
        for (let m = 1; m < 4; ++m) ctx.lineTo(pts[m][0], pts[m][1]);
        ctx.stroke();
        for (const m of [1, 2]) {
          ctx.beginPath();
          ctx.arc(pts[m][0], pts[m][1], 3 * devicePixelRatio, 0, 2 * Math.PI);
          ctx.fill();
        }
      }
      ctx.lineWidth = 1;
    }
    if (ui.contacts.checked) {
      ctx.strokeStyle = "#d62828";
      ctx.fillStyle = "#d62828";
      const len = 12 * devicePixelRatio;
      for (let k = 0; k < f.c.length; k += 4) {
        const [X, Y] = toScreen(f.c[k], f.c[k + 1]);
        ctx.beginPath();
        ctx.arc(X, Y, 2.5 * devicePixelRatio, 0, 2 * Math.PI);
        ctx.fill();
        ctx.beginPath();
        ctx.moveTo(X, Y);
        ctx.lineTo(X + len * f.c[k + 2], Y - len * f.c[k + 3]);
        ctx.stroke();
      }
    }
    ui.clock.textContent = "t = " + f.t.toFixed(3) + " s  (" + (state.frame + 1) + "/" + frames.length + ")";
    ui.scrub.value = String(state.frame);
    let live = 0, awake = 0;
    for (let b = 0; b < asleep.length; ++b) {
      if (f.p[3 * b] === null) continue;
      ++live;
      if (!asleep[b]) ++awake;
    }
    ui.awake.textContent = live > 0 ? "awake " + awake + " of " + live : "";
  }

  function setPlaying(p) {
    state.playing = p;
    ui.play.textContent = p ? "Pause" : "Play";
  }
  function tick(now) {
    if (state.last !== null && state.playing && frames.length > 1) {
      const dt = (now - state.last) / 1000 * Number(ui.speed.value);
      const span = frames[frames.length - 1].t - frames[0].t;
      const perFrame = span > 0 ? span / (frames.length - 1) : 1 / 60;
      state.position += dt / perFrame;
      if (state.position >= frames.length) state.position = 0;
      state.frame = Math.min(frames.length - 1, Math.floor(state.position));
    }
    state.last = now;
    draw();
    requestAnimationFrame(tick);
  }
  function zoom(factor, sx, sy) {
    const wx = state.cx + (sx - canvas.width / 2) / state.scale, wy = state.cy - (sy - canvas.height / 2) / state.scale;
    state.scale *= factor;
    state.cx = wx - (sx - canvas.width / 2) / state.scale;
    state.cy = wy + (sy - canvas.height / 2) / state.scale;
    draw();
  }

  ui.play.addEventListener("click", () => setPlaying(!state.playing));
  ui.scrub.addEventListener("input", () => { state.frame = Number(ui.scrub.value); state.position = state.frame; draw(); });
  ui.contacts.addEventListener("change", draw);
  ui.joints.addEventListener("change", draw);
  ui.boxes.addEventListener("change", draw);
  ui.zoomIn.addEventListener("click", () => zoom(1.25, canvas.width / 2, canvas.height / 2));
  ui.zoomOut.addEventListener("click", () => zoom(0.8, canvas.width / 2, canvas.height / 2));
  ui.fit.addEventListener("click", () => { fit(); draw(); });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const r = canvas.getBoundingClientRect();
    zoom(e.deltaY < 0 ? 1.15 : 1 / 1.15, (e.clientX - r.left) * devicePixelRatio, (e.clientY - r.top) * devicePixelRatio);
  }, { passive: false });
  let drag = null;
  canvas.addEventListener("mousedown", (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    state.cx -= (e.clientX - drag[0]) * devicePixelRatio / state.scale;
    state.cy += (e.clientY - drag[1]) * devicePixelRatio / state.scale;
    drag = [e.clientX, e.clientY];
    draw();
  });
  window.addEventListener("keydown", (e) => {
    if (e.key === " ") { e.preventDefault(); setPlaying(!state.playing); }
    else if (e.key === "+" || e.key === "=") zoom(1.25, canvas.width / 2, canvas.height / 2);
    else if (e.key === "-") zoom(0.8, canvas.width / 2, canvas.height / 2);
    else if (e.key === "f") { fit(); draw(); }
  });
  window.addEventListener("resize", () => { resize(); fit(); draw(); });
  // For tests and tools: the viewer's state and controls.
  window.quackReplay = {
    get frame() { return state.frame; }, get playing() { return state.playing; }, frameCount: frames.length,
    play() { setPlaying(true); }, pause() { setPlaying(false); },
    /** Shows frame k (and pauses). */
    seek(k) { setPlaying(false); state.frame = k; state.position = k; draw(); },
    /** Indices (into the moving bodies) of the bodies asleep in frame k. */
    asleep(k) { const z = sleeping(frames[k]); return [...z.keys()].filter((b) => z[b]); },
    /** Where moving body b's origin is drawn in frame k, in canvas pixels. */
    screenOf(k, b) { return toScreen(frames[k].p[3 * b], frames[k].p[3 * b + 1]); },
    sleepingAlpha: SLEEPING_ALPHA,
  };
  resize();
  fit();
  requestAnimationFrame(tick);
})();
</script>
</body>
</html>
)QUACKPAGE";

}  // namespace quack
