// The operator's warnings (issue 28): stall, slip per track, tip-over gauge, the side view of
// the robot against the terrain ahead, the outcome banner, the course score and the driver's
// connection. Pure drawing on 2-D canvases and DOM text from a plain "view state", the same
// for the live page (the server's state, fields read defensively) and the replay (a row of
// trajectory.csv). Exposed on window.tracksim.hud so the browser test can feed fake states.

const deg = (r) => (r * 180) / Math.PI;
const num = (x) => typeof x === 'number' && Number.isFinite(x);
const fmt = (x, d = 2) => (num(x) ? x.toFixed(d) : '-');

/** Fraction of the tip-over limit at which the gauge turns amber, and red. */
export const TILT_AMBER = 0.6, TILT_RED = 0.85;
/** Slip ratio above which a track's bar is red. */
export const SLIP_RED = 0.5;
/** Client-side stall: |belt command| above this, m/s ... */
export const STALL_CMD_MPS = 0.05;
/** ... and forward speed below this, m/s ... */
export const STALL_SPEED_MPS = 0.02;
/** ... for this long, s. */
export const STALL_HOLD_S = 1.0;

/** Colour of a fraction of a limit: green, amber (>= 60 %), red (>= 85 %). */
export function levelColour(frac) {
  return frac >= TILT_RED ? '#e23b3b' : frac >= TILT_AMBER ? '#f0a830' : '#4cc35a';
}

/** Tilt of the body from upright (angle between its z and the world's z), deg. */
export function tiltDeg(roll, pitch) {
  return deg(Math.acos(Math.max(-1, Math.min(1, Math.cos(roll) * Math.cos(pitch)))));
}

/** Client-side stall detector: belts commanded, the robot not moving, for STALL_HOLD_S. */
export class StallDetector {
  constructor() { this.since = null; this.stalled = false; }
  /** Feeds one state (t s, belt commands m/s, forward speed m/s); returns whether stalled. */
  update(t, beltCmd, forward) {
    const commanded = (beltCmd ?? []).some((b) => Math.abs(b) > STALL_CMD_MPS);
    const still = num(forward) && Math.abs(forward) < STALL_SPEED_MPS;
    if (commanded && still) {
      if (this.since === null || t < this.since) this.since = t;
    } else this.since = null;
    this.stalled = this.since !== null && t - this.since >= STALL_HOLD_S - 1e-9;
    return this.stalled;
  }
}

/** The robot's outline in its x-z plane (body frame, m) from scene.json's vehicle. */
export function sideGeometry(vehicle) {
  const xz = (flat) => { const out = []; for (let i = 0; i + 2 < flat.length; i += 3) out.push([flat[i], flat[i + 2]]); return out; };
  const body = hull2(xz(vehicle.body?.vertices_m ?? []));
  const tracks = (vehicle.tracks ?? []).map((tr) => ({ parent: tr.parent, pts: hull2(xz(tr.points_m ?? [])) }));
  const flippers = (vehicle.flippers ?? []).map((f) => ({
    name: f.name, pivot: [f.pivot_m[0], f.pivot_m[2]], sign: (f.axis?.[1] ?? 1) < 0 ? -1 : 1,
    pts: f.mesh ? hull2(xz(f.mesh.vertices_m)) : [],
  }));
  let minZ = Infinity;
  for (const t of tracks) if (t.parent < 0) for (const p of t.pts) minZ = Math.min(minZ, p[1]);
  if (!Number.isFinite(minZ)) for (const p of body) minZ = Math.min(minZ, p[1]);
  return { body, tracks, flippers, rideHeight: Number.isFinite(minZ) ? -minZ : 0.1 };
}

/** Convex hull of 2-D points (monotone chain). */
function hull2(points) {
  const p = points.slice().sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  if (p.length < 3) return p;
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const lo = [], hi = [];
  for (const q of p) { while (lo.length >= 2 && cross(lo[lo.length - 2], lo[lo.length - 1], q) <= 0) lo.pop(); lo.push(q); }
  for (const q of p.slice().reverse()) { while (hi.length >= 2 && cross(hi[hi.length - 2], hi[hi.length - 1], q) <= 0) hi.pop(); hi.push(q); }
  return lo.slice(0, -1).concat(hi.slice(0, -1));
}

function sizeCanvas(c) {
  const w = c.clientWidth || c.width, h = c.clientHeight || c.height;
  if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
  return [c.width, c.height];
}

