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
let lastPose = null;
function pose(x, y, z, roll, pitch, yaw, flippers, beltPositions) {
  robot.position.set(x, y, z);
  euler.set(roll, pitch, yaw, 'ZYX'); // Rz(yaw) Ry(pitch) Rx(roll), REP 103
  robot.quaternion.setFromEuler(euler);
  flippers.forEach((a, i) => flipperPivots[i]?.pivot.quaternion.setFromAxisAngle(flipperPivots[i].axis, a));
  tracks.forEach((tk, i) => placeGrousers(tk, beltPositions[i] ?? 0));
  if (grid) grid.position.set(Math.round(x), Math.round(y), grid.position.z);
  lastPose = [x, y, z, roll, pitch, yaw];
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

// ---------- sensors: lidar hits, depth images, onboard cameras ----------
// scene.sensors (scene.json) places each sensor in its mount's frame: the body (`robot`) or a
// flipper (its `inner` group: the body frame at flipper angle 0, turning with the flipper).
const sensors = scene.sensors ?? [];
const mountFrame = (s) => (s.mount_index >= 0 && flipperPivots[s.mount_index] ? flipperPivots[s.mount_index].inner : robot);
const lidarMat = new THREE.PointsMaterial({ color: 0xff3030, size: 4, sizeAttenuation: false });
const lidars = {};
for (const s of sensors.filter((x) => x.kind === 'lidar')) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * 1024), 3));
  g.setDrawRange(0, 0);
  const points = new THREE.Points(g, lidarMat);
  points.frustumCulled = false;
  world.add(points); // world-frame points
  lidars[s.name] = { s, points, count: 0, hits: 0, t: null };
}
// Draws `n` world-frame points (flat x y z in `flat`) as lidar `l`'s cloud.
function setLidar(l, flat, n, t, hits) {
  const g = l.points.geometry;
  if (g.attributes.position.count < n) {
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * n), 3));
  }
  g.attributes.position.array.set(flat.subarray ? flat.subarray(0, 3 * n) : flat.slice(0, 3 * n));
  g.attributes.position.needsUpdate = true;
  g.setDrawRange(0, n);
  Object.assign(l, { count: n, hits, t });
}
api.lidar = () => Object.fromEntries(Object.entries(lidars).map(([k, l]) => [k, { count: l.count, hits: l.hits, t: l.t }]));
api.lidarPoints = (name) => Array.from(lidars[name].points.geometry.attributes.position.array.subarray(0, 3 * lidars[name].count));

// The depth panel: a camera's latest image, grey from the nearest depth in the image (bright)
// to the farthest (dim), no return dark blue.
const cams = sensors.filter((x) => x.kind === 'depth_camera');
let depthShown = cams.length > 0;
api.depth = {};
api.depthPose = {};
// Draws a depth image of camera `name`: `at(i)` is pixel i's depth, m (row-major from the top
// left; 0 or not finite: no return).
function drawDepth(name, w, h, at, t) {
  const c = $('depth-canvas');
  if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
  const g = c.getContext('2d');
  const img = g.createImageData(w, h);
  let lo = Infinity, hi = -Infinity, returns = 0;
  for (let i = 0; i < w * h; i++) { const d = at(i); if (d > 0 && Number.isFinite(d)) { lo = Math.min(lo, d); hi = Math.max(hi, d); returns++; } }
  const span = Math.max(hi - lo, 1e-6);
  for (let i = 0; i < w * h; i++) {
    const d = at(i);
    const o = 4 * i;
    if (!(d > 0) || !Number.isFinite(d)) { img.data[o] = 20; img.data[o + 1] = 30; img.data[o + 2] = 70; }
    else { const y = 255 - 200 * ((d - lo) / span); img.data[o] = img.data[o + 1] = img.data[o + 2] = y; }
    img.data[o + 3] = 255;
  }
  g.putImageData(img, 0, 0);
  const range = returns ? `${lo.toFixed(2)} m bright .. ${hi.toFixed(2)} m dim` : 'no return';
  $('depth-title').textContent = `${name} depth, t = ${t.toFixed(2)} s: ${range}`;
  api.depth[name] = { t, width: w, height: h, returns, near_m: lo, far_m: hi };
}
function showDepth(on) { depthShown = on && cams.length > 0; $('depth').classList.toggle('hidden', !depthShown); api.depthShown = depthShown; }
showDepth(depthShown);

