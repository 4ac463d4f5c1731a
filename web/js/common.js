// Shared by the pages: loading the WebAssembly module, a world-to-canvas view, and drawing
// Quack's shapes (core points grown by a radius, as the library sees them).

/** Loads quack_web.js's module and wraps its C functions; JSON answers come back parsed. */
export async function loadQuack() {
  // createQuack is defined by quack_web.js, loaded by a classic <script> tag before us.
  const module = await globalThis.createQuack();
  const call = (name, args, types) => {
    const text = module.ccall(name, 'string', types, args);
    return JSON.parse(text);
  };
  return {
    setShape: (slot, shape) => call('qk_set_shape', [slot, JSON.stringify(shape)], ['number', 'string']),
    analyze: (pa, pb) =>
      call('qk_analyze', [pa.pos[0], pa.pos[1], pa.angle, pb.pos[0], pb.pos[1], pb.angle],
        ['number', 'number', 'number', 'number', 'number', 'number']),
    // The 3D page: shapes in the 3D shape JSON, poses {pos: [x, y, z], quat: [x, y, z, w]}.
    setShape3: (slot, shape) => call('qk3_set_shape', [slot, JSON.stringify(shape)], ['number', 'string']),
    analyze3: (pa, pb) => call('qk3_analyze', [JSON.stringify({ pa, pb })], ['string']),
    worldReset: (kind) => call('qk_world_reset', [kind], ['string']),
    worldAdd: (shape, type, pos, angle, vel, restitution) =>
      call('qk_world_add', [JSON.stringify(shape), type, pos[0], pos[1], angle, vel[0], vel[1], restitution],
        ['string', 'number', 'number', 'number', 'number', 'number', 'number', 'number']),
    worldCull: (y) => module.ccall('qk_world_cull', 'number', ['number'], [y]),
    worldStep: (dt, steps) => call('qk_world_step', [dt, steps], ['number', 'number']),
    worldState: () => call('qk_world_state', [], []),
    worldWake: (pos, radius) => call('qk_world_wake', [pos[0], pos[1], radius], ['number', 'number', 'number']),
    // Joints: a mouse joint for dragging, the jointed drop-ins and the cars' motors.
    worldGrab: (pos, radius) => call('qk_world_grab', [pos[0], pos[1], radius], ['number', 'number', 'number']),
    worldDrag: (pos) => module.ccall('qk_world_drag', 'number', ['number', 'number'], [pos[0], pos[1]]),
    worldRelease: () => module.ccall('qk_world_release', 'number', [], []),
    worldDrop: (kind, pos) => call('qk_world_drop', [kind, pos[0], pos[1]], ['string', 'number', 'number']),
    worldDrive: (speed) => module.ccall('qk_world_drive', 'number', ['number'], [speed]),
    // The 3D sandbox (sandbox3d.html): a World3 from a 3D scene's text, read by the parser
    // of `quack run`; bodies added as {shape, pos, quat, vel, density, restitution}.
    world3Load: (text, fileName) => call('qk3_world_load', [text, fileName], ['string', 'string']),
    world3Add: (body) => call('qk3_world_add', [JSON.stringify(body)], ['string']),
    world3Step: (dt, steps) => call('qk3_world_step', [dt, steps], ['number', 'number']),
    world3State: (withContacts) => call('qk3_world_state', [withContacts ? 1 : 0], ['number']),
    world3Shapes: () => call('qk3_world_shapes', [], []),
    world3RayCast: (origin, translation) =>
      call('qk3_world_raycast', [...origin, ...translation], Array(6).fill('number')),
    world3Cull: (y) => module.ccall('qk3_world_cull', 'number', ['number'], [y]),
  };
}

