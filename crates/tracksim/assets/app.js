// tracksim's 3-D page: the live view of `tracksim drive` and the replay of `tracksim view`.
// Frames are REP 103 (x forward, y left, z up): the camera's up is +z. Every length is in m.
import * as THREE from 'three';
import { OrbitControls } from '/vendor/OrbitControls.js';
import { createHud, tiltDeg } from '/hud.js';
import { createMinimap, gateEnds, itemYaw } from '/minimap.js';
import { computeEvents, eventColour, jumpTarget, inputSeries, drawInputs, courseAt, patchAt } from '/review.js';
import { createRuts, parseRuts } from '/ruts.js';

const $ = (id) => document.getElementById(id);
const deg = (r) => (r * 180) / Math.PI;
const session = await (await fetch('/session.json')).json();
// A session of several robots: `?robot=NAME` drives (or with `watch=1` follows) that robot;
// its scene holds its own vehicle. Names are ROS-safe ([a-z][a-z0-9_]*): nothing to escape.
const query = new URLSearchParams(location.search);
const askedRobot = /^[a-z][a-z0-9_]{0,63}$/.test(query.get('robot') ?? '') ? query.get('robot') : null;
const watchOnly = query.get('watch') === '1';
// The instructor's page (issue 43): opened as /?instructor=TOKEN, the URL `tracksim drive`
// printed (the token is never served: live/instructor.rs). It never drives, shows everything
// (a trainee's dropped video too) and has the instructor's panel.
const instructorToken = /^[0-9a-f]{32}$/.test(query.get('instructor') ?? '') ? query.get('instructor') : null;
const live = session.mode === 'drive';
// A watch-only session (a learning environment's `render_mode="human"`, live/watch.rs): the
// server says so in /session.json; nobody drives, so the page has no drive controls, no
// driver's status, and shows what the learner commands (belts, flipper targets).
const watchSession = live && session.watch_only === true;
// The runs a replay shows: one, or every method of a `tracksim compare` folder (/runs.json).
let runs = { compare: false, runs: [{ index: 0, name: 'run', base: '/run' }] };
if (!live) {
  const r = await fetch('/runs.json');
  if (r.ok) runs = await r.json();
}
// A team run's review: `?robot=NAME` makes that robot the solid one (the review panel is its),
// the others ghosts; by default the first by name.
if (!live && runs.team && askedRobot) {
  const k = runs.runs.findIndex((r) => r.name === askedRobot);
  if (k > 0) runs.runs.unshift(...runs.runs.splice(k, 1));
}
// A session's attempts (issue 43): `?attempt=N` replays attempt N (each reset kept one).
const attempts = Array.isArray(runs.attempts) ? runs.attempts : [];
const attempt = attempts.find((a) => String(a.attempt) === query.get('attempt')) ?? attempts[attempts.length - 1] ?? null;
if (attempt && attempt.base !== '/run') runs.runs[0].base = attempt.base;
const sceneUrl = attempt && attempt.base !== '/run' ? `${attempt.base}/scene.json`
  : !live && runs.team ? `${runs.runs[0].base}/scene.json`
  : `/scene.json${askedRobot ? `?robot=${askedRobot}` : ''}`;
const scene = await (await fetch(sceneUrl)).json();
if (attempts.length > 1) {
  const sel = document.createElement('select');
  sel.id = 'attempt';
  sel.style.cssText = 'position:fixed;top:8px;left:50%;transform:translateX(-50%);z-index:6;font:13px monospace';
  for (const a of attempts) {
    const o = document.createElement('option');
    o.value = a.attempt;
    o.textContent = `attempt ${a.attempt} of ${attempts.length}${a.outcome ? `: ${a.outcome}` : ''}`;
    o.selected = a === attempt;
    sel.appendChild(o);
  }
  sel.addEventListener('change', () => { location.search = `?attempt=${sel.value}`; });
  document.body.appendChild(sel);
}

// Exposed for tests and curious users: the latest state and what is drawn.
const api = { mode: session.mode, watchOnly: watchSession, state: null, states: 0, frames: 0, role: null, replayTime: 0, errors: [], hudOverride: null };
window.tracksim = api;
// A session's attempts (replay), and the one shown.
api.attempts = attempts.map((a) => a.attempt);
api.attempt = attempt ? attempt.attempt : null;

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
// Ruts in deformable soil (ruts.js): filled from `ruts.csv` in a replay, from the states live.
const ruts = createRuts(THREE, world);
api.ruts = ruts;
const rutLog = { epoch: null, next: 0 };
if (scene.success_x_m !== null) {
  const line = new THREE.Mesh(new THREE.BoxGeometry(0.02, 4, 0.002), new THREE.MeshBasicMaterial({ color: 0x22aa22 }));
  line.position.set(scene.success_x_m, 0, (t.ground_z_m ?? 0) + 0.002);
  world.add(line);
}
// The course (scene.course, issue 28): each gate as two posts and a bar, obstacles as red boxes.
const course = scene.course ?? null;
const gateMeshes = [];
if (course) {
  const z0 = t.ground_z_m ?? 0;
  const postMat = new THREE.MeshStandardMaterial({ color: 0x40c0ff });
  for (const gt of course.gates ?? []) {
    const e = gateEnds(gt);
    const group = new THREE.Group();
    for (const p of [e.a, e.b]) {
      const post = new THREE.Mesh(new THREE.CylinderGeometry(0.02, 0.02, 0.5, 8), postMat);
      post.rotation.x = Math.PI / 2; // the cylinder's axis is its y: stand it up along z
      post.position.set(p[0], p[1], z0 + 0.25);
      group.add(post);
    }
    const bar = new THREE.Mesh(new THREE.BoxGeometry(0.02, 2 * e.half, 0.02), postMat);
    bar.position.set(e.c[0], e.c[1], z0 + 0.5);
    bar.rotation.z = itemYaw(gt);
    group.add(bar);
    world.add(group);
    gateMeshes.push(group);
  }
  const obsMat = new THREE.MeshStandardMaterial({ color: 0xd05a3c, roughness: 0.7 });
  for (const o of course.obstacles ?? []) {
    const m = new THREE.Mesh(new THREE.BoxGeometry(2 * o.half_m[0], 2 * o.half_m[1], 2 * o.half_m[2]), obsMat);
    m.position.fromArray(o.centre_m);
    m.rotation.z = itemYaw(o);
    world.add(m);
  }
}
api.course = course ? { gates: gateMeshes.length, obstacles: (course.obstacles ?? []).length } : null;
// What the side-view gauge ray-casts when the state brings no profile ahead.
const terrainObjects = world.children.filter((o) => o.isMesh);

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
  const beltMesh = new THREE.Mesh(g, beltMat);
  parent.add(beltMesh);
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
  return { tr, lat, instanced, beltMesh };
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
// Where track i's first grouser is drawn, in the track's frame (it moves only as the belt
// runs), m; null for a track without grousers. For tests: the belts run in the 3-D view.
const grouserAt = new THREE.Matrix4();
api.grouser = (i) => {
  const im = tracks[i]?.instanced[0];
  if (!im || im.count === 0) return null;
  im.getMatrixAt(0, grouserAt);
  return new THREE.Vector3().setFromMatrixPosition(grouserAt).toArray();
};
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

