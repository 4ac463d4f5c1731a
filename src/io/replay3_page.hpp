#pragma once
// The 3D replay page's HTML, CSS and JavaScript (internal to the io layer): raw WebGL 1, no
// library, nothing fetched. @TITLE@ and @DATA@ are replaced by the title and the recording
// (JSON; render3.cpp says its fields). The orbit camera and the shading follow the usual
// model viewer: yaw and pitch about a target, a Lambert term from two lights and a sky term.

namespace quack {

inline constexpr const char* kReplay3Page = R"QUACKPAGE(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>quack 3D replay: @TITLE@</title>
<style>
  html, body { margin: 0; height: 100%; font: 14px system-ui, sans-serif; background: #fbfaf7; color: #222; }
  #bar { display: flex; gap: 10px; align-items: center; padding: 6px 10px; background: #efece4; flex-wrap: wrap; }
  #bar input[type=range] { flex: 1; min-width: 200px; }
  #view { display: block; width: 100%; height: calc(100% - 44px); cursor: grab; touch-action: none; }
  button { font: inherit; padding: 2px 10px; }
  #clock { font-variant-numeric: tabular-nums; min-width: 11em; }
  #hint { color: #666; }
  #nogl { padding: 2em; }
</style>
</head>
<body>
<div id="bar">
  <button id="play" title="play / pause (space)">Pause</button>
  <input id="scrub" type="range" min="0" max="0" value="0" aria-label="time">
  <span id="clock"></span>
  <span id="awake" title="bodies simulated in this frame; sleeping bodies are drawn faded"></span>
  <label>speed <select id="speed"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>4</option></select></label>
  <label title="contact points and normals, drawn over everything"><input type="checkbox" id="contacts"> contacts</label>
  <button id="fit" title="fit the view (f)">fit</button>
  <span id="hint">drag: orbit &middot; shift-drag or right-drag: pan &middot; wheel: zoom &middot; arrows: step</span>
  <span id="note"></span>
</div>
<canvas id="view"></canvas>
<div id="nogl" hidden>This replay draws with WebGL, which this browser does not offer.</div>
<script type="application/json" id="quack-data">@DATA@</script>
<script>
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("quack-data").textContent);
  const canvas = document.getElementById("view");
  const ui = {};
  for (const id of ["play", "scrub", "clock", "awake", "speed", "contacts", "fit", "note"]) ui[id] = document.getElementById(id);
  const frames = data.frames;
  const gl = canvas.getContext("webgl", { antialias: true, preserveDrawingBuffer: true });
  if (!gl) {
    document.getElementById("nogl").hidden = false;
    canvas.hidden = true;
    window.quackReplay = { error: "no WebGL", frameCount: frames.length };
    return;
  }
  const notes = [];
  if (data.drawn < data.total) notes.push("showing " + data.drawn + " of " + data.total + " shapes");
  if (data.capped) notes.push("contacts capped per frame");
  if (notes.length) ui.note.textContent = notes.join("; ") + " (size budget)";