/** Tip-over gauge: |roll| and |pitch| as bars against `limit` deg (60 % amber, 85 % red). */
export function drawTilt(c, rollDeg, pitchDeg, limit) {
  const [w, h] = sizeCanvas(c);
  const g = c.getContext('2d');
  g.clearRect(0, 0, w, h);
  g.font = '11px ui-monospace, monospace';
  const rows = [['roll', rollDeg], ['pitch', pitchDeg]];
  const x0 = 40, bw = w - x0 - 48, bh = (h - 12) / 2 - 4;
  let worst = 0;
  rows.forEach(([name, a], i) => {
    const y = 4 + i * (bh + 8);
    const frac = num(a) && limit > 0 ? Math.abs(a) / limit : 0;
    worst = Math.max(worst, frac);
    g.fillStyle = '#333'; g.fillRect(x0, y, bw, bh);
    g.fillStyle = levelColour(frac); g.fillRect(x0, y, bw * Math.min(frac, 1), bh);
    for (const f of [TILT_AMBER, TILT_RED]) { g.fillStyle = '#ddd'; g.fillRect(x0 + bw * f, y, 1, bh); }
    g.fillStyle = '#eee';
    g.fillText(name, 2, y + bh - 2);
    g.fillText(`${fmt(a, 0)}°`, x0 + bw + 4, y + bh - 2);
  });
  return worst;
}

/** Slip per track as bars (0 .. 1; red above SLIP_RED). Returns the largest. */
export function drawSlip(c, names, slip) {
  const [w, h] = sizeCanvas(c);
  const g = c.getContext('2d');
  g.clearRect(0, 0, w, h);
  g.font = '10px ui-monospace, monospace';
  const x0 = Math.min(100, 6 + Math.max(30, ...names.map((nm) => g.measureText(nm).width)));
  const n = Math.max(names.length, 1), bh = Math.max(4, (h - 2) / n - 3), bw = w - x0 - 36;
  let worst = 0;
  names.forEach((name, i) => {
    const s = slip?.[i];
    const y = 1 + i * (bh + 3);
    const frac = num(s) ? Math.min(Math.abs(s), 1) : 0;
    worst = Math.max(worst, frac);
    g.fillStyle = '#333'; g.fillRect(x0, y, bw, bh);
    g.fillStyle = frac > SLIP_RED ? '#e23b3b' : '#4ca0e0'; g.fillRect(x0, y, bw * frac, bh);
    g.fillStyle = '#ddd'; g.fillRect(x0 + bw * SLIP_RED, y, 1, bh);
    g.fillStyle = '#eee';
    g.fillText(name, 2, y + bh - 1);
    g.fillText(fmt(s, 2), x0 + bw + 4, y + bh - 1);
  });
  return worst;
}

/**
 * Side view: the terrain profile ahead (`ahead.d_m`, `ahead.z_m`: m along the heading from the
 * body origin, heights relative to the terrain under the body) and the robot (geometry from
 * sideGeometry, pitched by `pitch` rad, flippers at `flippers` rad) standing on height 0.
 * Returns the drawing's scale and placement (for tests).
 */