// Views (v cycles): the chase camera behind the robot ('follow'), a free mouse orbit around
// it ('orbit'), a map view from above ('top-down'), then each depth camera's mount (or,
// without one, a default mount on the chassis front, on top of the body at its front, looking
// forward). The three.js camera looks along its -z with +y up; a sensor looks along its +x
// with +z up.
const views = [{ name: 'follow' }, { name: 'orbit' }, { name: 'top-down' }];
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
// Top-down: the camera's right is world -y, its up world +x (x up the screen, as the minimap).
const topDownQuat = new THREE.Quaternion().setFromRotationMatrix(
  new THREE.Matrix4().makeBasis(new THREE.Vector3(0, -1, 0), new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 0, 1)));
/** Chase camera offset in the robot's heading frame (behind, above), m; top-down height, m. */
const CHASE_BACK_M = 1.8, CHASE_UP_M = 0.9, TOP_DOWN_M = 5;
let viewIndex = 0;
api.views = views.map((x) => x.name);
api.view = 'follow';
function setView(i) {
  viewIndex = ((i % views.length) + views.length) % views.length;
  const vw = views[viewIndex];
  api.view = vw.name;
  if (!vw.anchor && Math.abs(camera.fov - 50) > 1e-9) { camera.fov = 50; camera.updateProjectionMatrix(); }
  if (vw.name === 'orbit') followInit = false;
  orbit.enabled = vw.name === 'orbit';
}
function nextView() { setView(viewIndex + 1); }
api.setView = (name) => setView(views.findIndex((x) => x.name === name));
// Places `cam` at an onboard view's mount (after the robot is posed).
function onboard(vw, cam = camera) {
  robot.updateMatrixWorld(true);
  vw.anchor.getWorldPosition(cam.position);
  vw.anchor.getWorldQuaternion(cam.quaternion).multiply(sensorToCamera);
  const fov = deg(2 * Math.atan(Math.tan(vw.hfov / 2) / cam.aspect));
  if (Math.abs(cam.fov - fov) > 1e-9) { cam.fov = fov; cam.updateProjectionMatrix(); }
}
// The chase camera: behind the robot along its heading (yaw only), looking at it.
function chase() {
  const p = robot.position, yaw = lastPose ? lastPose[5] : 0;
  camera.position.set(p.x - CHASE_BACK_M * Math.cos(yaw), p.y - CHASE_BACK_M * Math.sin(yaw), p.z + CHASE_UP_M);
  camera.up.set(0, 0, 1);
  camera.lookAt(p.x + 0.5 * Math.cos(yaw), p.y + 0.5 * Math.sin(yaw), p.z);
  orbit.target.copy(p);
}
function topDown() {
  const p = robot.position;
  camera.position.set(p.x, p.y, p.z + TOP_DOWN_M);
  camera.quaternion.copy(topDownQuat);
  orbit.target.copy(p);
}
const camDir = new THREE.Vector3();
function placeCamera() {
  const vw = views[viewIndex];
  if (vw.anchor) onboard(vw);
  else if (vw.name === 'follow') chase();
  else if (vw.name === 'top-down') topDown();
  else follow();
  camera.getWorldDirection(camDir);
  api.camera = { view: vw.name, position: camera.position.toArray(), direction: camDir.toArray(), fov_deg: camera.fov, pose: lastPose };
}
orbit.enabled = false;

// Picture in picture: the first onboard view, drawn into a corner while another view is shown.
const pipView = views.find((x) => x.anchor) ?? null;
const pipCam = new THREE.PerspectiveCamera(60, 4 / 3, 0.01, 500);
pipCam.up.set(0, 0, 1);
let pipOn = false; // t: on (a second render of the scene each frame)
/** Size and place of the picture in picture, CSS px from the canvas's bottom right. */
// Left, above the warnings' level (and the depth panel when it is shown).
const PIP_W = 220, PIP_H = 140, PIP_LEFT = 8;
function pipRect() {
  const h = renderer.domElement.clientHeight;
  const bottom = layout() + Math.max($('warn').offsetHeight, depthShown ? $('depth').offsetHeight : 0) + 8;
  return { x: PIP_LEFT, y: bottom, w: PIP_W, h: PIP_H, top: h - bottom - PIP_H };
}
function renderPip() {
  const shown = pipOn && pipView && !views[viewIndex].anchor;
  $('pip-label').classList.toggle('hidden', !shown);
  api.pip = { on: pipOn, shown: !!shown, view: pipView?.name ?? null };
  if (!shown) return;
  const r = pipRect();
  pipCam.aspect = r.w / r.h;
  onboard(pipView, pipCam);
  renderer.setScissorTest(true);
  renderer.setScissor(r.x, r.y, r.w, r.h);
  renderer.setViewport(r.x, r.y, r.w, r.h);
  renderer.render(world, pipCam);
  renderer.setScissorTest(false);
  renderer.setViewport(0, 0, renderer.domElement.clientWidth, renderer.domElement.clientHeight);
  const lab = $('pip-label');
  lab.style.left = `${PIP_LEFT}px`; lab.style.top = `${r.top - 18}px`;
  lab.textContent = `onboard: ${pipView.name} (t: off)`;
  api.pip.rect = r;
}

