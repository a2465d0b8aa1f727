// tracksim's 3-D page: the live view of `tracksim drive` and the replay of `tracksim view`.
// Frames are REP 103 (x forward, y left, z up): the camera's up is +z. Every length is in m.
import * as THREE from 'three';
import { OrbitControls } from '/vendor/OrbitControls.js';

const $ = (id) => document.getElementById(id);
const deg = (r) => (r * 180) / Math.PI;
const session = await (await fetch('/session.json')).json();
const scene = await (await fetch('/scene.json')).json();
const live = session.mode === 'drive';

// Exposed for tests and curious users: the latest state and what is drawn.
const api = { mode: session.mode, state: null, states: 0, frames: 0, role: null, replayTime: 0, errors: [] };
window.tracksim = api;

// ---------- renderer, camera, lights ----------
THREE.Object3D.DEFAULT_UP.set(0, 0, 1);
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setSize(window.innerWidth, window.innerHeight);
$('view').appendChild(renderer.domElement);
const world = new THREE.Scene();
world.background = new THREE.Color(0x9fb8cc);
const camera = new THREE.PerspectiveCamera(50, window.innerWidth / window.innerHeight, 0.01, 500);
camera.up.set(0, 0, 1);
const orbit = new OrbitControls(camera, renderer.domElement);
orbit.enableDamping = false;
world.add(new THREE.HemisphereLight(0xffffff, 0x445544, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(3, -4, 8);
world.add(sun);
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

function meshGeometry(m) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(m.vertices_m, 3));
  g.setIndex(m.triangles);
  const ng = g.toNonIndexed(); // flat shading: hard edges stay visible
  ng.computeVertexNormals();
  return ng;
}

// ---------- terrain ----------
const terrainMat = new THREE.MeshStandardMaterial({ color: 0xb8a586, roughness: 0.9, side: THREE.DoubleSide });
const t = scene.terrain;
let grid = null;
if (t.ground_z_m !== null) {
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(400, 400), new THREE.MeshStandardMaterial({ color: 0x8a9a78, roughness: 1 }));
  plane.position.z = t.ground_z_m;
  world.add(plane);
  grid = new THREE.GridHelper(40, 80, 0x4d5a45, 0x6d7a62);
  grid.rotation.x = Math.PI / 2; // GridHelper lies in x-z; ours lies in x-y
  grid.position.z = t.ground_z_m + 0.001;
  world.add(grid);
}
for (const b of t.boxes) {
  const m = new THREE.Mesh(new THREE.BoxGeometry(2 * b.half_m[0], 2 * b.half_m[1], 2 * b.half_m[2]), terrainMat);
  m.position.fromArray(b.centre_m);
  m.quaternion.fromArray(b.quat_xyzw);
  world.add(m);
  const edges = new THREE.LineSegments(new THREE.EdgesGeometry(m.geometry), new THREE.LineBasicMaterial({ color: 0x5a4a36 }));
  m.add(edges);
}
for (const c of t.cylinders) {
  const m = new THREE.Mesh(new THREE.CylinderGeometry(c.radius_m, c.radius_m, 2 * c.half_length_m, 24), terrainMat);
  m.position.fromArray(c.centre_m);
  m.rotation.z = c.yaw_rad; // the cylinder's axis is its local y, as in the simulation
  world.add(m);
}
for (const mesh of t.meshes) world.add(new THREE.Mesh(meshGeometry(mesh), terrainMat));
if (scene.success_x_m !== null) {
  const line = new THREE.Mesh(new THREE.BoxGeometry(0.02, 4, 0.002), new THREE.MeshBasicMaterial({ color: 0x22aa22 }));
  line.position.set(scene.success_x_m, 0, (t.ground_z_m ?? 0) + 0.002);
  world.add(line);
}