/** A view: world metres (y up) to canvas pixels. */
export class View {
  constructor(canvas, scale, center = [0, 0]) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.scale = scale;
    this.center = center;
  }
  toCanvas(p) {
    return [this.canvas.width / 2 + (p[0] - this.center[0]) * this.scale,
      this.canvas.height / 2 - (p[1] - this.center[1]) * this.scale];
  }
  toWorld(x, y) {
    return [(x - this.canvas.width / 2) / this.scale + this.center[0],
      -(y - this.canvas.height / 2) / this.scale + this.center[1]];
  }
  clear(color = '#fbfaf7') {
    const { ctx, canvas } = this;
    ctx.fillStyle = color;
    ctx.fillRect(0, 0, canvas.width, canvas.height);
  }
  grid(step = 1, color = '#ecebe6') {
    const { ctx, canvas } = this;
    const [x0, y1] = this.toWorld(0, 0);
    const [x1, y0] = this.toWorld(canvas.width, canvas.height);
    ctx.strokeStyle = color;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
      const [cx] = this.toCanvas([x, 0]);
      ctx.moveTo(cx, 0); ctx.lineTo(cx, canvas.height);
    }
    for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
      const [, cy] = this.toCanvas([0, y]);
      ctx.moveTo(0, cy); ctx.lineTo(canvas.width, cy);
    }
    ctx.stroke();
  }
  path(points, close) {
    const { ctx } = this;
    ctx.beginPath();
    points.forEach((p, i) => {
      const [x, y] = this.toCanvas(p);
      if (i === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
    });
    if (close) ctx.closePath();
  }
  line(p, q, color, width = 1.5, dash = []) {
    const { ctx } = this;
    ctx.save();
    ctx.setLineDash(dash);
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    this.path([p, q], false);
    ctx.stroke();
    ctx.restore();
  }
  arrow(from, to, color, width = 2) {
    const { ctx } = this;
    const [x0, y0] = this.toCanvas(from);
    const [x1, y1] = this.toCanvas(to);
    const len = Math.hypot(x1 - x0, y1 - y0);
    ctx.save();
    ctx.strokeStyle = color;
    ctx.fillStyle = color;
    ctx.lineWidth = width;
    ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(x1, y1); ctx.stroke();
    if (len > 4) {
      const ux = (x1 - x0) / len, uy = (y1 - y0) / len;
      const h = Math.min(10, len / 2);
      ctx.beginPath();
      ctx.moveTo(x1, y1);
      ctx.lineTo(x1 - h * ux - 0.5 * h * uy, y1 - h * uy + 0.5 * h * ux);
      ctx.lineTo(x1 - h * ux + 0.5 * h * uy, y1 - h * uy - 0.5 * h * ux);
      ctx.closePath();
      ctx.fill();
    }
    ctx.restore();
  }
  dot(p, color, radius = 4) {
    const { ctx } = this;
    const [x, y] = this.toCanvas(p);
    ctx.fillStyle = color;
    ctx.beginPath(); ctx.arc(x, y, radius, 0, 2 * Math.PI); ctx.fill();
  }
  label(p, text, color = '#333', dx = 6, dy = -6) {
    const { ctx } = this;
    const [x, y] = this.toCanvas(p);
    ctx.fillStyle = color;
    ctx.font = '12px sans-serif';
    ctx.fillText(text, x + dx, y + dy);
  }
  /**
   * The points within `radius` of the convex polygon `points` (world frame, either winding;
   * two points are a segment, one a disc): the core's edges pushed out by the radius, joined
   * by arcs around the vertices, filled translucent and outlined.
   */
  roundedHull(points, radius, fill, stroke) {
    const { ctx } = this;
    ctx.save();
    ctx.lineJoin = 'round';
    if (points.length === 1 || (radius > 0 && points.length >= 1)) {
      this.path(roundedOutline(points, Math.max(radius, 2 / this.scale)), true);
      ctx.fillStyle = fill; ctx.fill();
      ctx.strokeStyle = stroke; ctx.lineWidth = 1.5; ctx.stroke();
    } else {
      this.path(points, true);
      ctx.fillStyle = fill; ctx.fill();
      ctx.strokeStyle = stroke; ctx.lineWidth = points.length === 2 ? 3 : 1.5; ctx.stroke();
    }
    ctx.restore();
  }
}

/** Points along the boundary of the convex polygon `points` grown by `radius` (> 0). */
export function roundedOutline(points, radius) {
  if (points.length === 1) {
    return Array.from({ length: 48 }, (_, i) => {
      const a = (2 * Math.PI * i) / 48;
      return [points[0][0] + radius * Math.cos(a), points[0][1] + radius * Math.sin(a)];
    });
  }
  let area = 0;
  for (let i = 0; i < points.length; ++i) {
    const p = points[i];
    const q = points[(i + 1) % points.length];
    area += p[0] * q[1] - p[1] * q[0];
  }
  const pts = area < 0 ? [...points].reverse() : points;
  const n = pts.length;
  // Outward normal angle of edge i (counter-clockwise polygon: the right-hand side).
  const normalAngle = (i) => {
    const p = pts[i];
    const q = pts[(i + 1) % n];
    return Math.atan2(-(q[0] - p[0]), q[1] - p[1]);
  };
  const out = [];
  for (let i = 0; i < n; ++i) {
    const from = normalAngle((i + n - 1) % n);
    let sweep = normalAngle(i) - from;
    while (sweep < 0) sweep += 2 * Math.PI;
    while (sweep >= 2 * Math.PI) sweep -= 2 * Math.PI;
    const k = Math.max(1, Math.ceil(sweep / 0.15));
    for (let j = 0; j <= k; ++j) {
      const a = from + (sweep * j) / k;
      out.push([pts[i][0] + radius * Math.cos(a), pts[i][1] + radius * Math.sin(a)]);
    }
  }
  return out;
}

/** A point of the shape frame placed by {pos, angle}. */
export function place(pose, p) {
  const c = Math.cos(pose.angle), s = Math.sin(pose.angle);
  return [pose.pos[0] + c * p[0] - s * p[1], pose.pos[1] + s * p[0] + c * p[1]];
}

/** Draws an outline {type, points (shape frame), radius} placed by pose. */
export function drawShape(view, outline, pose, fill, stroke) {
  const pts = outline.points.map((p) => place(pose, p));
  view.roundedHull(pts, outline.radius, fill, stroke);
  // A line from the centre to the first point shows the rotation of round shapes.
  if (outline.type === 'circle') {
    const c = pts[0];
    const edge = place(pose, [outline.points[0][0] + outline.radius, outline.points[0][1]]);
    view.line(c, edge, stroke, 1);
  }
}

/** A number for display: fixed significant digits, no "-0". */
export function fmt(x, digits = 6) {
  if (typeof x !== 'number' || !Number.isFinite(x)) return String(x);
  if (Object.is(x, -0) || Math.abs(x) < 1e-30) return '0';
  return Number(x.toPrecision(digits)).toString();
}

export function fmtVec(v, digits = 4) {
  return `(${fmt(v[0], digits)}, ${fmt(v[1], digits)})`;
}

export function fmtVec3(v, digits = 4) {
  return `(${fmt(v[0], digits)}, ${fmt(v[1], digits)}, ${fmt(v[2], digits)})`;
}