  // ---- small vector and matrix helpers (column-major 4x4, as WebGL takes them) ----
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };
  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  }
  function lookAt(eye, target, up) {
    const z = norm(sub(eye, target)), x = norm(cross(up, z)), y = cross(z, x);
    return new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1]);
  }
  // worldFromBody from a position and a quaternion [x, y, z, w] (normalised here: the
  // recording keeps 4 decimals).
  function pose(p, o) {
    let x = p[o + 3], y = p[o + 4], z = p[o + 5], w = p[o + 6];
    const l = Math.hypot(x, y, z, w) || 1;
    x /= l; y /= l; z /= l; w /= l;
    return new Float32Array([
      1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
      2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
      2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
      p[o], p[o + 1], p[o + 2], 1]);
  }

  // ---- geometry: every shape as triangles (position, normal) and edge lines, body frame ----
  const tris = [], lines = [];
  function tri(a, b, c, na, nb, nc) { tris.push(...a, ...na, ...b, ...nb, ...c, ...nc); }
  function flat(a, b, c) { const n = norm(cross(sub(b, a), sub(c, a))); tri(a, b, c, n, n, n); }
  function line(a, b) { lines.push(...a, ...b); }
  const vertex = (v, i) => [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
  // Rings of points around an axis, joined into a band of quads: spheres and capsules.
  function rings(list, slices) {
    for (let k = 0; k + 1 < list.length; ++k) {
      for (let s = 0; s < slices; ++s) {
        const t = (i) => (i % slices);
        const a = list[k][t(s)], b = list[k][t(s + 1)], c = list[k + 1][t(s + 1)], d = list[k + 1][t(s)];
        tri(a.p, b.p, c.p, a.n, b.n, c.n);
        tri(a.p, c.p, d.p, a.n, c.n, d.n);
      }
    }
  }
  function roundCap(c0, c1, r, axis) {
    // A capsule about the segment c0-c1 (a sphere when they coincide), rings from -axis to +axis.
    const u = norm(Math.abs(axis[0]) < 0.9 ? cross(axis, [1, 0, 0]) : cross(axis, [0, 1, 0])), v = cross(axis, u);
    const slices = 24, half = 8, list = [];
    for (let k = 0; k <= 2 * half; ++k) {
      const phi = -Math.PI / 2 + Math.PI * k / (2 * half);
      for (const centre of k === half ? [c0, c1] : [k < half ? c0 : c1]) {
        const ring = [];
        for (let s = 0; s < slices; ++s) {
          const th = 2 * Math.PI * s / slices;
          const n = add(scale(add(scale(u, Math.cos(th)), scale(v, Math.sin(th))), Math.cos(phi)), scale(axis, Math.sin(phi)));
          ring.push({ p: add(centre, scale(n, r)), n });
        }
        list.push(ring);
      }
    }
    rings(list, slices);
  }
  function hull(g) {
    let v = g.v;
    if (g.r > 0) {
      // A rounded hull drawn as its core grown by the radius along each vertex's mean face
      // normal: the rounded solid's corners, cut flat.
      const grown = v.slice(), normals = v.map(() => 0);
      for (const f of g.f) {
        const n = norm(cross(sub(vertex(v, f[1]), vertex(v, f[0])), sub(vertex(v, f[2]), vertex(v, f[0]))));
        for (const i of f) for (let a = 0; a < 3; ++a) normals[3 * i + a] += n[a];
      }
      for (let i = 0; 3 * i < v.length; ++i) {
        const n = norm(vertex(normals, i));
        for (let a = 0; a < 3; ++a) grown[3 * i + a] = v[3 * i + a] + g.r * n[a];
      }
      v = grown;
    }
    for (const f of g.f) {
      for (let k = 1; k + 1 < f.length; ++k) flat(vertex(v, f[0]), vertex(v, f[k]), vertex(v, f[k + 1]));
      for (let k = 0; k < f.length; ++k) line(vertex(v, f[k]), vertex(v, f[(k + 1) % f.length]));
    }
  }
  function mesh(g) {
    const edges = g.i.length <= 3 * 20000;
    for (let k = 0; k < g.i.length; k += 3) {
      const a = vertex(g.v, g.i[k]), b = vertex(g.v, g.i[k + 1]), c = vertex(g.v, g.i[k + 2]);
      flat(a, b, c);
      if (edges) { line(a, b); line(b, c); line(c, a); }
    }
  }
  const base = { static: [0.73, 0.71, 0.66], kinematic: [0.61, 0.76, 0.9], dynamic: [0.95, 0.71, 0.35] };
  const palette = [[0.95, 0.71, 0.35], [0.91, 0.55, 0.38], [0.55, 0.74, 0.52], [0.52, 0.66, 0.86], [0.83, 0.62, 0.8], [0.93, 0.82, 0.45]];
  const shapes = data.shapes.map((s) => {
    const t0 = tris.length / 6, l0 = lines.length / 3, g = s.g;
    if (g.t === "sphere") roundCap(g.c, g.c, g.r, [0, 1, 0]);
    else if (g.t === "capsule") roundCap(g.a, g.b, g.r, norm(sub(g.b, g.a)));
    else if (g.t === "hull") hull(g);
    else mesh(g);
    return { b: s.b, model: s.b < 0 ? pose(s.x, 0) : null, color: s.k === "dynamic" ? palette[s.h % palette.length] : base[s.k],
      tri: [t0, tris.length / 6 - t0], line: [l0, lines.length / 3 - l0] };
  });

  // ---- WebGL ----
  function compile(type, text) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, text);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    return sh;
  }
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, `
    attribute vec3 aPos; attribute vec3 aNormal;
    uniform mat4 uProj, uView, uModel;
    varying vec3 vN;
    void main() {
      vN = (uModel * vec4(aNormal, 0.0)).xyz;
      gl_Position = uProj * uView * uModel * vec4(aPos, 1.0);
      gl_PointSize = 4.0;
    }`));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `
    precision mediump float;
    uniform vec3 uColor; uniform float uLit, uFade;
    varying vec3 vN;
    void main() {
      vec3 c = uColor;
      if (uLit > 0.5) {
        vec3 n = normalize(vN);
        if (!gl_FrontFacing) n = -n;
        float d = 0.32 + 0.55 * max(dot(n, normalize(vec3(0.45, 0.8, 0.35))), 0.0)
                + 0.18 * max(dot(n, normalize(vec3(-0.6, 0.25, -0.75))), 0.0) + 0.08 * n.y;
        c = uColor * d;
      }
      gl_FragColor = vec4(mix(c, vec3(0.984, 0.98, 0.969), uFade), 1.0);
    }`));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  gl.useProgram(program);
  const loc = {};
  for (const n of ["uProj", "uView", "uModel", "uColor", "uLit", "uFade"]) loc[n] = gl.getUniformLocation(program, n);
  const aPos = gl.getAttribLocation(program, "aPos"), aNormal = gl.getAttribLocation(program, "aNormal");
  const triBuffer = gl.createBuffer(), lineBuffer = gl.createBuffer(), overlayBuffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, triBuffer);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(tris), gl.STATIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, lineBuffer);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(lines), gl.STATIC_DRAW);
  tris.length = 0;
  lines.length = 0;
  const identity = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);

  // ---- camera: yaw and pitch about a target ----
  // The camera fits the moving bodies (data.focus) with a margin; near and far planes
  // follow the whole scene (data.bounds).
  const boxCentre = (b) => [(b[0] + b[3]) / 2, (b[1] + b[4]) / 2, (b[2] + b[5]) / 2];
  const boxRadius = (b) => Math.max(0.5 * Math.hypot(b[3] - b[0], b[4] - b[1], b[5] - b[2]), 1e-3);
  const centre = boxCentre(data.focus), focusRadius = boxRadius(data.focus);
  const radius = Math.max(boxRadius(data.bounds), focusRadius);
  const fovy = 45 * Math.PI / 180;
  const cam = { yaw: 0, pitch: 0, distance: 1, target: centre.slice() };
  function fit() {
    cam.yaw = 0.6; cam.pitch = 0.5; cam.target = centre.slice();
    cam.distance = 1.3 * focusRadius / Math.sin(fovy / 2);
  }
  function eye() {
    const c = Math.cos(cam.pitch);
    return add(cam.target, scale([c * Math.sin(cam.yaw), Math.sin(cam.pitch), c * Math.cos(cam.yaw)], cam.distance));
  }
  function resize() {
    const r = canvas.getBoundingClientRect();
    canvas.width = Math.max(1, Math.floor(r.width * devicePixelRatio));
    canvas.height = Math.max(1, Math.floor(r.height * devicePixelRatio));
  }

  const state = { frame: 0, playing: true, position: 0, last: null };
  ui.scrub.max = String(Math.max(0, frames.length - 1));
  // Per moving body of frame f: 1 when it sleeps. f.w holds run lengths, awake first.
  function sleeping(f) {
    if (f.z) return f.z;
    const n = f.p.length / 7;
    f.z = new Uint8Array(n);
    let at = 0;
    (f.w || []).forEach((run, k) => {
      if (k % 2 === 1) f.z.fill(1, at, Math.min(n, at + run));
      at += run;
    });
    return f.z;
  }

  function bind(buffer, withNormals) {
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    const stride = withNormals ? 24 : 12;
    gl.enableVertexAttribArray(aPos);
    gl.vertexAttribPointer(aPos, 3, gl.FLOAT, false, stride, 0);
    if (withNormals) {
      gl.enableVertexAttribArray(aNormal);
      gl.vertexAttribPointer(aNormal, 3, gl.FLOAT, false, stride, 12);
    } else {
      gl.disableVertexAttribArray(aNormal);
      gl.vertexAttrib3f(aNormal, 0, 1, 0);
    }
  }
  const SLEEPING_FADE = 0.4;

  function draw() {
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(0.984, 0.98, 0.969, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    const f = frames[state.frame];
    if (!f) return;
    gl.enable(gl.DEPTH_TEST);
    const near = Math.max(cam.distance - 2.5 * radius, cam.distance * 1e-3), far = cam.distance + 2.5 * radius;
    gl.uniformMatrix4fv(loc.uProj, false, perspective(fovy, canvas.width / canvas.height, near, far));
    gl.uniformMatrix4fv(loc.uView, false, lookAt(eye(), cam.target, [0, 1, 0]));
    const asleep = sleeping(f);
    const models = shapes.map((s) => (s.b < 0 ? s.model : f.p[7 * s.b] === null ? null : pose(f.p, 7 * s.b)));
    // Faces, pushed back a little so that the edges drawn next stay on top.
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    bind(triBuffer, true);
    gl.uniform1f(loc.uLit, 1);
    shapes.forEach((s, k) => {
      if (!models[k] || s.tri[1] === 0) return;
      gl.uniformMatrix4fv(loc.uModel, false, models[k]);
      gl.uniform3fv(loc.uColor, s.color);
      gl.uniform1f(loc.uFade, s.b >= 0 && asleep[s.b] ? SLEEPING_FADE : 0);
      gl.drawArrays(gl.TRIANGLES, s.tri[0], s.tri[1]);
    });
    gl.disable(gl.POLYGON_OFFSET_FILL);
    bind(lineBuffer, false);
    gl.uniform1f(loc.uLit, 0);
    gl.uniform3fv(loc.uColor, [0.29, 0.27, 0.21]);
    shapes.forEach((s, k) => {
      if (!models[k] || s.line[1] === 0) return;
      gl.uniformMatrix4fv(loc.uModel, false, models[k]);
      gl.uniform1f(loc.uFade, s.b >= 0 && asleep[s.b] ? SLEEPING_FADE : 0.25);
      gl.drawArrays(gl.LINES, s.line[0], s.line[1]);
    });
    if (ui.contacts.checked && f.c.length) {
      // Contact points and normals over everything (no depth test): most lie between bodies.
      const pts = [], len = 0.08 * focusRadius;
      for (let k = 0; k < f.c.length; k += 6) {
        const p = [f.c[k], f.c[k + 1], f.c[k + 2]];
        pts.push(...p, ...add(p, scale([f.c[k + 3], f.c[k + 4], f.c[k + 5]], len)));
      }
      gl.disable(gl.DEPTH_TEST);
      gl.bindBuffer(gl.ARRAY_BUFFER, overlayBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(pts), gl.STREAM_DRAW);
      bind(overlayBuffer, false);
      gl.uniformMatrix4fv(loc.uModel, false, identity);
      gl.uniform3fv(loc.uColor, [0.84, 0.16, 0.16]);
      gl.uniform1f(loc.uFade, 0);
      gl.drawArrays(gl.LINES, 0, pts.length / 3);
      for (let k = 0; k < pts.length / 6; ++k) gl.drawArrays(gl.POINTS, 2 * k, 1);
    }
    ui.clock.textContent = "t = " + f.t.toFixed(3) + " s  (" + (state.frame + 1) + "/" + frames.length + ")";
    ui.scrub.value = String(state.frame);
    let live = 0, awake = 0;
    for (let k = 0; k < asleep.length; ++k) {
      if (f.p[7 * k] === null) continue;
      ++live;
      if (!asleep[k]) ++awake;
    }
    ui.awake.textContent = live > 0 ? "awake " + awake + " of " + live : "";
  }

  function setPlaying(p) {
    state.playing = p;
    ui.play.textContent = p ? "Pause" : "Play";
  }
  function seek(k) {
    setPlaying(false);
    state.frame = Math.max(0, Math.min(frames.length - 1, k));
    state.position = state.frame;
    draw();
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
  function zoom(factor) {
    cam.distance = Math.min(Math.max(cam.distance / factor, 1e-3 * radius), 100 * radius);
    draw();
  }
  function orbit(dx, dy) {
    cam.yaw -= dx * 0.008;
    cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + dy * 0.008));
    draw();
  }
  function pan(dx, dy) {
    const z = norm(sub(eye(), cam.target)), x = norm(cross([0, 1, 0], z)), y = cross(z, x);
    const k = cam.distance * 2 * Math.tan(fovy / 2) / canvas.clientHeight;
    cam.target = add(cam.target, add(scale(x, -dx * k), scale(y, dy * k)));
    draw();
  }

  ui.play.addEventListener("click", () => setPlaying(!state.playing));
  ui.scrub.addEventListener("input", () => seek(Number(ui.scrub.value)));
  ui.contacts.addEventListener("change", draw);
  ui.fit.addEventListener("click", () => { fit(); draw(); });
  canvas.addEventListener("wheel", (e) => { e.preventDefault(); zoom(e.deltaY < 0 ? 1.15 : 1 / 1.15); }, { passive: false });
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  let drag = null;
  canvas.addEventListener("mousedown", (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 }; });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) pan(dx, dy); else orbit(dx, dy);
  });
  window.addEventListener("keydown", (e) => {
    if (e.target === ui.scrub) return;
    if (e.key === " ") { e.preventDefault(); setPlaying(!state.playing); }
    else if (e.key === "+" || e.key === "=") zoom(1.25);
    else if (e.key === "-") zoom(0.8);
    else if (e.key === "f") { fit(); draw(); }
    else if (e.key === "ArrowRight") seek(state.frame + 1);
    else if (e.key === "ArrowLeft") seek(state.frame - 1);
  });
  window.addEventListener("resize", () => { resize(); draw(); });
  // For tests and tools: the viewer's state and controls.
  window.quackReplay = {
    get frame() { return state.frame; }, get playing() { return state.playing; }, frameCount: frames.length,
    get camera() { return { yaw: cam.yaw, pitch: cam.pitch, distance: cam.distance, target: cam.target.slice() }; },
    play() { setPlaying(true); }, pause() { setPlaying(false); },
    /** Shows frame k (and pauses). */
    seek,
    /** Indices (into the moving bodies) of the bodies asleep in frame k. */
    asleep(k) { const z = sleeping(frames[k]); return [...z.keys()].filter((i) => z[i]); },
    sleepingFade: SLEEPING_FADE,
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