export function drawSide(c, geo, pitch, flippers, ahead) {
  const [w, h] = sizeCanvas(c);
  const g = c.getContext('2d');
  g.fillStyle = '#1b2430'; g.fillRect(0, 0, w, h);
  const xMin = -0.8, xMax = 1.6, scale = w / (xMax - xMin);
  const zBase = h * 0.72;
  const X = (x) => (x - xMin) * scale, Z = (z) => zBase - z * scale;
  // Terrain.
  const d = ahead?.d_m ?? [], z = ahead?.z_m ?? [];
  g.fillStyle = '#8a7a5c';
  g.beginPath();
  if (d.length >= 2) {
    g.moveTo(X(d[0]), h);
    d.forEach((di, i) => g.lineTo(X(di), Z(num(z[i]) ? z[i] : 0)));
    g.lineTo(X(d[d.length - 1]), h);
  } else { g.moveTo(0, Z(0)); g.lineTo(w, Z(0)); g.lineTo(w, h); g.lineTo(0, h); }
  g.closePath(); g.fill();
  // Robot: body frame point (x, z) -> pitched, lifted by the ride height.
  const cp = Math.cos(pitch || 0), sp = Math.sin(pitch || 0), lift = geo.rideHeight;
  const P = ([x, zz]) => [X(x * cp + zz * sp), Z(-x * sp + zz * cp + lift)];
  const poly = (pts, fill, stroke) => {
    if (pts.length < 2) return;
    g.beginPath();
    pts.forEach((p, i) => { const [a, b] = P(p); if (i) g.lineTo(a, b); else g.moveTo(a, b); });
    g.closePath();
    if (fill) { g.fillStyle = fill; g.fill(); }
    if (stroke) { g.strokeStyle = stroke; g.lineWidth = 1.5; g.stroke(); }
  };
  const rot = (f, a) => ([x, zz]) => {
    // About the pivot, by the flipper angle about its axis (REP 103: about +y, x toward -z).
    const t = a * f.sign, c2 = Math.cos(t), s2 = Math.sin(t);
    const dx = x - f.pivot[0], dz = zz - f.pivot[1];
    return [f.pivot[0] + dx * c2 + dz * s2, f.pivot[1] - dx * s2 + dz * c2];
  };
  for (const t of geo.tracks) if (t.parent < 0) poly(t.pts, '#2a2a2a', '#111');
  poly(geo.body, '#5f7044', '#c8d8a0');
  geo.flippers.forEach((f, i) => {
    const a = flippers?.[i] ?? 0;
    const own = geo.tracks.filter((t) => t.parent === i).map((t) => t.pts);
    for (const pts of own.length ? own : [f.pts]) poly(pts.map(rot(f, a)), 'rgba(230,160,40,0.55)', '#f0b040');
  });
  // Step ahead.
  if (num(ahead?.step_m)) {
    g.fillStyle = '#eee'; g.font = '11px ui-monospace, monospace';
    g.fillText(`step ahead ${ahead.step_m.toFixed(2)} m`, 4, 12);
  }
  return { scale, zBase, xMin };
}

/** The largest rise within 1 m ahead (d in (0, 1]) of a profile, m. */
export function stepAhead(ahead) {
  if (!ahead?.d_m) return null;
  let best = 0;
  ahead.d_m.forEach((d, i) => { if (d > 0 && d <= 1 + 1e-9 && num(ahead.z_m[i])) best = Math.max(best, ahead.z_m[i]); });
  return best;
}

/**
 * The HUD's warnings on the page: `els` holds the DOM elements (warn panel, stall badge,
 * canvases, banners, course panel); update(vs) draws view state `vs`:
 * { t, pose:[x,y,z,roll,pitch,yaw], forward_mps, belt_cmd:[], slip:[]|null, stall:bool|null,
 *   flipper:[rad], tilt_limit_deg, ahead:{d_m,z_m,step_m}|null, outcome:{name,reason,t}|null,
 *   course:{...}|null, driver:{connected,grace_left_s}|null }.
 */