// ---------- vehicle ----------
const v = scene.vehicle;
const robot = new THREE.Group();
world.add(robot);
robot.add(new THREE.Mesh(meshGeometry(v.body), new THREE.MeshStandardMaterial({ color: 0x4f5d3a, roughness: 0.6 })));
const flipperPivots = v.flippers.map((f) => {
  const pivot = new THREE.Group();
  pivot.position.fromArray(f.pivot_m);
  const inner = new THREE.Group();
  inner.position.set(-f.pivot_m[0], -f.pivot_m[1], -f.pivot_m[2]);
  pivot.add(inner);
  robot.add(pivot);
  if (f.mesh) inner.add(new THREE.Mesh(meshGeometry(f.mesh), new THREE.MeshStandardMaterial({ color: 0x6b6b60 })));
  return { pivot, inner, axis: new THREE.Vector3().fromArray(f.axis) };
});
const beltMat = new THREE.MeshStandardMaterial({ color: 0x1d1d1d, roughness: 0.8, side: THREE.DoubleSide });
const grouserMat = new THREE.MeshStandardMaterial({ color: 0x3a3a3a, roughness: 0.5 });
// A belt along its sampled loop (lateral per sample for a loop that leaves its plane), with
// instanced grousers; `parent` is the frame its points are in.
function buildTrack(tr, parent) {
  const n = tr.s_m.length;
  const lat = new THREE.Vector3().fromArray(tr.lateral);
  const latAt = (i) => (tr.laterals ? new THREE.Vector3().fromArray(tr.laterals, 3 * i) : lat);
  const pos = [];
  const idx = [];
  for (let i = 0; i < n; i++) {
    const p = new THREE.Vector3().fromArray(tr.points_m, 3 * i);
    const a = p.clone().addScaledVector(latAt(i), 0.5 * tr.width_m);
    const b = p.clone().addScaledVector(latAt(i), -0.5 * tr.width_m);
    pos.push(a.x, a.y, a.z, b.x, b.y, b.z);
    const j = (i + 1) % n;
    idx.push(2 * i, 2 * i + 1, 2 * j, 2 * j, 2 * i + 1, 2 * j + 1);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  g.setIndex(idx);
  g.computeVertexNormals();
  parent.add(new THREE.Mesh(g, beltMat));
  const gr = tr.grousers;
  const instanced = [];
  if (gr) {
    gr.shapes.forEach((shape, si) => {
      const count = Math.ceil((gr.count - si) / gr.shapes.length);
      const im = new THREE.InstancedMesh(meshGeometry(shape), grouserMat, Math.max(count, 0));
      im.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      parent.add(im);
      instanced.push(im);
    });
  }
  return { tr, lat, instanced };
}
const tracks = v.tracks.map((tr) => buildTrack(tr, tr.parent < 0 ? robot : flipperPivots[tr.parent].inner));

// ---------- conveyors (tracks on the world) and loose boxes ----------
const conveyors = (scene.conveyors ?? []).map((c) => {
  const frame = new THREE.Group();
  frame.position.fromArray(c.centre_m);
  frame.rotation.z = c.yaw_rad;
  world.add(frame);
  return buildTrack(c.track, frame);
});
const looseMat = new THREE.MeshStandardMaterial({ color: 0xb5651d, roughness: 0.7 });
const looseBoxes = (scene.loose_boxes ?? []).map((b) => {
  const m = new THREE.Mesh(new THREE.BoxGeometry(2 * b.half_m[0], 2 * b.half_m[1], 2 * b.half_m[2]), looseMat);
  m.position.fromArray(b.centre_m); // the start; a replay moves it (a live view does not)
  m.rotation.z = b.yaw_rad;
  world.add(m);
  return m;
});
api.conveyors = conveyors.length;
api.looseBoxes = looseBoxes.length;

// Grousers at arc length offset + k * pitch + s along the path, s the belt's unwrapped
// position: they run with the belt (the simulation's one-pitch rollback of the links is not
// drawn, only the belt's true motion).
const mtx = new THREE.Matrix4();
const latA = new THREE.Vector3(), latB = new THREE.Vector3();
const pA = new THREE.Vector3(), pB = new THREE.Vector3(), nA = new THREE.Vector3(), nB = new THREE.Vector3(), tan = new THREE.Vector3();
function placeGrousers(track, beltPos) {
  const { tr, lat, instanced } = track;
  const gr = tr.grousers;
  if (!gr) return;
  const L = tr.length_m, n = tr.s_m.length, ns = gr.shapes.length;
  for (let k = 0; k < gr.count; k++) {
    let s = (gr.offset_m + k * gr.pitch_m + beltPos) % L;
    if (s < 0) s += L;
    const f = (s / L) * n;
    const i = Math.floor(f) % n, j = (i + 1) % n, w = f - Math.floor(f);
    pA.fromArray(tr.points_m, 3 * i); pB.fromArray(tr.points_m, 3 * j);
    nA.fromArray(tr.normals, 3 * i); nB.fromArray(tr.normals, 3 * j);
    pA.lerp(pB, w);
    nA.lerp(nB, w).normalize();
    const l = tr.laterals ? latA.fromArray(tr.laterals, 3 * i).lerp(latB.fromArray(tr.laterals, 3 * j), w).normalize() : lat;
    tan.crossVectors(l, nA).normalize(); // normal = tangent x lateral
    mtx.makeBasis(tan, l, nA).setPosition(pA);
    instanced[k % ns].setMatrixAt(Math.floor(k / ns), mtx);
  }
  for (const im of instanced) im.instanceMatrix.needsUpdate = true;
}
// Cleats at their start (a replay moves them; the live state does not stream conveyors).
conveyors.forEach((c) => placeGrousers(c, 0));

const euler = new THREE.Euler();
function pose(x, y, z, roll, pitch, yaw, flippers, beltPositions) {
  robot.position.set(x, y, z);
  euler.set(roll, pitch, yaw, 'ZYX'); // Rz(yaw) Ry(pitch) Rx(roll), REP 103
  robot.quaternion.setFromEuler(euler);
  flippers.forEach((a, i) => flipperPivots[i]?.pivot.quaternion.setFromAxisAngle(flipperPivots[i].axis, a));
  tracks.forEach((tk, i) => placeGrousers(tk, beltPositions[i] ?? 0));
  if (grid) grid.position.set(Math.round(x), Math.round(y), grid.position.z);
}

// ---------- camera that follows ----------
let followInit = false;
function follow() {
  const p = robot.position;
  if (!followInit) {
    camera.position.set(p.x - 1.4, p.y - 1.6, p.z + 0.9);
    orbit.target.copy(p);
    followInit = true;
  } else {
    const d = p.clone().sub(orbit.target);
    camera.position.add(d);
    orbit.target.copy(p);
  }
  orbit.update();
}

// ---------- HUD ----------
const flipperNames = v.flippers.map((f) => f.name);
const trackNames = v.tracks.map((tr) => tr.name);
function hud(lines) { $('hud').textContent = lines.join('\n'); }
const fmt = (x, d = 2) => (x === null || x === undefined || Number.isNaN(x) ? '-' : x.toFixed(d));

// ---------- drive ----------
let speedLin = 0.3, speedAng = 1.0;
const held = new Set();
const flipperDeg = v.flippers.map((f) => deg(f.initial_angle_rad));
const flipperTouched = v.flippers.map(() => false);
// Flipper pairs: names equal once "left"/"right" are removed (front_left + front_right).
const pairs = [];
v.flippers.forEach((f, i) => {
  const key = f.name.replace(/_?(left|right)_?/g, '') || f.name;
  let p = pairs.find((q) => q.key === key);
  if (!p) pairs.push((p = { key, members: [] }));
  p.members.push(i);
});
const pairKeys = [['r', 'f'], ['y', 'h'], ['p', ';']];
const moveKeys = {
  w: [1, 0], arrowup: [1, 0], s: [-1, 0], arrowdown: [-1, 0], a: [0, 1], arrowleft: [0, 1], d: [0, -1], arrowright: [0, -1],
  i: [1, 0], ',': [-1, 0], j: [0, 1], l: [0, -1], u: [1, 1], o: [1, -1], m: [-1, -1], '.': [-1, 1],
};
if (live) {
  $('help-flippers').innerHTML = pairs.length
    ? '<td>' + pairs.map((p, i) => (pairKeys[i] ? `<kbd>${pairKeys[i][0]}</kbd>/<kbd>${pairKeys[i][1]}</kbd>` : '')).join('<br>') + '</td><td>' +
      pairs.map((p) => `${p.members.map((i) => flipperNames[i]).join(' + ')}: +/- 5 deg`).join('<br>') + '</td>'
    : '<td></td><td>(no flippers)</td>';
} else {
  $('help-drive').classList.add('hidden');
  $('help-view').classList.remove('hidden');
}

let ws = null;
function send(msg) { if (ws && ws.readyState === 1) ws.send(JSON.stringify(msg)); }
function stopAll() { held.clear(); pad.stopped = true; }
const pad = { stopped: false, prev: [] };

window.addEventListener('keydown', (e) => {
  if (!live) {
    if (e.key === ' ') { togglePlay(); e.preventDefault(); }
    return;
  }
  const k = e.key.toLowerCase();
  if (k in moveKeys) { held.add(k); e.preventDefault(); return; }
  if (k === ' ' || k === 'k') { stopAll(); e.preventDefault(); return; }
  if (k === 'backspace') { stopAll(); send({ type: 'reset' }); flipperDeg.forEach((_, i) => { flipperDeg[i] = deg(v.flippers[i].initial_angle_rad); flipperTouched[i] = false; }); e.preventDefault(); return; }
  if (k === 'q') { speedLin *= 1.1; speedAng *= 1.1; }
  if (k === 'z') { speedLin /= 1.1; speedAng /= 1.1; }
  if (k === 'e') speedAng *= 1.1;
  if (k === 'c') speedAng /= 1.1;
  pairKeys.forEach(([up, down], pi) => {
    if (!pairs[pi] || (k !== up && k !== down)) return;
    for (const i of pairs[pi].members) { flipperDeg[i] += k === up ? 5 : -5; flipperTouched[i] = true; }
  });
});
window.addEventListener('keyup', (e) => held.delete(e.key.toLowerCase()));
window.addEventListener('blur', () => held.clear());

function gamepadControl() {
  const gp = navigator.getGamepads ? [...navigator.getGamepads()].find((g) => g) : null;
  if (!gp) return null;
  const b = (i) => !!gp.buttons[i]?.pressed;
  const edge = (i) => b(i) && !pad.prev[i];
  const pairsBtn = [[12, 13], [3, 0]];
  pairsBtn.forEach(([up, down], pi) => {
    if (!pairs[pi]) return;
    if (edge(up) || edge(down)) for (const i of pairs[pi].members) { flipperDeg[i] += edge(up) ? 5 : -5; flipperTouched[i] = true; }
  });
  pad.prev = gp.buttons.map((x) => x.pressed);
  if (!b(4)) return [0, 0]; // dead-man (LB) released: stop
  const dz = (x) => (Math.abs(x) < 0.1 ? 0 : x);
  const turbo = b(5) ? 2 : 1;
  return [-dz(gp.axes[1] ?? 0) * speedLin * turbo, -dz(gp.axes[0] ?? 0) * speedAng * turbo];
}

let lastSent = '';
function driveTick() {
  let f = 0, w = 0;
  for (const k of held) { f += moveKeys[k][0]; w += moveKeys[k][1]; }
  f = Math.sign(f) * speedLin;
  w = Math.sign(w) * speedAng;
  const g = gamepadControl();
  if (g && (g[0] || g[1]) && held.size === 0) [f, w] = g;
  const msg = { type: 'control', forward_mps: f, yaw_rate_rad_s: w, flipper_angle_deg: flipperDeg.map((a, i) => (flipperTouched[i] ? a : null)) };
  const text = JSON.stringify(msg);
  if (text !== lastSent && ws && ws.readyState === 1) { ws.send(text); lastSent = text; }
}

let ended = false;
function connect() {
  ws = new WebSocket(`ws://${location.host}/ws`);
  ws.onmessage = (ev) => {
    const m = JSON.parse(ev.data);
    if (m.type === 'hello') api.role = m.role;
    else if (m.type === 'state') { api.state = m; api.states++; }
    else if (m.type === 'error') api.errors.push(m.message);
  };
  ws.onclose = () => { ended = true; };
}
$('stop').addEventListener('click', () => send({ type: 'stop' }));

function liveFrame() {
  driveTick();
  const s = api.state;
  if (!s) { hud(['waiting for the simulation ...']); return; }
  const [x, y, z, roll, pitch, yaw] = s.pose;
  pose(x, y, z, roll, pitch, yaw, s.flipper, s.belt_position);
  const o = s.outcome ? `${s.outcome.name}: ${s.outcome.reason} (t = ${fmt(s.outcome.t)} s)` : 'undecided';
  hud([
    `${ended ? 'SESSION ENDED (outputs written)' : api.role === 'driver' ? 'DRIVING' : 'WATCHING (another page drives)'}`,
    `sim time   ${fmt(s.t, 2)} s   x${fmt(s.speed, 2)} requested`,
    `RTF        paced ${fmt(s.rtf_paced, 2)}   compute ${fmt(s.rtf_compute, 1)}`,
    `speed      ${fmt(s.forward_mps, 3)} m/s (0.1 s mean)   cmd ${fmt(s.control.forward_mps, 2)} m/s, ${fmt(s.control.yaw_rate_rad_s, 2)} rad/s`,
    `set speeds ${fmt(speedLin, 2)} m/s, ${fmt(speedAng, 2)} rad/s`,
    `roll/pitch ${fmt(deg(roll), 1)} / ${fmt(deg(pitch), 1)} deg   yaw ${fmt(deg(yaw), 1)} deg`,
    `position   ${fmt(x, 3)} ${fmt(y, 3)} ${fmt(z, 3)} m`,
    ...flipperNames.map((n, i) => `flipper    ${n} ${fmt(deg(s.flipper[i]), 1)} deg (target ${fmt(flipperDeg[i], 0)})`),
    ...trackNames.map((n, i) => `belt       ${n} ${fmt(s.belt_speed[i], 3)} m/s`),
    `outcome    ${o}`,
  ]);
}

// ---------- replay ----------
function parseCsv(text) {
  const lines = text.trim().split('\n');
  const head = lines[0].split(',');
  const rows = lines.slice(1).map((l) => l.split(',').map(Number));
  const col = (name) => head.indexOf(name);
  return { head, rows, col };
}
let replay = null;
let playing = true, playTime = 0, lastWall = null;
function togglePlay() { playing = !playing; $('play').textContent = playing ? 'pause' : 'play'; }
if (!live) {
  const traj = parseCsv(await (await fetch('/run/trajectory.csv')).text());
  const belts = parseCsv(await (await fetch('/run/belts.csv')).text());
  const summaryResp = await fetch('/run/summary.json');
  const summary = summaryResp.ok ? await summaryResp.json() : null;
  const c = (n) => traj.col(n);
  replay = {
    traj, belts, summary,
    pose: ['x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad'].map(c),
    flip: flipperNames.map((n) => c(`flipper_${n}_rad`)),
    speed: trackNames.map((n) => c(`belt_speed_${n}_mps`)),
    beltPos: trackNames.map((n) => belts.col(`belt_position_${n}_m`)),
    conveyorPos: conveyors.map((_, i) => belts.col(`conveyor_position_${i}_m`)),
    boxPose: looseBoxes.map((_, i) => ['x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad'].map((c) => belts.col(`box_${i}_${c}`))),
    end: traj.rows[traj.rows.length - 1][0],
  };
  api.replayEnd = replay.end;
  $('bar').classList.remove('hidden');
  $('play').addEventListener('click', togglePlay);
  $('scrub').addEventListener('input', (e) => { playTime = Number(e.target.value) * replay.end; });
}
function lerpRow(rows, t) {
  let lo = 0, hi = rows.length - 1;
  if (t <= rows[0][0]) return rows[0];
  if (t >= rows[hi][0]) return rows[hi];
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (rows[mid][0] <= t) lo = mid; else hi = mid; }
  const a = rows[lo], b = rows[hi], w = (t - a[0]) / (b[0] - a[0] || 1);
  return a.map((x, i) => x + (b[i] - x) * w);
}
function lerpAngle(a, b, w) { let d = b - a; while (d > Math.PI) d -= 2 * Math.PI; while (d < -Math.PI) d += 2 * Math.PI; return a + d * w; }
function replayFrame() {
  const now = performance.now();
  if (lastWall !== null && playing) playTime += ((now - lastWall) / 1000) * Number($('rate').value);
  lastWall = now;
  if (playTime > replay.end) playTime = 0; // loop
  api.replayTime = playTime;
  const r = lerpRow(replay.traj.rows, playTime);
  // Yaw is interpolated the short way round.
  const rows = replay.traj.rows;
  let k = rows.findIndex((row) => row[0] > playTime);
  if (k > 0) {
    const a = rows[k - 1], b = rows[k];
    const w = (playTime - a[0]) / (b[0] - a[0] || 1);
    r[replay.pose[5]] = lerpAngle(a[replay.pose[5]], b[replay.pose[5]], w);
  }
  const br = lerpRow(replay.belts.rows, playTime);
  const [x, y, z, roll, pitch, yaw] = replay.pose.map((i) => r[i]);
  pose(x, y, z, roll, pitch, yaw, replay.flip.map((i) => r[i]), replay.beltPos.map((i) => br[i]));
  conveyors.forEach((c, i) => placeGrousers(c, br[replay.conveyorPos[i]] ?? 0));
  looseBoxes.forEach((m, i) => {
    const [bx, by, bz, br_, bp, byaw] = replay.boxPose[i].map((k) => br[k]);
    m.position.set(bx, by, bz);
    euler.set(br_, bp, byaw, 'ZYX');
    m.quaternion.setFromEuler(euler);
  });
  $('scrub').value = String(playTime / (replay.end || 1));
  $('clock').textContent = `${fmt(playTime, 2)} / ${fmt(replay.end, 2)} s`;
  const s = replay.summary;
  const decided = s && playTime >= s.outcome_time_s ? `${s.outcome}: ${s.outcome_reason}` : 'undecided';
  hud([
    `REPLAY     ${playing ? 'playing' : 'paused'} at ${$('rate').value} x`,
    `sim time   ${fmt(playTime, 2)} s of ${fmt(replay.end, 2)} s`,
    s ? `RTF        of the run: compute ${fmt(s.real_time_factor, 1)}` : '',
    `roll/pitch ${fmt(deg(roll), 1)} / ${fmt(deg(pitch), 1)} deg   yaw ${fmt(deg(yaw), 1)} deg`,
    `position   ${fmt(x, 3)} ${fmt(y, 3)} ${fmt(z, 3)} m`,
    ...flipperNames.map((n, i) => `flipper    ${n} ${fmt(deg(r[replay.flip[i]]), 1)} deg`),
    ...trackNames.map((n, i) => `belt       ${n} ${fmt(r[replay.speed[i]], 3)} m/s`),
    `outcome    ${decided}`,
  ]);
}

if (live) connect();
function frame() {
  if (live) liveFrame(); else replayFrame();
  follow();
  renderer.render(world, camera);
  api.frames++;
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
