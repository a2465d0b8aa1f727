// The minimap (issue 28): a top-down 2-D canvas, x up the canvas (the usual course heading),
// y to the left: terrain footprints, the course's gates and obstacles, the path so far, the
// success line, ghosts of a compare replay, and the robot as an arrow.

const num = (x) => typeof x === 'number' && Number.isFinite(x);

/** Yaw (rad) of a quaternion x y z w. */
/** A course item's yaw, rad: scene.json's `yaw_rad` (or a `yaw_deg`). */
export function itemYaw(o) { return num(o.yaw_rad) ? o.yaw_rad : ((o.yaw_deg ?? 0) * Math.PI) / 180; }

function quatYaw([x, y, z, w]) { return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)); }

/** A gate's two ends (world x y) and its centre: width across its yaw, or a ring's radius. */
export function gateEnds(gt) {
  const half = num(gt.width_m) ? gt.width_m / 2 : num(gt.radius_m) ? gt.radius_m : 0.5;
  const yaw = itemYaw(gt);
  // The gate is crossed along its yaw: its ends lie across it.
  const ax = -Math.sin(yaw) * half, ay = Math.cos(yaw) * half;
  const cx = gt.x_m ?? gt.centre_m?.[0] ?? 0, cy = gt.y_m ?? gt.centre_m?.[1] ?? 0;
  return { c: [cx, cy], a: [cx + ax, cy + ay], b: [cx - ax, cy - ay], half };
}

export function createMinimap(canvas, scene) {
  const boxes = (scene.terrain?.boxes ?? []).map((b) => ({ c: b.centre_m, h: b.half_m, yaw: quatYaw(b.quat_xyzw ?? [0, 0, 0, 1]), top: b.centre_m[2] + b.half_m[2] }));
  const course = scene.course ?? null;
  const gates = (course?.gates ?? []).map(gateEnds);
  const obstacles = (course?.obstacles ?? []).map((o) => ({ c: o.centre_m, h: o.half_m, yaw: itemYaw(o) }));
  const ground = scene.terrain?.ground_z_m ?? 0;
  const info = { draws: 0, span_m: 0, gates: gates.length, obstacles: obstacles.length };
  /**
   * Draws the map around the robot at `pose` ([x y z roll pitch yaw]) with `path` (flat x y
   * list), `ghosts` ([{pose, colour}]) and `nextGate` (index or null).
   */
  function draw(pose, path, ghosts = [], nextGate = null) {
    const w = canvas.width, h = canvas.height;
    const g = canvas.getContext('2d');
    g.fillStyle = '#20303c'; g.fillRect(0, 0, w, h);
    // Extent: the course (if any) and the path, at least 3 m around the robot.
    let x0 = pose[0] - 3, x1 = pose[0] + 3, y0 = pose[1] - 3, y1 = pose[1] + 3;
    const grow = (x, y) => { x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); };
    for (const gt of gates) { grow(gt.a[0], gt.a[1]); grow(gt.b[0], gt.b[1]); }
    for (const o of obstacles) grow(o.c[0], o.c[1]);
    for (let i = 0; i + 1 < path.length; i += 2) grow(path[i], path[i + 1]);
    for (const gh of ghosts) grow(gh.pose[0], gh.pose[1]);
    const span = Math.min(Math.max(x1 - x0, y1 - y0) * 1.1, 60);
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, s = Math.min(w, h) / span;
    info.span_m = span;
    // World (x, y) -> canvas: x up, y left.
    const P = (x, y) => [w / 2 - (y - cy) * s, h / 2 - (x - cx) * s];
    const rect = (c, hf, yaw, fill) => {
      const cs = Math.cos(yaw), sn = Math.sin(yaw);
      g.beginPath();
      [[1, 1], [1, -1], [-1, -1], [-1, 1]].forEach(([a, b], i) => {
        const lx = a * hf[0], ly = b * hf[1];
        const [px, py] = P(c[0] + lx * cs - ly * sn, c[1] + lx * sn + ly * cs);
        if (i) g.lineTo(px, py); else g.moveTo(px, py);
      });
      g.closePath(); g.fillStyle = fill; g.fill();
    };
    for (const b of boxes) if (b.top > ground + 0.01) rect(b.c, b.h, b.yaw, 'rgba(184,165,134,0.85)');
    for (const c of scene.terrain?.cylinders ?? []) rect(c.centre_m, [c.radius_m, c.half_length_m], c.yaw_rad, 'rgba(160,140,110,0.85)');
    for (const o of obstacles) rect(o.c, o.h, o.yaw, 'rgba(220,90,60,0.9)');
    if (num(scene.success_x_m)) {
      g.strokeStyle = '#3c3'; g.lineWidth = 2; g.beginPath();
      const [ax, ay] = P(scene.success_x_m, cy - span), [bx, by] = P(scene.success_x_m, cy + span);
      g.moveTo(ax, ay); g.lineTo(bx, by); g.stroke();
    }
    gates.forEach((gt, i) => {
      const [ax, ay] = P(gt.a[0], gt.a[1]), [bx, by] = P(gt.b[0], gt.b[1]);
      g.strokeStyle = i === nextGate ? '#ffe040' : '#40c0ff'; g.lineWidth = i === nextGate ? 3 : 2;
      g.beginPath(); g.moveTo(ax, ay); g.lineTo(bx, by); g.stroke();
      const [tx, ty] = P(gt.c[0], gt.c[1]);
      g.fillStyle = '#fff'; g.font = '10px sans-serif'; g.fillText(String(i + 1), tx + 3, ty - 3);
    });
    // Path so far.
    if (path.length >= 4) {
      g.strokeStyle = '#ffffff'; g.lineWidth = 1.5; g.beginPath();
      for (let i = 0; i + 1 < path.length; i += 2) { const [px, py] = P(path[i], path[i + 1]); if (i) g.lineTo(px, py); else g.moveTo(px, py); }
      g.stroke();
    }
    const arrow = (p, colour, size) => {
      const [px, py] = P(p[0], p[1]);
      const yaw = p[5];
      // Canvas direction of world heading: x up (-py), y left (-px).
      const dx = -Math.sin(yaw), dy = -Math.cos(yaw);
      g.fillStyle = colour; g.beginPath();
      g.moveTo(px + dx * size, py + dy * size);
      g.lineTo(px - dx * size * 0.6 - dy * size * 0.5, py - dy * size * 0.6 + dx * size * 0.5);
      g.lineTo(px - dx * size * 0.6 + dy * size * 0.5, py - dy * size * 0.6 - dx * size * 0.5);
      g.closePath(); g.fill();
    };
    for (const gh of ghosts) arrow(gh.pose, gh.colour, 7);
    arrow(pose, '#ff3030', 9);
    info.draws++;
    info.robotPx = P(pose[0], pose[1]);
  }
  return { draw, info };
}