// The minimap (n) and the help panel (? or F1; remembered).
let mapOn = true;
const minimap = createMinimap($('minimap'), scene);
api.minimap = minimap.info;
function showMap(on) { mapOn = on; $('minimap').classList.toggle('hidden', !on); api.mapShown = on; }
showMap(true);
const storage = (() => { try { return window.localStorage; } catch { return null; } })();
function showHelp(on) {
  $('help').classList.toggle('hidden', !on);
  $('help-tab').classList.toggle('hidden', on);
  api.helpShown = on;
  try { storage?.setItem('tracksim.help', on ? 'shown' : 'hidden'); } catch { /* private mode */ }
}
showHelp(storage?.getItem('tracksim.help') !== 'hidden');
$('help-tab').addEventListener('click', () => showHelp(true));
// The path so far (x y, every 5 cm), for the minimap.
const path = [];
function recordPath(x, y) {
  const n = path.length;
  if (n >= 2 && Math.hypot(path[n - 2] - x, path[n - 1] - y) < 0.05) return;
  if (n >= 2 && Math.hypot(path[n - 2] - x, path[n - 1] - y) > 2) path.length = 0; // a reset or a jump
  path.push(x, y);
  if (path.length > 20000) path.splice(0, 2);
}
window.addEventListener('keydown', (e) => {
  const k = e.key.toLowerCase();
  if (e.ctrlKey || e.altKey || e.metaKey) return;
  if (k === 'v') nextView();
  if (k === 'b') showDepth(!depthShown);
  if (k === 'n') showMap(!mapOn);
  if (k === 't') pipOn = !pipOn;
  if (k === '?' || e.key === 'F1') { showHelp($('help').classList.contains('hidden')); e.preventDefault(); }
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
      const r = await fetch(`${runs.runs[0].base}/sensors/${encodeURIComponent(s.name)}.npz`);
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

// ---------- warnings (hud.js) ----------
const warn = createHud(v, {
  stall: $('w-stall'), tiltWarn: $('w-tilt'), tiltTitle: $('w-tilt-title'), slip: $('w-slip'), tilt: $('w-tiltc'), side: $('w-side'),
  banner: $('banner'), driver: $('driver-banner'), course: $('course'),
});
api.hud = { update: (vs) => warn.update(vs), info: warn.info, geometry: warn.geo };
const isNum = (x) => typeof x === 'number' && Number.isFinite(x);
// The scenario's tip-over limit: scene.json's max_tilt_deg (read under the names it may take).
const sceneTiltLimit = [scene.max_tilt_deg, scene.outcome?.max_tilt_deg, scene.tilt_limit_deg].find(isNum) ?? null;
// The terrain profile ahead when the state brings none: heights (ray cast down onto the drawn
// terrain) along the heading, relative to the terrain under the body, every 0.2 m, 4 times a s.
const caster = new THREE.Raycaster();
const down = new THREE.Vector3(0, 0, -1), rayFrom = new THREE.Vector3();
let aheadCache = { at: -1, key: '', value: null };
function groundAt(x, y, zTop) {
  rayFrom.set(x, y, zTop);
  caster.set(rayFrom, down);
  caster.far = 50;
  const h = caster.intersectObjects(terrainObjects, false)[0];
  return h ? h.point.z : null;
}
function profileAhead(x, y, z, yaw) {
  const now = performance.now();
  const key = `${x.toFixed(2)},${y.toFixed(2)},${yaw.toFixed(2)}`;
  if (aheadCache.key === key || now - aheadCache.at < 250) return aheadCache.value;
  const d_m = [], z_m = [];
  const z0 = groundAt(x, y, z + 3) ?? z;
  for (let d = -0.8; d <= 1.6 + 1e-9; d += 0.2) {
    const g = groundAt(x + d * Math.cos(yaw), y + d * Math.sin(yaw), z + 3);
    d_m.push(d); z_m.push(g === null ? 0 : g - z0);
  }
  aheadCache = { at: now, key, value: { d_m, z_m, source: 'page' } };
  return aheadCache.value;
}
// Layout: the panels at the bottom stand above the replay's time bar.
function layout() {
  const base = live ? 8 : $('bar').offsetHeight + 16;
  for (const id of ['warn', 'minimap', 'depth']) $(id).style.bottom = `${base}px`;
  const below = $('hud').offsetTop + $('hud').offsetHeight + 8;
  $('course').style.top = `${below}px`;
  $('legend').style.top = `${below + ($('course').offsetHeight ? $('course').offsetHeight + 8 : 0)}px`;
  if ($('depth').offsetWidth > 0) $('warn').style.left = `${Math.max(0.5 * window.innerWidth, $('depth').offsetWidth + 16 + 0.5 * $('warn').offsetWidth)}px`;
  return base;
}

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
if (watchSession) {
  $('help-drive').classList.add('hidden');
  $('help-watch').classList.remove('hidden');
} else if (live) {
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
  if (watchSession) return; // nothing to drive: only the view keys (above) act
  if (!live) {
    if (e.key === ' ') { togglePlay(); e.preventDefault(); }
    if (e.key === '[' || e.key === ']') jumpTo(jumpTarget(events, playTime, e.key === ']' ? 1 : -1));
    return;
  }
  const k = e.key.toLowerCase();
  if (k in moveKeys) { held.add(k); e.preventDefault(); return; }
  if (k === ' ' || k === 'k') { stopAll(); e.preventDefault(); return; }
  if (k === 'backspace' && api.instructor) { api.instructor.reset(); e.preventDefault(); return; }
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
  if (instructorToken || watchSession) return; // the instructor's page and a watcher never drive
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

// ---------- several robots: the picker and the other robots ----------
// The robot picker (a session of several robots): drive a robot (its seat, if free) or
// watch one; choosing loads that robot's page.
function showRobotPicker() {
  const el = $('robots');
  if (api.robots.length < 2) { el.classList.add('hidden'); return; }
  el.classList.remove('hidden');
  const sel = $('robot-select');
  if (sel.options.length === 0) {
    for (const n of api.robots) {
      for (const w of [false, true]) {
        const o = document.createElement('option');
        o.value = `${n}${w ? ':watch' : ''}`;
        o.textContent = `${w ? 'watch' : 'drive'} ${n}`; // names are ROS-safe: text, never markup
        sel.append(o);
      }
    }
    sel.addEventListener('change', () => {
      const [n, w] = sel.value.split(':');
      location.assign(`/?robot=${n}${w ? '&watch=1' : ''}`);
    });
  }
  sel.value = `${api.robot}${watchOnly ? ':watch' : ''}`;
  $('robot-role').textContent = api.role === 'driver' ? `driving ${api.robot}` : `watching ${api.robot}`;
}

// The other robots of the world, drawn as coloured see-through copies of this page's robot
// (the state's `others`: name, pose, flipper angles), labelled on the minimap.
const others = new Map();
function placeOthers(list) {
  if (!Array.isArray(list)) return;
  for (const o of list) {
    let g = others.get(o.name);
    if (!g) {
      // Drawn once its own vehicle has come (its scene.json); nothing until then.
      g = { colour: GHOST_COLOURS[others.size % GHOST_COLOURS.length], group: null, pivots: [], now: null };
      others.set(o.name, g);
      const slot = g;
      fetch(`/scene.json?robot=${o.name}`).then((r) => r.json()).then((sc) => {
        Object.assign(slot, makeGhost(slot.colour, sc.vehicle ?? null));
        slot.vehicle = sc.vehicle?.name ?? null;
      }).catch((err) => api.errors.push(`robot ${o.name}: ${err}`));
    }
    if (!g.group) { g.now = o.pose; continue; }
    const [x, y, z, roll, pitch, yaw] = o.pose;
    g.group.position.set(x, y, z);
    euler.set(roll, pitch, yaw, 'ZYX');
    g.group.quaternion.setFromEuler(euler);
    (o.flipper ?? []).forEach((a, k) => g.pivots[k]?.pivot.quaternion.setFromAxisAngle(g.pivots[k].axis, a));
    g.now = o.pose;
  }
}
api.others = () => [...others.entries()].filter(([, g]) => g.group).map(([name, g]) => ({ name, colour: hex(g.colour), position: g.group.position.toArray(), vehicle: g.vehicle ?? null }));

let ended = false;
// A dropped connection (a reload, a network hiccup) is not the session's end: the page
// reconnects every 0.5 s, presenting the driver's token (kept for the tab in sessionStorage)
// so that it takes the driver's seat back within the server's grace (live/seat.rs). It stops
// trying once the last state said the session ended, or the grace has passed.
const TOKEN_KEY = 'tracksim-driver-token';
api.connected = false;
api.reconnects = 0;
let lostAt = null;
// The robot this page drives or follows (a session of several robots names it in its hello).
api.robot = askedRobot;
api.robots = [];
const tokenKey = () => (api.robot ? `${TOKEN_KEY}:${api.robot}` : TOKEN_KEY);
function connect() {
  let token = null;
  try { token = sessionStorage.getItem(tokenKey()); } catch (_) { /* storage off: no token */ }
  const params = new URLSearchParams();
  if (api.robot) params.set('robot', api.robot);
  if (watchOnly) params.set('watch', '1');
  if (instructorToken) params.set('instructor', instructorToken);
  else {
    if (token) params.set('token', token);
    // The session's token (from /session.json, which only this server's own pages can read):
    // without it the server lets a connection watch, never drive (live/access.rs).
    if (typeof session.token === 'string') params.set('session', session.token);
  }
  const q = params.toString();
  ws = new WebSocket(`ws://${location.host}/ws${q ? `?${q}` : ''}`);
  ws.onopen = () => { api.connected = true; lostAt = null; lastSent = ''; };
  ws.onmessage = (ev) => {
    const m = JSON.parse(ev.data);
    if (m.type === 'hello') {
      api.role = m.role;
      api.graceS = m.grace_s;
      api.robots = Array.isArray(m.robots) ? m.robots : [];
      const several = api.robots.length > 1;
      if (several && typeof m.robot === 'string' && m.robot !== askedRobot) {
        // The server gave this page another robot's seat than the scene it loaded: keep the
        // token, load that robot's page (its own vehicle).
        if (m.token) try { sessionStorage.setItem(`${TOKEN_KEY}:${m.robot}`, m.token); } catch (_) { /* no storage */ }
        location.replace(`/?robot=${m.robot}${watchOnly ? '&watch=1' : ''}`);
        return;
      }
      if (several) api.robot = m.robot;
      if (m.token) try { sessionStorage.setItem(tokenKey(), m.token); } catch (_) { /* no storage */ }
      showRobotPicker();
      if (m.role === 'instructor') showInstructorPanel();
    } else if (m.type === 'state') {
      api.state = m; api.states++;
      // A trainee's dropped video: no new sensor readings either (the feed is frozen).
      if (!(m.faults?.video === 'dropped' && api.role !== 'instructor')) liveSensors(m.sensors);
      placeOthers(m.others);
      if (m.session_ended) ended = true;
    } else if (m.type === 'ruts') {
      // The session's rut log (live/hub.rs): cells numbered from m.first; a reconnection
      // sends the log again from its start, a new epoch means the ruts before are gone.
      if (m.epoch !== rutLog.epoch) { ruts.clear(); rutLog.epoch = m.epoch; rutLog.next = 0; }
      const skip = Math.max(0, rutLog.next - m.first);
      if (skip < m.cells.length) {
        ruts.add(m.cells.slice(skip).map((r) => [...r, api.state?.t ?? 0]));
        rutLog.next = m.first + m.cells.length;
      }
    } else if (m.type === 'error') api.errors.push(m.message);
  };
  ws.onclose = () => {
    api.connected = false;
    if (ended) return;
    lostAt ??= performance.now();
    if ((performance.now() - lostAt) / 1000 > (api.graceS ?? 30) + 5) { ended = true; return; }
    setTimeout(() => { api.reconnects++; connect(); }, 500);
  };
}
$('stop').addEventListener('click', () => send({ type: instructorToken ? 'end' : 'stop' }));

// ---------- the instructor's seat (issue 43; protocol in live/instructor.rs) ----------
const noSignal = document.createElement('div');
noSignal.id = 'nosignal';
noSignal.className = 'hidden';
noSignal.textContent = 'NO SIGNAL';
noSignal.style.cssText = 'position:fixed;inset:0;display:flex;align-items:center;justify-content:center;'
  + 'font:bold 48px monospace;color:#ddd;background:rgba(20,20,20,0.9);pointer-events:none;z-index:5';
document.body.appendChild(noSignal);
// Faults in force, in words (the instructor's HUD).
function faultLine(f) {
  const parts = [];
  (f.track ?? []).forEach((k, i) => { if (k !== 'ok') parts.push(`track ${trackNames[i]} ${k}`); });
  (f.flipper ?? []).forEach((k, i) => { if (k !== 'ok') parts.push(`flipper ${flipperNames[i]} ${k}`); });
  if (f.latency_s > 0) parts.push(`latency ${fmt(f.latency_s, 2)} s`);
  if (f.video === 'dropped') parts.push('video dropped');
  if (f.patch) parts.push(`low-friction patch ${fmt(f.patch.friction, 2)} (${fmt(f.patch.size_m[0], 1)} x ${fmt(f.patch.size_m[1], 1)} m at x ${fmt(f.patch.centre_m[0], 1)}, y ${fmt(f.patch.centre_m[1], 1)} m)`);
  return `faults     ${parts.length ? parts.join(', ') : 'none'}`;
}
const robotOf = (msg) => (api.robots.length > 1 && api.robot ? { ...msg, robot: api.robot } : msg);
api.instructor = instructorToken ? {
  pause: () => send({ type: 'pause' }),
  resume: () => send({ type: 'resume' }),
  reset: () => send(robotOf({ type: 'reset' })),
  end: () => send({ type: 'end' }),
  fault: (fault) => send(robotOf({ type: 'fault', fault })),
} : null;
let panelShown = false;
function showInstructorPanel() {
  if (panelShown || !api.instructor) return;
  panelShown = true;
  const p = document.createElement('div');
  p.id = 'instructor';
  p.style.cssText = 'position:fixed;right:10px;bottom:70px;background:rgba(0,0,0,0.75);color:#fff;'
    + 'font:12px monospace;padding:8px;border-radius:4px;z-index:6;max-width:300px';
  const row = (html) => { const d = document.createElement('div'); d.style.margin = '3px 0'; d.innerHTML = html; p.appendChild(d); return d; };
  row('<b>Instructor</b>');
  const b = row('<button id="i-pause">Pause</button> <button id="i-reset">Reset robot</button> <button id="i-end">End session</button>');
  b.querySelector('#i-pause').addEventListener('click', () => (api.state?.paused ? api.instructor.resume() : api.instructor.pause()));
  b.querySelector('#i-reset').addEventListener('click', () => api.instructor.reset());
  b.querySelector('#i-end').addEventListener('click', () => api.instructor.end());
  const select = (opts) => `<select>${opts.map((o) => `<option>${o}</option>`).join('')}</select>`;
  trackNames.forEach((n) => {
    const r = row(`track ${n} ${select(['ok', 'stopped', 'unpowered'])}`);
    r.querySelector('select').addEventListener('change', (e) => api.instructor.fault({ track: { [n]: e.target.value } }));
  });
  flipperNames.forEach((n) => {
    const r = row(`flipper ${n} ${select(['ok', 'jammed'])}`);
    r.querySelector('select').addEventListener('change', (e) => api.instructor.fault({ flipper: { [n]: e.target.value } }));
  });
  const lat = row('latency <input type="number" min="0" max="10" step="0.1" value="0" style="width:4em"> s <button>set</button>');
  lat.querySelector('button').addEventListener('click', () => api.instructor.fault({ latency_s: Number(lat.querySelector('input').value) }));
  const vid = row(`trainee's video ${select(['ok', 'dropped'])}`);
  vid.querySelector('select').addEventListener('change', (e) => api.instructor.fault({ video: e.target.value }));
  // A low-friction patch (friction, a square of side, its centre this far ahead of the robot).
  const pat = row('patch friction <input id="i-patch-mu" type="number" min="0" max="2" step="0.05" value="0.1" style="width:4em">'
    + ' side <input id="i-patch-side" type="number" min="0.1" step="0.5" value="2" style="width:3.5em"> m'
    + ' ahead <input id="i-patch-ahead" type="number" step="0.5" value="0" style="width:3.5em"> m'
    + ' <button id="i-patch-put">put</button> <button id="i-patch-remove">remove</button>');
  pat.querySelector('#i-patch-put').addEventListener('click', () => {
    const [x, y, , , , yaw] = api.state?.pose ?? [0, 0, 0, 0, 0, 0];
    const num = (id) => Number(pat.querySelector(id).value);
    const side = num('#i-patch-side'), ahead = num('#i-patch-ahead');
    api.instructor.fault({ patch: { centre_m: [x + ahead * Math.cos(yaw), y + ahead * Math.sin(yaw)], size_m: [side, side], friction: num('#i-patch-mu') } });
  });
  pat.querySelector('#i-patch-remove').addEventListener('click', () => api.instructor.fault({ patch: 'ok' }));
  document.body.appendChild(p);
  $('stop').textContent = 'End session (instructor)';
  setInterval(() => { b.querySelector('#i-pause').textContent = api.state?.paused ? 'Resume' : 'Pause'; }, 250);
}

// ---------- a low-friction patch on the ground (an instructor's fault, issue 43) ----------
// Every page shows it (a wet or icy patch is visible in reality): a translucent blue sheet
// draped 5 mm over the ground inside the patch's rectangle (heights by downward rays); the
// instructor's HUD lists it with the faults. `api.patch`: the patch drawn (centre_m, size_m,
// friction), or null; `api.patchDrawn`: its sheet's triangles.
const patchMat = new THREE.MeshBasicMaterial({ color: 0x3a8fe0, transparent: true, opacity: 0.5, side: THREE.DoubleSide, depthWrite: false });
let patchMesh = null, patchKey = '';
api.patch = null;
api.patchDrawn = 0;
function showPatch(p, zNear) {
  const key = p ? JSON.stringify(p) : '';
  if (key === patchKey) return;
  patchKey = key;
  if (patchMesh) { world.remove(patchMesh); patchMesh.geometry.dispose(); patchMesh = null; }
  api.patch = p ?? null;
  api.patchDrawn = 0;
  if (!p) return;
  const [cx, cy] = p.centre_m, [sx, sy] = p.size_m;
  const nx = Math.min(60, Math.max(1, Math.ceil(sx / 0.1))), ny = Math.min(60, Math.max(1, Math.ceil(sy / 0.1)));
  const pos = [], idx = [];
  for (let j = 0; j <= ny; j++) {
    for (let i = 0; i <= nx; i++) {
      const x = cx - sx / 2 + (sx * i) / nx, y = cy - sy / 2 + (sy * j) / ny;
      pos.push(x, y, (groundAt(x, y, zNear + 20) ?? 0) + 0.005);
    }
  }
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const a = j * (nx + 1) + i;
      idx.push(a, a + 1, a + nx + 2, a, a + nx + 2, a + nx + 1);
    }
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  g.setIndex(idx);
  patchMesh = new THREE.Mesh(g, patchMat);
  patchMesh.name = 'friction-patch';
  patchMesh.renderOrder = 1;
  world.add(patchMesh);
  api.patchDrawn = idx.length / 3;
}

function liveFrame() {
  driveTick();
  const s = api.state;
  if (!s) { hud(['waiting for the simulation ...']); return; }
  const [x, y, z, roll, pitch, yaw] = s.pose;
  showPatch(s.faults?.patch ?? null, z);
  // The onboard video and sensors dropped (an instructor's fault): the trainee's view stays
  // frozen at its last picture under "NO SIGNAL"; the instructor's page shows everything.
  api.noSignal = s.faults?.video === 'dropped' && api.role !== 'instructor';
  noSignal.classList.toggle('hidden', !api.noSignal);
  if (!api.noSignal) {
    pose(x, y, z, roll, pitch, yaw, s.flipper, s.belt_position);
    recordPath(x, y);
  }
  // The warnings: the server's fields where it sends them (slip, stall, ahead, tilt_limit_deg,
  // course, driver), else what the page can tell. A test may show a made-up state instead.
  const vs = api.hudOverride ?? {
    t: s.t, pose: s.pose, forward_mps: s.forward_mps, belt_cmd: s.belt_speed,
    slip: Array.isArray(s.slip) ? s.slip : pageSlip(s),
    stall: typeof s.stall === 'boolean' ? s.stall : null,
    flipper: s.flipper,
    tilt_limit_deg: isNum(s.tilt_limit_deg) ? s.tilt_limit_deg : sceneTiltLimit,
    ahead: s.ahead && Array.isArray(s.ahead.d_m) ? s.ahead : profileAhead(x, y, z, yaw),
    outcome: s.outcome, course: s.course ?? null, driver: watchSession ? null : s.driver ?? null,
    standings: s.team?.standings ?? null,
  };
  warn.update(vs);
  if (mapOn) minimap.draw(vs.pose, path, [...others.values()].filter((g) => g.now).map((g) => ({ pose: g.now, colour: hex(g.colour) })), isNum(s.course?.next_gate) ? s.course.next_gate : null);
  const o = s.outcome ? `${s.outcome.name}: ${s.outcome.reason} (t = ${fmt(s.outcome.t)} s)` : 'undecided';
  if (watchSession) { hud(watchHud(s, o, roll, pitch, yaw, x, y, z)); return; }
  hud([
    `${ended ? (api.state?.stopped ? `SESSION STOPPED: ${api.state.stopped} (every robot's run written)` : 'SESSION ENDED (outputs written)') : !api.connected ? 'RECONNECTING ...' : api.role === 'driver' ? 'DRIVING' : api.role === 'instructor' ? 'INSTRUCTOR (sees everything)' : 'WATCHING (another page drives)'}${api.robots.length > 1 ? ` robot ${api.robot}` : ''}`,
    ...(s.team?.outcome ? [`team       ${s.team.rule}: ${s.team.outcome.name}: ${s.team.outcome.reason}`] : []),
    ...(s.paused ? ['PAUSED by the instructor (simulated time stands still)'] : []),
    ...(isNum(s.attempt) && s.attempt > 1 ? [`attempt    ${s.attempt} (each reset keeps the one before)`] : []),
    ...(api.role === 'instructor' && s.faults ? [faultLine(s.faults)] : []),
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

// The HUD of a watch-only session: what the learner commands (each belt's speed, each
// flipper's target: the state's `control.flipper_angle_deg`), no drive settings.
function watchHud(s, o, roll, pitch, yaw, x, y, z) {
  const target = s.control?.flipper_angle_deg ?? [];
  return [
    `${!api.connected ? 'RECONNECTING ...' : 'WATCHING a learning environment (watch-only: nobody drives)'}`,
    `sim time   ${fmt(s.t, 2)} s${s.speed > 0 ? `   x${fmt(s.speed, 2)} paced` : '   unpaced'}`,
    `speed      ${fmt(s.forward_mps, 3)} m/s forward`,
    `roll/pitch ${fmt(deg(roll), 1)} / ${fmt(deg(pitch), 1)} deg   yaw ${fmt(deg(yaw), 1)} deg`,
    `position   ${fmt(x, 3)} ${fmt(y, 3)} ${fmt(z, 3)} m`,
    ...flipperNames.map((n, i) => `flipper    ${n} ${fmt(deg(s.flipper[i]), 1)} deg (target ${fmt(target[i], 0)})`),
    ...trackNames.map((n, i) => `belt       ${n} ${fmt(s.belt_speed[i], 3)} m/s commanded, at ${fmt(s.belt_position[i], 2)} m`),
    `outcome    ${o}`,
    ...sensorHud(),
  ];
}

// Slip per track when the state brings none: 1 - forward speed / belt command (belts
// commanded faster than 0.05 m/s; 0 otherwise), an estimate that ignores turning.
function pageSlip(s) {
  return (s.belt_speed ?? []).map((b) => (Math.abs(b) > 0.05 ? Math.max(0, Math.min(1, 1 - (s.forward_mps ?? 0) / b)) : 0));
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
// A ghost of a compare replay or another robot of the world: a vehicle's body, flippers and
// belts, translucent, one colour; `vj` the vehicle of its own scene.json (null: this page's).
const GHOST_COLOURS = [0xff5050, 0x40a0ff, 0xffd040, 0xc060ff, 0x40e0a0, 0xff9040, 0xffffff, 0x90ff40];
function makeGhost(colour, vj = null) {
  const mat = new THREE.MeshStandardMaterial({ color: colour, transparent: true, opacity: 0.4, depthWrite: false });
  const g = new THREE.Group();
  const own = vj ?? v;
  g.add(vj ? new THREE.Mesh(meshGeometry(vj.body), mat) : new THREE.Mesh(robot.children[0].geometry, mat));
  const pivots = own.flippers.map((f, i) => {
    const pivot = new THREE.Group();
    pivot.position.fromArray(f.pivot_m);
    const inner = new THREE.Group();
    inner.position.set(-f.pivot_m[0], -f.pivot_m[1], -f.pivot_m[2]);
    pivot.add(inner);
    g.add(pivot);
    if (vj) { if (f.mesh) inner.add(new THREE.Mesh(meshGeometry(f.mesh), mat)); } else for (const m of flipperPivots[i].inner.children) if (m.isMesh) inner.add(new THREE.Mesh(m.geometry, mat));
    return { pivot, inner, axis: new THREE.Vector3().fromArray(f.axis) };
  });
  own.tracks.forEach((tr, i) => {
    const parent = tr.parent < 0 ? g : pivots[tr.parent].inner;
    if (!vj) { parent.add(new THREE.Mesh(tracks[i].beltMesh.geometry, mat)); return; }
    // The belt alone (grousers are drawn only on this page's robot).
    const holder = new THREE.Group();
    const tk = buildTrack({ ...tr, grousers: null }, holder);
    tk.beltMesh.material = mat;
    parent.add(holder);
  });
  world.add(g);
  return { group: g, pivots, flipperNames: own.flippers.map((f) => f.name) };
}
const hex = (c) => `#${c.toString(16).padStart(6, '0')}`;
const ghosts = [];
let events = [], lanes = [];
if (!live) {
  const base = runs.runs[0].base;
  const traj = parseCsv(await (await fetch(`${base}/trajectory.csv`)).text());
  const belts = parseCsv(await (await fetch(`${base}/belts.csv`)).text());
  const summaryResp = await fetch(`${base}/summary.json`);
  const summary = summaryResp.ok ? await summaryResp.json() : null;
  const controlsResp = await fetch(`${base}/controls.csv`);
  const controls = controlsResp.ok ? parseCsv(await controlsResp.text()) : null;
  if (scene.ruts_csv) {
    const rutsResp = await fetch(`${base}/ruts.csv`);
    if (rutsResp.ok) ruts.add(parseRuts(await rutsResp.text()));
  }
  const c = (n) => traj.col(n);
  replay = {
    traj, belts, summary, controls,
    pose: ['x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad'].map(c),
    vel: ['vx_mps', 'vy_mps'].map(c),
    flip: flipperNames.map((n) => c(`flipper_${n}_rad`)),
    speed: trackNames.map((n) => c(`belt_speed_${n}_mps`)),
    cmd: trackNames.map((n) => c(`belt_cmd_${n}_mps`)),
    slip: trackNames.map((n) => c(`slip_${n}`)),
    beltPos: trackNames.map((n) => belts.col(`belt_position_${n}_m`)),
    conveyorPos: conveyors.map((_, i) => belts.col(`conveyor_position_${i}_m`)),
    boxPose: looseBoxes.map((_, i) => ['x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad'].map((c) => belts.col(`box_${i}_${c}`))),
    end: traj.rows[traj.rows.length - 1][0],
  };
  // A reset robot of a team run (its attempts' samples joined by the server, issue 43): each
  // attempt's summary, so that the review's events, the course score and the outcome at a
  // replay time are those of the attempt under way then (`parts`: attempt, from_s, summary).
  replay.parts = [];
  for (const p of Array.isArray(runs.runs[0].parts) ? runs.runs[0].parts : []) {
    const pr = typeof p.summary === 'string' ? await fetch(p.summary) : null;
    replay.parts.push({ attempt: p.attempt, from_s: p.from_s, summary: pr && pr.ok ? await pr.json() : null });
  }
  replay.parts.forEach((p, i) => { p.end_s = replay.parts[i + 1]?.from_s ?? Infinity; });
  if (replay.parts.length && replay.parts.every((p) => p.summary && isNum(p.from_s))) {
    events = replay.parts.flatMap((p) => computeEvents(traj, p.summary, trackNames));
  } else {
    replay.parts = [];
    events = computeEvents(traj, summary, trackNames);
  }
  api.parts = replay.parts.map((p) => ({ attempt: p.attempt, from_s: p.from_s }));
  // The other methods of a compare folder: ghosts of their own colours, driven by the time bar.
  for (const run of runs.runs.slice(1)) {
    try {
      const gt = parseCsv(await (await fetch(`${run.base}/trajectory.csv`)).text());
      const gsr = await fetch(`${run.base}/summary.json`);
      const gs = gsr.ok ? await gsr.json() : null;
      const colour = GHOST_COLOURS[ghosts.length % GHOST_COLOURS.length];
      // Its own vehicle (a robot of a team folder may be another vehicle).
      const gsc = await fetch(`${run.base}/scene.json`);
      const gv = gsc.ok ? (await gsc.json()).vehicle ?? null : null;
      const made = makeGhost(colour, gv);
      const gh = { name: runLabel(run), folder: run.name, colour, vehicle: gv?.name ?? v.name, traj: gt, summary: gs, ...made, pose: ['x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad'].map((n) => gt.col(n)), flip: made.flipperNames.map((n) => gt.col(`flipper_${n}_rad`)), end: gt.rows[gt.rows.length - 1][0] };
      ghosts.push(gh);
      replay.end = Math.max(replay.end, gh.end);
      if (gs && isNum(gs.outcome_time_s) && gs.outcome) events.push({ t_s: gs.outcome_time_s, kind: 'outcome', detail: `${runLabel(run)}: ${gs.outcome}: ${gs.outcome_reason ?? ''}` });
    } catch (err) {
      api.errors.push(`run ${run.name}: ${err}`);
    }
  }
  events.sort((a, b) => a.t_s - b.t_s);
  if (runs.compare) {
    const lg = $('legend');
    lg.classList.remove('hidden');
    const out = (sm) => (sm ? ` (${sm.outcome})` : '');
    const entry = (colour, text) => {
      const sw = document.createElement('span');
      sw.className = 'sw';
      sw.style.background = colour;
      lg.append(sw, document.createTextNode(text)); // names are folder names: text, never markup
    };
    const title = document.createElement('b');
    title.textContent = runs.team ? 'robots' : runs.sessions ? 'trainees' : 'compare';
    lg.append(title);
    entry('#4f5d3a', `${runLabel(runs.runs[0])}${out(summary)} (solid)`);
    for (const g of ghosts) entry(hex(g.colour), `${g.name}${out(g.summary)}`);
  }
  api.runs = runs.runs.map((r) => r.name);
  api.ghosts = () => ghosts.map((g) => ({ name: g.name, folder: g.folder, colour: hex(g.colour), vehicle: g.vehicle, position: g.group.position.toArray(), visible: g.group.visible }));
  api.events = events;
  lanes = inputSeries(controls, traj, trackNames);
  api.inputs = { lanes: lanes.map((l) => ({ title: l.title, series: l.series.map((x) => x.name) })), source: controls ? 'controls.csv' : 'trajectory.csv', drawn: 0 };
  await loadReplaySensors();
  api.replayEnd = replay.end;
  $('bar').classList.remove('hidden');
  // The run as an MP4 (`/video.mp4`, rendered by the server on the first request).
  if (session.video) $('video-link').classList.remove('hidden');
  showDebriefLink(base);
  api.video = Boolean(session.video);
  $('play').addEventListener('click', togglePlay);
  $('scrub').addEventListener('input', (e) => { playTime = Number(e.target.value) * replay.end; });
  const mk = $('markers');
  events.forEach((ev, i) => {
    const b = document.createElement('button');
    b.className = 'marker';
    b.dataset.index = String(i);
    b.dataset.kind = ev.kind;
    b.style.left = `${(100 * ev.t_s) / (replay.end || 1)}%`;
    b.style.background = eventColour(ev.kind);
    b.title = `${ev.t_s.toFixed(2)} s: ${ev.kind}${ev.detail ? ' — ' + ev.detail : ''}`;
    b.addEventListener('click', () => jumpTo(ev));
    mk.appendChild(b);
  });
}
// A run's name on the page: its trainee (a folder of sessions, view/server.rs `label`), else
// its folder's name.
function runLabel(run) { return typeof run.label === 'string' && run.label ? run.label : run.name; }
// The printable debrief of the run (debrief.html in its folder, output/debrief.rs), linked
// from the time bar when the folder has one.
async function showDebriefLink(base) {
  const r = await fetch(`${base}/debrief.html`, { method: 'HEAD' }).catch(() => null);
  api.debrief = Boolean(r?.ok);
  if (!r?.ok) return;
  const a = $('debrief-link');
  a.href = `${base}/debrief.html`;
  a.classList.remove('hidden');
}
function jumpTo(ev) {
  if (!ev) return;
  playTime = Math.min(ev.t_s, replay.end);
  api.replayTime = playTime;
  $('event-label').textContent = `${ev.kind}${ev.detail ? ': ' + ev.detail : ''} (${ev.t_s.toFixed(2)} s)`;
  api.lastJump = ev;
}
// The inputs strip: drawn once into a canvas of its own, copied with a cursor each frame.
const inputsBase = document.createElement('canvas');
function drawInputsStrip(t) {
  const c = $('inputs');
  const w = c.clientWidth;
  if (!w) return;
  if (c.width !== w) c.width = w;
  if (inputsBase.width !== w || inputsBase.height !== c.height) {
    inputsBase.width = w; inputsBase.height = c.height;
    api.inputs.drawn = drawInputs(inputsBase, lanes, replay.end, null);
  }
  const g = c.getContext('2d');
  g.clearRect(0, 0, c.width, c.height);
  g.drawImage(inputsBase, 0, 0);
  g.fillStyle = '#fff';
  g.fillRect(Math.round((t / (replay.end || 1)) * w), 0, 1, c.height);
}
// The replay's path so far: the trajectory's samples up to the replay time (x y).
let pathUpTo = -1;
function recordReplayPath(t) {
  const rows = replay.traj.rows, [ix, iy] = replay.pose;
  if (t < pathUpTo) { path.length = 0; pathUpTo = -1; }
  for (const row of rows) {
    if (row[0] <= pathUpTo) continue;
    if (row[0] > t) break;
    const n = path.length;
    if (n < 2 || Math.hypot(path[n - 2] - row[ix], path[n - 1] - row[iy]) >= 0.05) path.push(row[ix], row[iy]);
    pathUpTo = row[0];
  }
}
function lerpRow(rows, t) {
  let lo = 0, hi = rows.length - 1;
  if (t <= rows[0][0]) return rows[0];
  if (t >= rows[hi][0]) return rows[hi];
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (rows[mid][0] <= t) lo = mid; else hi = mid; }
  const a = rows[lo], b = rows[hi], w = (t - a[0]) / (b[0] - a[0] || 1);
  return a.map((x, i) => x + (b[i] - x) * w);
}
// The attempt under way at replay time `t` s (a reset robot of a team run; else the run as
// one attempt): its summary and the time it ended.
function partAt(t) {
  let p = null;
  for (const q of replay.parts ?? []) if (!p || q.from_s <= t + 1e-9) p = q;
  return p ?? { summary: replay.summary, end_s: replay.end };
}
// The course panel of a replay: the score at the replay time (review.js courseAt), not the
// final one; window.tracksim.courseAt(t) gives it for any time.
function replayCourse(t) {
  const p = partAt(t);
  const c = courseAt(p.summary?.course ?? null, t, Math.min(p.end_s, replay.end));
  api.replayCourse = c;
  return c;
}
api.courseAt = (t) => (replay ? courseAt(partAt(t).summary?.course ?? null, t, Math.min(partAt(t).end_s, replay.end)) : null);
function lerpAngle(a, b, w) { let d = b - a; while (d > Math.PI) d -= 2 * Math.PI; while (d < -Math.PI) d += 2 * Math.PI; return a + d * w; }
function replayFrame() {
  const now = performance.now();
  if (lastWall !== null && playing) playTime += ((now - lastWall) / 1000) * Number($('rate').value);
  lastWall = now;
  if (playTime > replay.end) playTime = 0; // loop
  api.replayTime = playTime;
  ruts.showUntil(playTime);
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
  // The low-friction patch as it was at the replay time (scene.json `patches`, the run's own).
  showPatch(patchAt(scene.patches, playTime), z);
  conveyors.forEach((c, i) => placeGrousers(c, br[replay.conveyorPos[i]] ?? 0));
  looseBoxes.forEach((m, i) => {
    const [bx, by, bz, br_, bp, byaw] = replay.boxPose[i].map((k) => br[k]);
    m.position.set(bx, by, bz);
    euler.set(br_, bp, byaw, 'ZYX');
    m.quaternion.setFromEuler(euler);
  });
  replaySensorFrame(playTime);
  recordReplayPath(playTime);
  for (const gh of ghosts) {
    const gr = lerpRow(gh.traj.rows, playTime);
    const [gx, gy, gz, groll, gpitch, gyaw] = gh.pose.map((i) => gr[i]);
    gh.group.position.set(gx, gy, gz);
    euler.set(groll, gpitch, gyaw, 'ZYX');
    gh.group.quaternion.setFromEuler(euler);
    gh.flip.forEach((i, k) => gh.pivots[k]?.pivot.quaternion.setFromAxisAngle(gh.pivots[k].axis, gr[i] ?? 0));
    gh.now = [gx, gy, gz, groll, gpitch, gyaw];
  }
  const sm = partAt(playTime).summary;
  const vs = api.hudOverride ?? {
    t: playTime, pose: [x, y, z, roll, pitch, yaw],
    forward_mps: r[replay.vel[0]] * Math.cos(yaw) + r[replay.vel[1]] * Math.sin(yaw),
    belt_cmd: replay.cmd.map((i) => (i >= 0 ? r[i] : 0)),
    slip: replay.slip.every((i) => i >= 0) ? replay.slip.map((i) => r[i]) : null,
    stall: events.some((ev) => ev.kind === 'stall' && playTime >= ev.t_s && playTime <= (ev.t_end_s ?? Infinity)),
    flipper: replay.flip.map((i) => r[i]),
    tilt_limit_deg: [sceneTiltLimit, sm?.max_tilt_deg].find(isNum) ?? null,
    ahead: profileAhead(x, y, z, yaw),
    outcome: sm && isNum(sm.outcome_time_s) && playTime >= sm.outcome_time_s ? { name: sm.outcome, reason: sm.outcome_reason, t: sm.outcome_time_s } : null,
    course: replayCourse(playTime), driver: null,
  };
  warn.update(vs);
  if (mapOn) minimap.draw(vs.pose, path, ghosts.filter((g) => g.now).map((g) => ({ pose: g.now, colour: hex(g.colour) })), isNum(vs.course?.next_gate) ? vs.course.next_gate : null);
  drawInputsStrip(playTime);
  $('scrub').value = String(playTime / (replay.end || 1));
  $('clock').textContent = `${fmt(playTime, 2)} / ${fmt(replay.end, 2)} s`;
  const s = sm;
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
  layout();
  placeCamera();
  renderer.render(world, camera);
  renderPip();
  api.frames++;
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