export function createHud(vehicle, els) {
  const geo = sideGeometry(vehicle);
  const names = (vehicle.tracks ?? []).map((t) => t.name);
  const stall = new StallDetector();
  els.slip.style.height = `${Math.max(44, 12 * names.length)}px`; // a 12 px row per track
  const info = { stall: false, stallSource: null, slip: null, tiltFrac: 0, tiltLevel: 'ok', banner: null, driverBanner: null, course: null, side: null };
  function update(vs) {
    const [, , , roll = 0, pitch = 0] = vs.pose ?? [];
    // Stall: the server's flag, else the client-side rule.
    const local = stall.update(vs.t ?? 0, vs.belt_cmd, vs.forward_mps);
    const stalled = typeof vs.stall === 'boolean' ? vs.stall : local;
    info.stall = stalled;
    info.stallSource = typeof vs.stall === 'boolean' ? 'server' : 'page';
    els.stall.classList.toggle('on', stalled);
    // Slip.
    info.slip = drawSlip(els.slip, names, vs.slip);
    // Tilt.
    const limit = num(vs.tilt_limit_deg) ? vs.tilt_limit_deg : 90;
    const frac = drawTilt(els.tilt, deg(roll), deg(pitch), limit);
    info.tiltFrac = frac;
    info.tiltLevel = frac >= TILT_RED ? 'red' : frac >= TILT_AMBER ? 'amber' : 'ok';
    els.tiltWarn.classList.toggle('on', frac >= TILT_RED);
    els.tiltWarn.classList.toggle('amber', frac >= TILT_AMBER && frac < TILT_RED);
    els.tiltTitle.textContent = `tip-over (limit ${fmt(limit, 0)}°, tilt ${fmt(tiltDeg(roll, pitch), 0)}°)`;
    // Side view.
    const ahead = vs.ahead ? { ...vs.ahead, step_m: num(vs.ahead.step_m) ? vs.ahead.step_m : stepAhead(vs.ahead) } : null;
    info.side = drawSide(els.side, geo, pitch, vs.flipper, ahead);
    info.step_m = ahead?.step_m ?? null;
    // Outcome banner.
    const o = vs.outcome;
    if (o && o.name && o.name !== 'undecided') {
      const kind = o.name === 'success' ? 'success' : o.name === 'failure' ? 'failure' : 'other';
      els.banner.className = `banner ${kind}`;
      els.banner.textContent = `${o.name.toUpperCase().replace(/_/g, ' ')}${o.reason ? ': ' + o.reason : ''}${num(o.t) ? ` (t = ${o.t.toFixed(2)} s)` : ''}`;
      info.banner = { kind, text: els.banner.textContent };
    } else { els.banner.className = 'banner hidden'; info.banner = null; }
    // Driver connection.
    const dr = vs.driver;
    if (dr && dr.connected === false) {
      els.driver.classList.remove('hidden');
      els.driver.textContent = num(dr.grace_left_s)
        ? `driver disconnected — reconnect within ${Math.ceil(dr.grace_left_s)} s`
        : 'driver disconnected';
      info.driverBanner = els.driver.textContent;
    } else { els.driver.classList.add('hidden'); info.driverBanner = null; }
    // Course score.
    const cs = vs.course;
    const scored = cs && ['name', 'next_gate', 'repetitions_done', 'repetitions', 'faults', 'elapsed_s'].some((k) => cs[k] !== undefined && cs[k] !== null);
    if (scored) {
      els.course.classList.remove('hidden');
      const pick = (...ks) => { for (const k of ks) if (cs[k] !== undefined && cs[k] !== null) return cs[k]; return undefined; };
      const faults = pick('faults') ?? {};
      // run/course.rs CourseScore: repetitions_done of repetitions_required.
      const reps = pick('repetitions_done', 'repetitions', 'laps_done', 'reps');
      const laps = pick('repetitions_required', 'laps', 'repetitions_total');
      const next = pick('next_gate');
      const total = pick('gates_total', 'gates');
      const lines = [
        `course  ${cs.name ?? ''}`,
        `reps    ${reps ?? '-'}${laps !== undefined ? ' / ' + laps : ''}`,
        `time    ${fmt(pick('elapsed_s', 't_s'), 1)} s${num(pick('time_limit_s')) ? ' of ' + fmt(pick('time_limit_s'), 0) + ' s' : ''}`,
        `gate    ${num(next) ? next + 1 : '-'}${num(total) ? ' / ' + total : Array.isArray(total) ? ' / ' + total.length : ''}`,
        ...(num(pick('gates_passed')) ? [`passed  ${pick('gates_passed')} gates`] : []),
        `faults  ${Object.entries(faults).map(([k, n]) => `${k.replace(/_/g, '-')} ${n}`).join(', ') || 'none'}`,
        ...(num(pick('penalty_s')) ? [`penalty ${fmt(pick('penalty_s'), 1)} s`] : []),
        ...(num(cs.score?.score_s) ? [`score   ${fmt(cs.score.score_s, 1)} s`] : []),
        ...((pick('rep_times_s') ?? []).length ? [`laps    ${pick('rep_times_s').map((x) => fmt(x, 1)).join(' ')} s`] : []),
        ...(pick('finished') ? ['FINISHED'] : []),
        // Several robots on the course (run/standings.rs): the race or the team, best first.
        ...(Array.isArray(vs.standings?.robots) ? [
          `${vs.standings.rule === 'first' ? 'race' : 'team'}    ${vs.standings.completed} / ${vs.standings.robots.length} in${vs.standings.winner ? `, won by ${vs.standings.winner}` : ''}`,
          ...vs.standings.robots.map((x) => `  ${x.rank}. ${x.name} ${x.status === 'completed' ? `${fmt(x.score_s, 1)} s` : `rep ${x.repetitions} gate ${x.gates_passed}`}`),
        ] : []),
      ];
      els.course.textContent = lines.join('\n');
      info.course = lines;
    } else { els.course.classList.add('hidden'); info.course = null; }
    return info;
  }
  return { update, info, geo, stall };
}