// Views: the follow camera, then each depth camera's mount (or, without one, a default mount
// on the chassis front, on top of the body at its front, looking forward). The three.js camera
// looks along its -z with +y up; a sensor looks along its +x with +z up.
const views = [{ name: 'follow' }];
function addMount(name, frame, xyz, quat, hfov) {
  const anchor = new THREE.Object3D();
  anchor.position.fromArray(xyz);
  anchor.quaternion.fromArray(quat);
  frame.add(anchor);
  views.push({ name, anchor, hfov });
}
for (const s of cams) addMount(`camera ${s.name}`, mountFrame(s), s.xyz_m, s.quat_xyzw, s.depth_camera.horizontal_fov_rad);
if (cams.length === 0) {
  const vx = v.body.vertices_m;
  let maxX = -Infinity, maxZ = -Infinity;
  for (let i = 0; i < vx.length; i += 3) { maxX = Math.max(maxX, vx[i]); maxZ = Math.max(maxZ, vx[i + 2]); }
  if (Number.isFinite(maxX)) addMount('chassis front (default mount)', robot, [maxX + 0.01, 0, maxZ + 0.02], [0, 0, 0, 1], (90 * Math.PI) / 180);
}
const sensorToCamera = new THREE.Quaternion().setFromRotationMatrix(
  new THREE.Matrix4().makeBasis(new THREE.Vector3(0, -1, 0), new THREE.Vector3(0, 0, 1), new THREE.Vector3(-1, 0, 0)));
let viewIndex = 0;
api.views = views.map((x) => x.name);
api.view = 'follow';
function nextView() {
  viewIndex = (viewIndex + 1) % views.length;
  api.view = views[viewIndex].name;
  if (viewIndex === 0) { followInit = false; camera.fov = 50; camera.updateProjectionMatrix(); }
  orbit.enabled = viewIndex === 0;
}
// Places the camera of an onboard view at its mount (after the robot is posed).
function onboard(vw) {
  robot.updateMatrixWorld(true);
  vw.anchor.getWorldPosition(camera.position);
  vw.anchor.getWorldQuaternion(camera.quaternion).multiply(sensorToCamera);
  const fov = deg(2 * Math.atan(Math.tan(vw.hfov / 2) / camera.aspect));
  if (Math.abs(camera.fov - fov) > 1e-9) { camera.fov = fov; camera.updateProjectionMatrix(); }
}
const camDir = new THREE.Vector3();
function placeCamera() {
  const vw = views[viewIndex];
  if (vw.anchor) onboard(vw); else follow();
  camera.getWorldDirection(camDir);
  api.camera = { view: vw.name, position: camera.position.toArray(), direction: camDir.toArray(), fov_deg: camera.fov, pose: lastPose };
}
window.addEventListener('keydown', (e) => {
  const k = e.key.toLowerCase();
  if (k === 'v') nextView();
  if (k === 'b') showDepth(!depthShown);
});
const sensorHud = () => [
  `view       ${api.view} (v: next of ${views.length})`,
  ...Object.entries(lidars).map(([n, l]) => `lidar      ${n} ${l.count} points of ${l.hits} hits${l.t === null ? '' : ` (t = ${fmt(l.t)} s)`}`),
  ...cams.map((s) => `depth      ${s.name} ${api.depth[s.name] ? `t = ${fmt(api.depth[s.name].t)} s` : '-'}${depthShown ? '' : ' (b: show)'}`),
];

// Live readings (state.sensors, live/sensor_feed.rs): lidar points already in the world frame,
// depth images in whole millimetres (0: no return).
function liveSensors(entries) {
  for (const e of entries ?? []) {
    if (e.kind === 'lidar' && lidars[e.name]) setLidar(lidars[e.name], e.points, e.points.length / 3, e.t, e.hits);
    if (e.kind === 'depth_camera') {
      api.depthPose[e.name] = { t: e.t, position: e.position, orientation: e.orientation };
      drawDepth(e.name, e.width, e.height, (i) => e.depth_mm[i] / 1000, e.t);
    }
  }
}

// Replay readings: sensors/NAME.npz of the run (uncompressed numpy archive: a zip of stored
// .npy entries). Parsed here: the zip's central directory, each entry's local header, the .npy
// header (little-endian float32/float64 only) and its data.
function parseNpz(buf) {
  const dv = new DataView(buf);
  let eocd = -1;
  for (let i = buf.byteLength - 22; i >= Math.max(0, buf.byteLength - 22 - 65535); i--) {
    if (dv.getUint32(i, true) === 0x06054b50) { eocd = i; break; }
  }
  if (eocd < 0) throw new Error('npz: no zip end record');
  const entries = dv.getUint16(eocd + 10, true);
  let p = dv.getUint32(eocd + 16, true);
  const dec = new TextDecoder();
  const out = {};
  for (let e = 0; e < entries; e++) {
    if (dv.getUint32(p, true) !== 0x02014b50) throw new Error('npz: bad central directory');
    const method = dv.getUint16(p + 10, true), size = dv.getUint32(p + 20, true);
    const nameLen = dv.getUint16(p + 28, true), extraLen = dv.getUint16(p + 30, true), commentLen = dv.getUint16(p + 32, true);
    const local = dv.getUint32(p + 42, true);
    const name = dec.decode(new Uint8Array(buf, p + 46, nameLen));
    p += 46 + nameLen + extraLen + commentLen;
    if (method !== 0 || size === 0xffffffff) throw new Error(`npz: ${name} is compressed or zip64`);
    const data = local + 30 + dv.getUint16(local + 26, true) + dv.getUint16(local + 28, true);
    out[name.replace(/\.npy$/, '')] = parseNpy(buf.slice(data, data + size));
  }
  return out;
}
function parseNpy(buf) {
  const dv = new DataView(buf);
  const major = dv.getUint8(6);
  const hl = major === 1 ? dv.getUint16(8, true) : dv.getUint32(8, true);
  const start = major === 1 ? 10 : 12;
  const head = new TextDecoder().decode(new Uint8Array(buf, start, hl));
  const descr = head.match(/'descr':\s*'([^']+)'/)[1];
  const shape = head.match(/'shape':\s*\(([^)]*)\)/)[1].split(',').filter((x) => x.trim()).map(Number);
  if (/True/.test(head.match(/'fortran_order':\s*(\w+)/)[1])) throw new Error('npy: Fortran order');
  const body = buf.slice(start + hl);
  const data = descr === '<f4' ? new Float32Array(body) : descr === '<f8' ? new Float64Array(body) : null;
  if (!data) throw new Error(`npy: dtype ${descr}`);
  return { shape, data };
}
const replaySensors = [];
api.sensorFiles = {};
async function loadReplaySensors() {
  for (const s of sensors.filter((x) => x.kind === 'lidar' || x.kind === 'depth_camera')) {
    try {
      const r = await fetch(`/run/sensors/${encodeURIComponent(s.name)}.npz`);
      if (!r.ok) { api.sensorFiles[s.name] = `not served (${r.status})`; continue; }
      replaySensors.push({ s, npz: parseNpz(await r.arrayBuffer()), shown: -1 });
      api.sensorFiles[s.name] = 'loaded';
    } catch (err) {
      api.sensorFiles[s.name] = `unreadable: ${err.message}`;
      api.errors.push(String(err));
    }
  }
}
// Index of the last reading at or before `t` (-1: none yet).
function readingAt(times, t) {
  let lo = 0, hi = times.length - 1, k = -1;
  while (lo <= hi) { const mid = (lo + hi) >> 1; if (times[mid] <= t + 1e-9) { k = mid; lo = mid + 1; } else hi = mid - 1; }
  return k;
}
const qS = new THREE.Quaternion(), pS = new THREE.Vector3(), hit = new THREE.Vector3();
function replaySensorFrame(t) {
  for (const r of replaySensors) {
    const { s, npz } = r;
    const k = readingAt(npz.t_s.data, t);
    if (k < 0 || k === r.shown) continue;
    r.shown = k;
    pS.fromArray(npz.position_m.data, 3 * k);
    qS.fromArray(npz.orientation.data, 4 * k);
    if (s.kind === 'lidar') {
      const pts = npz.points_m.data;
      const per = npz.points_m.shape.slice(1).reduce((a, b) => a * b, 1);
      const flat = new Float32Array(per);
      let n = 0;
      for (let i = k * per; i < (k + 1) * per; i += 3) {
        if (!Number.isFinite(pts[i])) continue;
        hit.set(pts[i], pts[i + 1], pts[i + 2]).applyQuaternion(qS).add(pS);
        flat[3 * n] = hit.x; flat[3 * n + 1] = hit.y; flat[3 * n + 2] = hit.z; n++;
      }
      setLidar(lidars[s.name], flat, n, npz.t_s.data[k], n);
    } else {
      const [, h, w] = npz.depth_m.shape;
      const d = npz.depth_m.data, o = k * w * h;
      drawDepth(s.name, w, h, (i) => d[o + i], npz.t_s.data[k]);
    }
  }
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
  document.body.classList.add('view-mode');
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
    else if (m.type === 'state') { api.state = m; api.states++; liveSensors(m.sensors); }
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
    ...sensorHud(),
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
  await loadReplaySensors();
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
  replaySensorFrame(playTime);
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
    ...sensorHud(),
  ]);
}

if (live) connect();
function frame() {
  if (live) liveFrame(); else replayFrame();
  placeCamera();
  renderer.render(world, camera);
  api.frames++;
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
