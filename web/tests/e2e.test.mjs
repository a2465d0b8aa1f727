// End-to-end test of the operator's seat in a real headless Chromium (issue 12):
// `tracksim drive` page loads, its 3-D canvas is not blank, holding the forward key moves the
// robot in the simulation's own state, the stop button writes the session, `tracksim run
// --commands` reproduces its trajectory.csv byte for byte, and `tracksim view` replays it.
// Screenshots are kept in web/tests/artifacts/. Run by scripts/test-browser.sh.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launchChromium } from './chromium.mjs';

const here = path.dirname(new URL(import.meta.url).pathname);
const root = path.resolve(here, '../..');
const bin = process.env.TRACKSIM_BIN || path.join(root, 'target/release/tracksim');
const artifacts = path.join(here, 'artifacts');
fs.mkdirSync(artifacts, { recursive: true });
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'tracksim-e2e-'));

/** Starts a tracksim command and resolves with the URL it prints. */
function start(args) {
  const child = spawn(bin, args, { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let out = '';
  const url = new Promise((resolve, reject) => {
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    });
    child.on('exit', (code) => reject(new Error(`tracksim ${args[0]} exited ${code}: ${out}`)));
  });
  const exited = new Promise((resolve) => child.on('exit', (code) => resolve({ code, out })));
  return { child, url, exited };
}

async function browser() {
  return launchChromium(tmp);
}

/** Pixel standard deviation (0-255, grey) of a PNG screenshot, decoded by the page. */
async function pixelStd(page, png) {
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let s = 0, s2 = 0, n = 0;
    for (let i = 0; i < d.length; i += 16) { const y = (d[i] + d[i + 1] + d[i + 2]) / 3; s += y; s2 += y * y; n++; }
    return Math.sqrt(s2 / n - (s / n) ** 2);
  }, png.toString('base64'));
}

/** Standard deviation of the WebGL canvas alone (the HUD excluded). */
async function canvasStd(page) {
  return page.evaluate(() => {
    const src = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let s = 0, s2 = 0, n = 0;
    for (let i = 0; i < d.length; i += 16) { const y = (d[i] + d[i + 1] + d[i + 2]) / 3; s += y; s2 += y * y; n++; }
    return Math.sqrt(s2 / n - (s / n) ** 2);
  });
}

/** Opens a replay page and waits until it plays; a page error fails at once with its text. */
async function openReplay(ctx, url) {
  const page = await ctx.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  try {
    await page.waitForFunction(() => window.tracksim?.replayEnd > 0 && window.tracksim.frames > 10, null, { timeout: 60000 });
  } catch (e) {
    throw new Error(`${e.message}; page errors: ${errors.join(' | ') || 'none'}`);
  }
  assert.deepEqual(errors, []);
  return page;
}

const out = path.join(tmp, 'drive');

test('drive: the page loads, draws, and the forward key moves the robot', async () => {
  const drive = start(['drive', 'scenarios/packbot_stairs.toml', '--port', '0', '--out', out]);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const page = await ctx.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto(url);
    await page.waitForFunction(() => window.tracksim?.state && window.tracksim.frames > 10, null, { timeout: 60000 });
    assert.deepEqual(errors, []);
    assert.equal(await page.evaluate(() => window.tracksim.role), 'driver');
    const std0 = await canvasStd(page);
    assert.ok(std0 > 5, `3-D canvas looks blank: pixel std ${std0}`);
    const x0 = await page.evaluate(() => window.tracksim.state.pose[0]);
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction((x) => window.tracksim.state.pose[0] > x + 0.1, x0, { timeout: 60000 });
    const state = await page.evaluate(() => window.tracksim.state);
    assert.ok(state.control.forward_mps > 0, JSON.stringify(state.control));
    const shot = await page.screenshot({ path: path.join(artifacts, 'drive.png') });
    await page.keyboard.up('ArrowUp');
    const std = await pixelStd(page, shot);
    assert.ok(std > 5, `screenshot looks blank: pixel std ${std}`);
    await page.waitForFunction(() => window.tracksim.state.control.forward_mps === 0, null, { timeout: 10000 });
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
  // The session was written as a run, with the operator's controls.
  for (const f of ['summary.json', 'trajectory.csv', 'belts.csv', 'scene.json', 'commands.toml', 'controls.csv', 'plot.png']) {
    assert.ok(fs.existsSync(path.join(out, f)), `${f} missing`);
  }
  const rows = fs.readFileSync(path.join(out, 'trajectory.csv'), 'utf8').trim().split('\n');
  const x = (row) => Number(row.split(',')[1]);
  assert.ok(x(rows[rows.length - 1]) > x(rows[1]) + 0.1, 'the recorded trajectory moved forward');
  const controls = fs.readFileSync(path.join(out, 'controls.csv'), 'utf8');
  assert.match(controls, /\n[0-9.]+,0\.300000,0\.000000/);
});

test('the session replays as `tracksim run --commands` byte for byte', () => {
  const toml = fs.readFileSync(path.join(out, 'commands.toml'), 'utf8');
  const duration = toml.match(/--duration ([0-9.e-]+)/)[1];
  const again = path.join(tmp, 'again');
  execFileSync(bin, ['run', 'scenarios/packbot_stairs.toml', '--commands', path.join(out, 'commands.toml'),
    '--duration', duration, '--out', again, '--quiet', '--no-plot'], { cwd: root });
  assert.equal(fs.readFileSync(path.join(again, 'trajectory.csv'), 'utf8'), fs.readFileSync(path.join(out, 'trajectory.csv'), 'utf8'));
});

test('view: the replay page plays the recorded run', async () => {
  const view = start(['view', out, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    const t0 = await page.evaluate(() => window.tracksim.replayTime);
    await page.waitForFunction((t) => window.tracksim.replayTime > t + 0.5, t0, { timeout: 30000 });
    const shot = await page.screenshot({ path: path.join(artifacts, 'view.png') });
    assert.ok((await pixelStd(page, shot)) > 5);
    // Pause holds the time; the scrubber moves it.
    await page.click('#play');
    const held = await page.evaluate(() => window.tracksim.replayTime);
    await page.waitForTimeout(300);
    assert.equal(await page.evaluate(() => window.tracksim.replayTime), held);
    await page.$eval('#scrub', (e) => { e.value = '0.9'; e.dispatchEvent(new Event('input')); });
    await page.waitForFunction(() => Math.abs(window.tracksim.replayTime - 0.9 * window.tracksim.replayEnd) < 1e-6);
    // A single run is listed alone (issue 28: a compare folder lists every method).
    const runs = await page.evaluate(async () => (await fetch('/runs.json')).json());
    assert.deepEqual(runs, { compare: false, runs: [{ index: 0, name: 'drive', base: '/run' }] });
    assert.equal(await page.evaluate(async () => (await fetch('/run/0/trajectory.csv')).status), 404);
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

/** Pauses a replay page (if playing) and scrubs it to `t` s; resolves once it is there. */
async function scrubTo(page, t) {
  if (await page.evaluate(() => document.getElementById('play').textContent === 'pause')) await page.click('#play');
  const end = await page.evaluate(() => window.tracksim.replayEnd);
  // The bar's steps are 0.001 of the run: the time is the step's nearest to t (1.2 ms here).
  const f = await page.$eval('#scrub', (e, x) => { e.value = String(x); e.dispatchEvent(new Event('input')); return Number(e.value); }, t / end);
  await page.waitForFunction((x) => Math.abs(window.tracksim.replayTime - x * window.tracksim.replayEnd) < 1e-6, f, { timeout: 10000 });
  // Two frames more: the frame that took the time has drawn the scene at it.
  const frames = await page.evaluate(() => window.tracksim.frames);
  await page.waitForFunction((n) => window.tracksim.frames > n + 1, frames, { timeout: 10000 });
}

test('view: the replay draws a low-friction patch only while the run had it (issue 43)', async () => {
  // A `run --commands` folder: the patch put at 0.4 s, removed at 0.8 s.
  const cmds = path.join(tmp, 'patch-commands.toml');
  fs.writeFileSync(cmds, [
    '[[commands]]', 't_s = 0.0', 'belt_speed_mps = { left = 0.3, right = 0.3 }', '',
    '[[commands]]', 't_s = 0.4', 'fault.patch = { centre_m = [0.5, 0.0], size_m = [1.0, 1.5], friction = 0.1 }', '',
    '[[commands]]', 't_s = 0.8', 'fault.patch = "ok"', '',
  ].join('\n'));
  const dir = path.join(tmp, 'patch-run');
  execFileSync(bin, ['run', 'scenarios/packbot_flat.toml', '--commands', cmds, '--duration', '1.2', '--out', dir, '--no-plot'], { cwd: root, stdio: 'ignore' });
  const scene = JSON.parse(fs.readFileSync(path.join(dir, 'scene.json'), 'utf8'));
  assert.deepEqual(scene.patches, [
    { t_s: 0.4, patch: { centre_m: [0.5, 0], size_m: [1, 1.5], friction: 0.1 } },
    { t_s: 0.8, patch: null },
  ]);
  const view = start(['view', dir, '--port', '0']);
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, await view.url);
    const drawn = () => page.evaluate(() => ({ patch: window.tracksim.patch, tris: window.tracksim.patchDrawn }));
    await scrubTo(page, 0.2);
    assert.deepEqual(await drawn(), { patch: null, tris: 0 }, 'a patch drawn before it was put');
    await scrubTo(page, 0.6);
    const during = await drawn();
    assert.equal(during.patch?.friction, 0.1);
    assert.deepEqual(during.patch?.size_m, [1, 1.5]);
    // 10 x 15 cells of at most 0.1 m, two triangles each.
    assert.equal(during.tris, 300);
    await page.screenshot({ path: path.join(artifacts, 'view-patch.png') });
    await scrubTo(page, 1.0);
    assert.deepEqual(await drawn(), { patch: null, tris: 0 }, 'the patch still drawn after it was removed');
    // Scrubbing back shows it again.
    await scrubTo(page, 0.5);
    assert.equal((await drawn()).tris, 300);
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

test('view: conveyors, loose boxes and a spatial loop are drawn and move (issue 17)', async () => {
  const run = path.join(tmp, 'conveyor');
  execFileSync(bin, ['run', 'scenarios/conveyor_box_step.toml', '--out', run, '--quiet', '--no-plot'], { cwd: root });
  const scene = JSON.parse(fs.readFileSync(path.join(run, 'scene.json'), 'utf8'));
  assert.equal(scene.conveyors.length, 1);
  assert.equal(scene.loose_boxes.length, 1);
  // belts.csv carries the conveyor's belt and the box's pose: the box is carried forwards.
  const belts = fs.readFileSync(path.join(run, 'belts.csv'), 'utf8').trim().split('\n');
  const head = belts[0].split(',');
  const bx = head.indexOf('box_0_x_m');
  assert.ok(bx > 0 && head.includes('conveyor_position_0_m'), belts[0]);
  const last = belts[belts.length - 1].split(',').map(Number);
  const first = belts[1].split(',').map(Number);
  assert.ok(last[bx] > first[bx] + 0.1, `box x ${first[bx]} -> ${last[bx]}`);
  const view = start(['view', run, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    assert.equal(await page.evaluate(() => window.tracksim.conveyors), 1);
    assert.equal(await page.evaluate(() => window.tracksim.looseBoxes), 1);
    const shot = await page.screenshot({ path: path.join(artifacts, 'conveyor.png') });
    assert.ok((await pixelStd(page, shot)) > 5);
  } finally {
    await ctx.close();
    view.child.kill();
  }
  // The spatial loop's scene carries a lateral axis per sample.
  const loop = path.join(tmp, 'loop3d');
  execFileSync(bin, ['run', 'scenarios/loop3d_objects.toml', '--out', loop, '--quiet', '--no-plot', '--duration', '1'], { cwd: root });
  const s3 = JSON.parse(fs.readFileSync(path.join(loop, 'scene.json'), 'utf8'));
  assert.ok(s3.conveyors[0].track.laterals.length === 3 * s3.conveyors[0].track.s_m.length);
});

// ---------- issue 25: sensors on the page ----------

/** Rotation of (roll, pitch, yaw) (Rz Ry Rx, REP 103) applied to vector `p`. */
function rpyRotate([roll, pitch, yaw], p) {
  const [cr, sr, cp, sp, cy, sy] = [Math.cos(roll), Math.sin(roll), Math.cos(pitch), Math.sin(pitch), Math.cos(yaw), Math.sin(yaw)];
  const R = [
    [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
    [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
    [-sp, cp * sr, cp * cr],
  ];
  return R.map((row) => row[0] * p[0] + row[1] * p[1] + row[2] * p[2]);
}
/** Quaternion [x, y, z, w] applied to vector `v`. */
function quatRotate([x, y, z, w], v) {
  const t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])];
  return [v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]), v[2] + w * t[2] + (x * t[1] - y * t[0])];
}
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const add = (a, b) => a.map((x, i) => x + b[i]);

test('drive packbot_sensors: lidar hits, the depth panel and the onboard camera view', async () => {
  const sensorsOut = path.join(tmp, 'sensors-drive');
  const drive = start(['drive', 'scenarios/packbot_sensors.toml', '--port', '0', '--out', sensorsOut, '--no-plot']);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const page = await ctx.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto(url);
    await page.waitForFunction(() => window.tracksim?.state && window.tracksim.lidar().scan?.count > 0 && window.tracksim.depth.front_camera, null, { timeout: 60000 });
    assert.deepEqual(errors, []);
    const scene = await page.evaluate(async () => (await fetch('/scene.json')).json());
    const scan = scene.sensors.find((s) => s.name === 'scan');
    const cam = scene.sensors.find((s) => s.name === 'front_camera');
    assert.equal(scan.kind, 'lidar');
    assert.equal(scan.lidar.azimuth_rays, 720);
    assert.equal(cam.depth_camera.width_px, 64);
    // Let the robot settle on the ground, then read the cloud with the pose it was drawn at.
    await page.waitForFunction(() => window.tracksim.state.t > 1.5, null, { timeout: 60000 });
    const { pts, lidar, pose } = await page.evaluate(() => ({ pts: window.tracksim.lidarPoints('scan'), lidar: window.tracksim.lidar().scan, pose: window.tracksim.state.pose }));
    assert.ok(lidar.count > 10 && pts.length === 3 * lidar.count, JSON.stringify(lidar));
    const origin = add(pose.slice(0, 3), rpyRotate(pose.slice(3), scan.xyz_m));
    for (let i = 0; i < pts.length; i += 3) {
      const p = pts.slice(i, i + 3);
      assert.ok(dist(p, origin) <= scan.lidar.max_range_m + 0.01, `point ${p} is ${dist(p, origin)} m from the lidar`);
      // Nothing but the staircase (from x = 0.9 m, 1.2 m wide) stands in the scan's plane.
      assert.ok(p[0] > 0.85 && Math.abs(p[1]) < 0.65 && Math.abs(p[2] - origin[2]) < 0.05, `point ${p} is not on the stairs`);
    }
    // The depth panel shows an image (not flat), and b hides and shows it.
    assert.equal(await page.evaluate(() => window.tracksim.depthShown), true);
    const depthStd = await page.evaluate(() => {
      const c = document.getElementById('depth-canvas');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let s = 0, s2 = 0, n = 0;
      for (let i = 0; i < d.length; i += 4) { s += d[i]; s2 += d[i] * d[i]; n++; }
      return { std: Math.sqrt(s2 / n - (s / n) ** 2), w: c.width, h: c.height, visible: c.offsetWidth > 0 };
    });
    assert.ok(depthStd.std > 10 && depthStd.w === 64 && depthStd.h === 48 && depthStd.visible, JSON.stringify(depthStd));
    await page.screenshot({ path: path.join(artifacts, 'sensors-drive.png') });
    await page.keyboard.press('b');
    assert.equal(await page.evaluate(() => document.getElementById('depth').offsetWidth), 0);
    await page.keyboard.press('b');
    assert.ok((await page.evaluate(() => document.getElementById('depth').offsetWidth)) > 0);
    // v: the camera moves to the front camera's mount and looks along its x axis.
    const far = await page.evaluate(() => window.tracksim.camera);
    assert.deepEqual(await page.evaluate(() => window.tracksim.views), ['follow', 'orbit', 'top-down', 'camera front_camera']);
    for (let i = 0; i < 3; i++) await page.keyboard.press('v');
    await page.waitForFunction(() => window.tracksim.camera.view === 'camera front_camera', null, { timeout: 10000 });
    await page.waitForTimeout(300);
    const onb = await page.evaluate(() => window.tracksim.camera);
    const mount = add(onb.pose.slice(0, 3), rpyRotate(onb.pose.slice(3), cam.xyz_m));
    assert.ok(dist(onb.position, mount) < 1e-4, `camera at ${onb.position}, mount at ${mount}`);
    assert.ok(dist(far.position, mount) > 0.5, 'the follow camera was elsewhere');
    const look = rpyRotate(onb.pose.slice(3), quatRotate(cam.quat_xyzw, [1, 0, 0]));
    assert.ok(dist(onb.direction, look) < 1e-4, `looks along ${onb.direction}, the sensor's x is ${look}`);
    // The simulation's own pose of the camera (the depth reading's) agrees: the robot is at rest.
    const reading = await page.evaluate(() => window.tracksim.depthPose.front_camera);
    assert.ok(dist(reading.position, onb.position) < 0.01, `reading at ${reading.position}`);
    assert.match(await page.evaluate(() => document.getElementById('hud').textContent), /view +camera front_camera/);
    const shot = await page.screenshot({ path: path.join(artifacts, 'sensors-onboard.png') });
    assert.ok((await pixelStd(page, shot)) > 5);
    await page.keyboard.press('v');
    assert.equal(await page.evaluate(() => window.tracksim.view), 'follow');
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
  assert.ok(fs.existsSync(path.join(sensorsOut, 'sensors/scan.npz')));
});

/** Finite values of reading `k` of array `key` in an uncompressed .npz (a test-side reader). */
function npzReading(file, key, k) {
  const b = fs.readFileSync(file);
  const at = b.indexOf(Buffer.from(`${key}.npy`));
  const start = b.indexOf(Buffer.from('\x93NUMPY', 'latin1'), at);
  const hl = b[start + 6] === 1 ? b.readUInt16LE(start + 8) : b.readUInt32LE(start + 8);
  const head = b.toString('latin1', start + (b[start + 6] === 1 ? 10 : 12), start + (b[start + 6] === 1 ? 10 : 12) + hl);
  assert.match(head, /'<f4'/);
  const shape = head.match(/\(([^)]*)\)/)[1].split(',').filter((x) => x.trim()).map(Number);
  const per = shape.slice(1).reduce((a, x) => a * x, 1);
  const data = start + (b[start + 6] === 1 ? 10 : 12) + hl;
  const vals = [];
  for (let i = 0; i < per; i++) vals.push(b.readFloatLE(data + 4 * (k * per + i)));
  return { shape, vals };
}

test('view of a packbot_sensors run: the page reads the npz streams and draws them', async () => {
  const run = path.join(tmp, 'sensors-run');
  execFileSync(bin, ['run', 'scenarios/packbot_sensors.toml', '--duration', '2', '--out', run, '--quiet', '--no-plot'], { cwd: root });
  const scene = JSON.parse(fs.readFileSync(path.join(run, 'scene.json'), 'utf8'));
  assert.deepEqual(scene.sensors.map((s) => s.kind), ['imu', 'encoders', 'lidar', 'elevation_map', 'depth_camera', 'imu']);
  const view = start(['view', run, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    assert.deepEqual(await page.evaluate(() => window.tracksim.sensorFiles), { scan: 'loaded', front_camera: 'loaded' });
    // Only listed .npz streams are served.
    assert.equal(await page.evaluate(async () => (await fetch('/run/sensors/imu.csv')).status), 404);
    await page.click('#play'); // pause, then scrub to 61.5 % (1.23 s of a 2 s run)
    await page.$eval('#scrub', (e) => { e.value = '0.615'; e.dispatchEvent(new Event('input')); });
    await page.waitForFunction(() => Math.abs(window.tracksim.replayTime - 0.615 * window.tracksim.replayEnd) < 1e-6, null, { timeout: 10000 });
    await page.waitForTimeout(300);
    const t = await page.evaluate(() => window.tracksim.replayTime);
    const lidar = await page.evaluate(() => window.tracksim.lidar().scan);
    // The reading at or before t: scan k at k / 10 s (10 Hz), with as many points as returns.
    const k = Math.floor(t * 10 + 1e-6);
    assert.ok(k > 5 && Math.abs(lidar.t - k / 10) < 1e-6, `t ${t}: ${JSON.stringify(lidar)}`);
    const ranges = npzReading(path.join(run, 'sensors/scan.npz'), 'range_m', k);
    assert.deepEqual(ranges.shape, [21, 1, 720]);
    const returns = ranges.vals.filter((r) => Number.isFinite(r)).length;
    assert.ok(returns > 10);
    assert.equal(lidar.count, returns);
    const pts = await page.evaluate(() => window.tracksim.lidarPoints('scan'));
    assert.ok(pts.every((x, i) => i % 3 !== 0 || x > 0.85), 'every hit is on the stairs');
    const depth = await page.evaluate(() => window.tracksim.depth.front_camera);
    const kd = Math.floor(t * 5 + 1e-6);
    assert.ok(depth && Math.abs(depth.t - kd / 5) < 1e-6 && depth.width === 64 && depth.height === 48, JSON.stringify(depth));
    // The panel's image is that reading: as many returns, the same nearest and farthest depths.
    const dv = npzReading(path.join(run, 'sensors/front_camera.npz'), 'depth_m', kd).vals.filter((d) => Number.isFinite(d) && d > 0);
    assert.equal(depth.returns, dv.length);
    assert.ok(Math.abs(depth.near_m - Math.min(...dv)) < 1e-6 && Math.abs(depth.far_m - Math.max(...dv)) < 1e-6, JSON.stringify(depth));
    await page.screenshot({ path: path.join(artifacts, 'sensors-view.png') });
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

// ---------- issue 28: the operator trainer ----------

/** A gamepad stub (standard mapping, 17 buttons, 4 axes) the test sets through window.__pad. */
function gamepadStub() {
  const pad = {
    id: 'tracksim test pad', index: 0, connected: true, mapping: 'standard', timestamp: 0,
    axes: [0, 0, 0, 0], buttons: Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 })),
  };
  window.__pad = pad;
  Object.defineProperty(Navigator.prototype, 'getGamepads', { configurable: true, value: () => [pad, null, null, null] });
}
const setButton = (page, i, on) => page.evaluate(([i, on]) => { Object.assign(window.__pad.buttons[i], { pressed: on, touched: on, value: on ? 1 : 0 }); }, [i, on]);
const setAxes = (page, axes) => page.evaluate((a) => { window.__pad.axes = a; }, axes);
/** Waits until the page has drawn `n` more frames (the page reads the pad once a frame). */
async function frames(page, n = 4) {
  const f = await page.evaluate(() => window.tracksim.frames);
  await page.waitForFunction((f) => window.tracksim.frames >= f, f + n, { timeout: 10000 });
}
/** Waits `dt` s of simulated time (from `from` s, else from now); returns the state then. */
async function simWait(page, dt, from = null) {
  const t0 = from ?? (await page.evaluate(() => window.tracksim.state.t));
  await page.waitForFunction((t) => window.tracksim.state.t >= t, t0 + dt, { timeout: 60000 });
  return page.evaluate(() => window.tracksim.state);
}
/** Opens a drive page (after `init`, if any) and waits for the state. */
async function openDrive(ctx, url, init) {
  const page = await ctx.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  if (init) await page.addInitScript(init);
  await page.goto(url);
  await page.waitForFunction(() => window.tracksim?.state && window.tracksim.frames > 10, null, { timeout: 60000 });
  assert.deepEqual(errors, []);
  return { page, errors };
}
/**
 * Reads a 2-D canvas (by id) or the WebGL canvas (id null) in the page, in a rectangle of
 * canvas pixels: the grey level's standard deviation, the number of pixels within 40 (each
 * channel) of each colour of `hexes`, the RGB at `at` ([x, y], if given), and the mean
 * difference (|dR| + |dG|) from the snapshot named `compare` (kept as `keep`, if given).
 */
async function pixels(page, id, { rect = null, hexes = [], at = null, keep = null, compare = null } = {}) {
  return page.evaluate(({ id, rect, hexes, at, keep, compare }) => {
    const src = id ? document.getElementById(id) : document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0);
    const r = rect ?? { x: 0, y: 0, w: src.width, h: src.height };
    const d = g.getImageData(r.x, r.y, r.w, r.h).data;
    const want = hexes.map((h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16)));
    const counts = want.map(() => 0);
    let s = 0, s2 = 0, n = 0;
    for (let i = 0; i < d.length; i += 4) {
      const y = (d[i] + d[i + 1] + d[i + 2]) / 3; s += y; s2 += y * y; n++;
      want.forEach((w, k) => { if (Math.abs(d[i] - w[0]) < 40 && Math.abs(d[i + 1] - w[1]) < 40 && Math.abs(d[i + 2] - w[2]) < 40) counts[k]++; });
    }
    window.__snaps = window.__snaps ?? {};
    if (keep) window.__snaps[keep] = d;
    let diff = null;
    if (compare) {
      const o = window.__snaps[compare];
      diff = 0;
      for (let i = 0; i < d.length; i += 4) diff += Math.abs(d[i] - o[i]) + Math.abs(d[i + 1] - o[i + 1]);
      diff /= n;
    }
    const rgb = at ? Array.from(d.slice(4 * (at[1] * r.w + at[0]), 4 * (at[1] * r.w + at[0]) + 3)) : null;
    return { std: Math.sqrt(s2 / n - (s / n) ** 2), n, counts, rgb, diff };
  }, { id, rect, hexes, at, keep, compare });
}
/** With E2E_TIMES set, prints the seconds since the test began at each step (to find slow ones). */
let T0 = Date.now();
const lap = (label) => { if (process.env.E2E_TIMES) console.error(`  ${((Date.now() - T0) / 1000).toFixed(1)} s  ${label}`); };
const near = (a, b, tol) => a.every((x, i) => Math.abs(x - b[i]) < tol);

test('drive with a gamepad (stub): dead-man, sticks and D-pad flippers; views, minimap, picture in picture, help, HUD', async () => {
  // Quince on flat ground: two flipper pairs (D-pad: the front pair), room to drive.
  T0 = Date.now();
  const drive = start(['drive', 'scenarios/quince_flat.toml', '--port', '0', '--out', path.join(tmp, 'pad'), '--no-plot', '--duration', '60', '--wait-for-page']);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const { page } = await openDrive(ctx, url, gamepadStub);
    lap('page open');
    const scene = await page.evaluate(async () => (await fetch('/scene.json')).json());
    await simWait(page, 0.5); // settled on the ground
    // Without the dead-man (LB, button 4) the stick does nothing.
    await setAxes(page, [0, -1, 0, 0]);
    const s0 = await page.evaluate(() => window.tracksim.state);
    const s1 = await simWait(page, 0.5);
    assert.equal(s1.control.forward_mps, 0);
    assert.ok(Math.abs(s1.pose[0] - s0.pose[0]) < 0.01, `moved without LB: ${s0.pose[0]} -> ${s1.pose[0]}`);
    lap('no LB done');
    // LB + left stick forward (axes[1] = -1): 0.3 m/s forward (the page's default speed).
    await setButton(page, 4, true);
    await page.waitForFunction(() => window.tracksim.state.control.forward_mps > 0, null, { timeout: 10000 });
    const a = await page.evaluate(() => window.tracksim.state);
    assert.ok(Math.abs(a.control.forward_mps - 0.3) < 1e-9 && a.control.yaw_rate_rad_s === 0, JSON.stringify(a.control));
    const b = await simWait(page, 1.5, a.t);
    const dx = b.pose[0] - a.pose[0], dt = b.t - a.t;
    // From rest, the belts' ramp-up and a few per cent of slip on friction 0.6 cost some of
    // 0.3 m/s x dt; nothing can make the robot outrun its belts (5 % for the 0.1 s state
    // interval at either end).
    assert.ok(dx > 0.5 * 0.3 * dt && dx < 1.05 * 0.3 * dt + 0.03, `dx ${dx} m in ${dt} s at 0.3 m/s`);
    lap('forward done');
    // Stick left (axes[0] = -1): yaw rate +1 rad/s, the yaw grows (left, REP 103).
    await setAxes(page, [-1, 0, 0, 0]);
    await page.waitForFunction(() => window.tracksim.state.control.yaw_rate_rad_s > 0, null, { timeout: 10000 });
    const c = await page.evaluate(() => window.tracksim.state);
    assert.ok(Math.abs(c.control.yaw_rate_rad_s - 1.0) < 1e-9 && c.control.forward_mps === 0, JSON.stringify(c.control));
    // Quince skid-steers hard: commanded 1 rad/s in place from rest it turns 0.24 rad in the
    // first 1.5 s (`tracksim run quince_flat --commands` with yaw_rate_rad_s = 1: 0.096 rad at
    // 0.5 s, 0.244 at 1.5 s). Over 1.5 s it must turn left by more than 0.15 rad (margin for
    // when the states are read); 0.5 s was too short to tell reliably.
    const d = await simWait(page, 1.5, c.t);
    assert.ok(d.pose[5] - c.pose[5] > 0.15, `yaw ${c.pose[5]} -> ${d.pose[5]}`);
    await setAxes(page, [1, 0, 0, 0]);
    await page.waitForFunction(() => window.tracksim.state.control.yaw_rate_rad_s < 0, null, { timeout: 10000 });
    // Releasing LB stops the robot, the stick still pushed.
    await setAxes(page, [0, -1, 0, 0]);
    await setButton(page, 4, false);
    await page.waitForFunction(() => window.tracksim.state.control.forward_mps === 0 && window.tracksim.state.control.yaw_rate_rad_s === 0, null, { timeout: 10000 });
    const e = await simWait(page, 0.6);
    assert.ok(Math.abs(e.forward_mps) < 0.02, `still moving at ${e.forward_mps} m/s after LB released`);
    lap('turn+release done');
    // D-pad up (button 12) raises the front flipper pair's target 5 deg a press; they follow.
    // The front pair (front_left + front_right) moves; the rear pair's targets stay unset.
    const initial = scene.vehicle.flippers.map((f) => (f.initial_angle_rad * 180) / Math.PI);
    const front = scene.vehicle.flippers.map((f, i) => [f.name, i]).filter(([n]) => n.startsWith('front')).map(([, i]) => i);
    assert.equal(front.length, 2);
    for (let press = 1; press <= 2; press++) {
      await setButton(page, 12, true); await frames(page, 2); await setButton(page, 12, false); await frames(page, 2);
      await page.waitForFunction(([want, front]) => window.tracksim.state.control.flipper_angle_deg.every((x, i) => (front.includes(i) ? x !== null && Math.abs(x - want[i]) < 1e-9 : x === null)),
        [initial.map((x) => x + 5 * press), front], { timeout: 10000 });
    }
    await page.waitForFunction(([want, front]) => front.every((i) => Math.abs((window.tracksim.state.flipper[i] * 180) / Math.PI - want[i]) < 1.0),
      [initial.map((x) => x + 10), front], { timeout: 30000 });

    lap('flippers done');
    // ---- views: v cycles follow (chase), orbit, top-down, the onboard default mount ----
    assert.deepEqual(await page.evaluate(() => window.tracksim.views), ['follow', 'orbit', 'top-down', 'chassis front (default mount)']);
    const vx = scene.vehicle.body.vertices_m;
    let maxX = -Infinity, maxZ = -Infinity;
    for (let i = 0; i < vx.length; i += 3) { maxX = Math.max(maxX, vx[i]); maxZ = Math.max(maxZ, vx[i + 2]); }
    for (const name of ['follow', 'orbit', 'top-down', 'chassis front (default mount)']) {
      await page.waitForFunction((n) => window.tracksim.camera.view === n, name, { timeout: 10000 });
      const cam = await page.evaluate(() => window.tracksim.camera);
      const [x, y, z, , , yaw] = cam.pose;
      const toRobot = [x - cam.position[0], y - cam.position[1], z - cam.position[2]];
      const unit = (v) => { const l = Math.hypot(...v); return v.map((q) => q / l); };
      if (name === 'follow') {
        assert.ok(near(cam.position, [x - 1.8 * Math.cos(yaw), y - 1.8 * Math.sin(yaw), z + 0.9], 1e-6), `chase camera at ${cam.position}, robot ${cam.pose}`);
      } else if (name === 'orbit') {
        assert.ok(Math.hypot(...toRobot) > 0.5 && near(cam.direction, unit(toRobot), 1e-3), `orbit camera ${JSON.stringify(cam)}`);
      } else if (name === 'top-down') {
        assert.ok(near(cam.position, [x, y, z + 5], 1e-6) && near(cam.direction, [0, 0, -1], 1e-6), `top-down camera ${JSON.stringify(cam)}`);
      } else {
        const mount = add(cam.pose.slice(0, 3), rpyRotate(cam.pose.slice(3), [maxX + 0.01, 0, maxZ + 0.02]));
        assert.ok(dist(cam.position, mount) < 1e-4 && dist(cam.direction, rpyRotate(cam.pose.slice(3), [1, 0, 0])) < 1e-4, `onboard ${JSON.stringify(cam)}`);
      }
      if (name !== 'orbit') await page.screenshot({ path: path.join(artifacts, `view-${name.split(' ')[0]}.png`) });
      await page.keyboard.press('v');
    }
    await page.waitForFunction(() => window.tracksim.view === 'follow', null, { timeout: 10000 });
    lap('views done');
    // The minimap: drawn, the robot's red arrow on it, n hides and shows it.
    await frames(page, 1);
    const map = await pixels(page, 'minimap', { hexes: ['#ff3030'] });
    // Not blank (a uniform canvas reads std 0; drawn ones read 5-8, once 4.99 in CI) and the arrow
    // is on it.
    assert.ok(map.std > 3 && map.counts[0] > 10, `minimap: std ${map.std}, robot pixels ${map.counts[0]}`);
    assert.ok((await page.evaluate(() => window.tracksim.minimap.draws)) > 10);
    await page.keyboard.press('n');
    assert.equal(await page.evaluate(() => document.getElementById('minimap').offsetWidth), 0);
    await page.keyboard.press('n');
    assert.ok((await page.evaluate(() => document.getElementById('minimap').offsetWidth)) > 0);
    lap('minimap done');
    // Picture in picture (the onboard view in a corner; t, off at first): its rectangle differs
    // with it off; none in the onboard view itself.
    assert.equal((await page.evaluate(() => window.tracksim.pip)).shown, false);
    await page.keyboard.press('t');
    await frames(page, 1);
    const pip = await page.evaluate(() => window.tracksim.pip);
    assert.ok(pip.shown && pip.view === 'chassis front (default mount)', JSON.stringify(pip));
    const rect = { x: pip.rect.x, y: pip.rect.top, w: pip.rect.w, h: pip.rect.h };
    const withPip = await pixels(page, null, { rect, keep: 'pip' });
    await page.keyboard.press('t');
    await frames(page, 1);
    assert.equal((await page.evaluate(() => window.tracksim.pip)).shown, false);
    const { diff } = await pixels(page, null, { rect, compare: 'pip' });
    assert.ok(withPip.std > 5 && diff > 10, `picture in picture: std ${withPip.std}, mean difference ${diff}`);
    await page.keyboard.press('t');
    await frames(page, 1);
    await page.screenshot({ path: path.join(artifacts, 'pip-minimap.png') });
    await page.evaluate(() => window.tracksim.setView('chassis front (default mount)'));
    await frames(page, 1);
    assert.equal((await page.evaluate(() => window.tracksim.pip)).shown, false, 'no picture in picture of the onboard view in itself');
    await page.keyboard.press('t');
    await page.evaluate(() => window.tracksim.setView('follow'));
    lap('pip done');
    // ? hides the help (remembered), F1 shows it.
    assert.ok((await page.evaluate(() => document.getElementById('help').offsetWidth)) > 0);
    await page.keyboard.press('?');
    assert.equal(await page.evaluate(() => document.getElementById('help').offsetWidth), 0);
    assert.equal(await page.evaluate(() => localStorage.getItem('tracksim.help')), 'hidden');
    assert.ok((await page.evaluate(() => document.getElementById('help-tab').offsetWidth)) > 0);
    await page.screenshot({ path: path.join(artifacts, 'help-hidden.png') });
    await page.keyboard.press('F1');
    assert.ok((await page.evaluate(() => document.getElementById('help').offsetWidth)) > 0);

    lap('help done');
    // ---- HUD warnings from the live state: no stall at rest, the tilt title with the limit ----
    const live = await page.evaluate(() => window.tracksim.hud.info);
    assert.equal(live.stall, false);
    if (typeof scene.max_tilt_deg === 'number') assert.match(await page.textContent('#w-tilt-title'), new RegExp(`limit ${Math.round(scene.max_tilt_deg)}°`));
    // ---- and from made-up states (the server's fields as issue 28 names them) ----
    const base = await page.evaluate(() => window.tracksim.state);
    // Shown at once (and kept by the following frames).
    const show = (over) => page.evaluate((vs) => { window.tracksim.hudOverride = vs; return window.tracksim.hud.update(vs); },
      { ...base, belt_cmd: [0, 0], tilt_limit_deg: 70, ...over });
    const cls = (id) => page.evaluate((id) => document.getElementById(id).className, id);
    const rad = (d) => (d * Math.PI) / 180;
    let info = await show({ pose: [0, 0, 0, rad(0.5 * 70), 0, 0] });
    assert.equal(info.tiltLevel, 'ok');
    info = await show({ pose: [0, 0, 0, rad(0.7 * 70), 0, 0] });
    assert.equal(info.tiltLevel, 'amber');
    assert.match(await cls('w-tilt'), /amber/);
    info = await show({ pose: [0, 0, 0, rad(10), rad(0.9 * 70), 0] });
    assert.equal(info.tiltLevel, 'red');
    assert.match(await cls('w-tilt'), /\bon\b/);
    assert.ok((await pixels(page, 'w-tiltc', { hexes: ['#e23b3b'] })).counts[0] > 20, 'the pitch bar is red');
    info = await show({ stall: true, slip: [0.8, 0.1], outcome: { name: 'failure', reason: 'tipped over (roll 75 deg)', t: 12.5 } });
    assert.equal(info.stall, true);
    assert.match(await cls('w-stall'), /\bon\b/);
    assert.ok(Math.abs(info.slip - 0.8) < 1e-9 && (await pixels(page, 'w-slip', { hexes: ['#e23b3b'] })).counts[0] > 20, 'a red slip bar');
    assert.match(await cls('banner'), /failure/);
    assert.match(await page.textContent('#banner'), /FAILURE: tipped over/);
    info = await show({
      outcome: { name: 'success', reason: 'reached z', t: 14 },
      driver: { connected: false, grace_left_s: 7.2 },
      course: { name: 'figure8', next_gate: 2, gates_total: 4, repetitions: 1, laps: 3, rep_times_s: [61.2], elapsed_s: 42.5, time_limit_s: 300, faults: { reset: 0, tip_over: 1, touch: 2 }, penalty_s: 10, finished: false, events: [] },
      ahead: { d_m: [-0.5, 0, 0.4, 0.41, 1.0, 1.5], z_m: [0, 0, 0, 0.15, 0.15, 0.15] },
      flipper: [rad(40), rad(40)],
    });
    assert.match(await cls('banner'), /success/);
    assert.match(await page.textContent('#driver-banner'), /driver disconnected — reconnect within 8 s/);
    const courseText = await page.textContent('#course');
    assert.match(courseText, /gate +3 \/ 4/);
    assert.match(courseText, /tip-over 1, touch 2/);
    assert.match(courseText, /reps +1 \/ 3/);
    assert.ok(Math.abs(info.step_m - 0.15) < 1e-9, `step ahead ${info.step_m}`);
    // The side view: terrain colour above the base line where the step is, the flippers drawn.
    const { scale, zBase, xMin } = info.side;
    const side = await pixels(page, 'w-side', { hexes: ['#f0b040'], at: [Math.round((1.2 - xMin) * scale), Math.round(zBase - 0.1 * scale)] });
    assert.deepEqual(side.rgb, [0x8a, 0x7a, 0x5c], 'the step is drawn 0.1 m up at 1.2 m ahead');
    assert.ok(side.counts[0] > 10, 'the flippers are drawn');
    await page.screenshot({ path: path.join(artifacts, 'hud-warnings.png') });
    await page.evaluate(() => { window.tracksim.hudOverride = null; });
    await frames(page, 2);
    assert.match(await cls('driver-banner'), /hidden/);
    lap('hud done');
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
});

const wallOut = path.join(tmp, 'wall');

test('drive into a wall: the STALL warning appears', async () => {
  const drive = start(['drive', 'scenarios/wall_low_friction.toml', '--port', '0', '--out', wallOut, '--no-plot', '--duration', '30', '--speed', '2', '--wait-for-page']);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const { page } = await openDrive(ctx, url);
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction(() => window.tracksim.hud.info.stall, null, { timeout: 60000 });
    const s = await page.evaluate(() => window.tracksim.state);
    assert.ok(s.pose[0] > 0.2 && s.pose[0] < 1.0 && Math.abs(s.forward_mps) < 0.02 && s.control.forward_mps > 0, JSON.stringify(s.pose));
    assert.match(await page.evaluate(() => document.getElementById('w-stall').className), /\bon\b/);
    await page.screenshot({ path: path.join(artifacts, 'hud-stall.png') });
    await simWait(page, 0.5);
    await page.keyboard.up('ArrowUp');
    await page.waitForFunction(() => !window.tracksim.hud.info.stall, null, { timeout: 10000 });
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
});

test('review: the inputs strip, event markers and jumps of the wall session', async () => {
  // A course on the folder (as issue 28's scene.json and summary.json carry it), unless the
  // run has one: a gate and an obstacle, a gate passed and a fault.
  const scenePath = path.join(wallOut, 'scene.json'), summaryPath = path.join(wallOut, 'summary.json');
  const sceneJson = JSON.parse(fs.readFileSync(scenePath, 'utf8'));
  const summaryJson = JSON.parse(fs.readFileSync(summaryPath, 'utf8'));
  if (!sceneJson.course) {
    sceneJson.course = { name: 'test', gates: [{ x_m: 0.5, y_m: 0, width_m: 1.0, yaw_deg: 0 }], obstacles: [{ centre_m: [0.3, 1.0, 0.1], half_m: [0.1, 0.1, 0.1], yaw_deg: 20 }], laps: 1, time_limit_s: 60 };
    summaryJson.course = { events: [{ t_s: 0.7, kind: 'gate', detail: 'gate 1' }, { t_s: 1.2, kind: 'touch', detail: 'touched an obstacle' }] };
    fs.writeFileSync(scenePath, JSON.stringify(sceneJson));
    fs.writeFileSync(summaryPath, JSON.stringify(summaryJson));
  }
  const view = start(['view', wallOut, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    const events = await page.evaluate(() => window.tracksim.events);
    const kinds = events.map((e) => e.kind);
    assert.ok(kinds.includes('stall') && kinds.includes('tilt'), JSON.stringify(events));
    for (const e of summaryJson.course.events ?? []) assert.ok(events.some((x) => x.kind === e.kind && x.t_s === e.t_s), `course event ${JSON.stringify(e)}`);
    const nGates = sceneJson.course.gates.length;
    assert.deepEqual(await page.evaluate(() => window.tracksim.course), { gates: nGates, obstacles: sceneJson.course.obstacles.length });
    assert.equal(await page.evaluate(() => window.tracksim.minimap.gates), nGates);
    assert.equal(await page.evaluate(() => document.querySelectorAll('#markers button').length), events.length);
    // The inputs: from controls.csv, the forward command drawn (green).
    const inputs = await page.evaluate(() => window.tracksim.inputs);
    assert.equal(inputs.source, 'controls.csv');
    assert.deepEqual(inputs.lanes[0].series, ['forward m/s', 'yaw rad/s']);
    assert.ok(inputs.drawn > 10);
    assert.ok((await pixels(page, 'inputs', { hexes: ['#5ad35a'] })).counts[0] > 20, 'the forward command is drawn');
    // ] and [ jump to the next and previous events; a marker's click jumps to its event.
    await page.click('#play');
    await page.$eval('#scrub', (e) => { e.value = '0'; e.dispatchEvent(new Event('input')); });
    await page.waitForFunction(() => window.tracksim.replayTime === 0);
    // The page's rule: next is the first event more than 0.05 s ahead, previous the last more
    // than 0.25 s behind (so that [ while playing past an event goes back beyond it).
    const next = (t) => events.find((e) => e.t_s > t + 0.05);
    const prev = (t) => [...events].reverse().find((e) => e.t_s < t - 0.25);
    const now = () => page.evaluate(() => window.tracksim.replayTime);
    await page.keyboard.press(']');
    const first = next(0);
    assert.equal(await now(), first.t_s);
    const second = next(first.t_s);
    if (second) {
      await page.keyboard.press(']');
      assert.equal(await now(), second.t_s);
      const back = prev(second.t_s);
      await page.keyboard.press('[');
      assert.equal(await now(), back ? back.t_s : second.t_s);
    }
    const stall = events.findIndex((e) => e.kind === 'stall');
    // (The marker's own click: a neighbouring marker may lie over it on the bar.)
    await page.$eval(`#markers button[data-index="${stall}"]`, (b) => b.click());
    assert.equal(await page.evaluate(() => window.tracksim.replayTime), events[stall].t_s);
    // The replay shows the stall warning during the episode.
    await page.$eval('#scrub', (e, t) => { e.value = String(t); e.dispatchEvent(new Event('input')); }, (events[stall].t_s + 0.5) / (await page.evaluate(() => window.tracksim.replayEnd)));
    await frames(page, 2);
    assert.equal(await page.evaluate(() => window.tracksim.hud.info.stall), true);
    await page.screenshot({ path: path.join(artifacts, 'review.png') });
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

test('view of a compare folder: every method a ghost on one terrain, the outcome banner', async () => {
  const cmp = path.join(tmp, 'compare');
  const methods = ['plates', 'constraint_to_ground'];
  execFileSync(bin, ['compare', 'scenarios/wall_low_friction.toml', '--methods', methods.join(','), '--duration', '2', '--out', cmp], { cwd: root, stdio: 'ignore' });
  const view = start(['view', cmp, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    assert.deepEqual(await page.evaluate(() => window.tracksim.runs), methods);
    const status = (u) => page.evaluate(async (u) => (await fetch(u)).status, u);
    assert.equal(await status('/run/0/trajectory.csv'), 200);
    assert.equal(await status('/run/1/summary.json'), 200);
    assert.equal(await status('/run/2/trajectory.csv'), 404);
    assert.equal(await status('/run/trajectory.csv'), 404);
    assert.equal(await status('/run/1/../../secret'), 404);
    const ghosts = await page.evaluate(() => window.tracksim.ghosts());
    assert.equal(ghosts.length, 1);
    assert.equal(ghosts[0].name, methods[1]);
    assert.match(await page.textContent('#legend'), new RegExp(`${methods[0]}.*${methods[1]}`));
    // The ghost stands where its own run was at the replay time.
    await page.click('#play');
    await page.$eval('#scrub', (e) => { e.value = '0.5'; e.dispatchEvent(new Event('input')); });
    await frames(page, 2);
    const t = await page.evaluate(() => window.tracksim.replayTime);
    const rows = fs.readFileSync(path.join(cmp, methods[1], 'trajectory.csv'), 'utf8').trim().split('\n').slice(1).map((l) => l.split(',').map(Number));
    const k = rows.findIndex((r) => r[0] >= t - 1e-9);
    const w = k > 0 ? (t - rows[k - 1][0]) / (rows[k][0] - rows[k - 1][0]) : 0;
    const want = [1, 2, 3].map((c) => (k > 0 ? rows[k - 1][c] + w * (rows[k][c] - rows[k - 1][c]) : rows[k][c]));
    const got = (await page.evaluate(() => window.tracksim.ghosts()))[0].position;
    assert.ok(near(got, want, 1e-6), `ghost at ${got}, its run at ${want}`);
    // At the end the outcome is decided: the banner in its colour.
    const summary = JSON.parse(fs.readFileSync(path.join(cmp, methods[0], 'summary.json'), 'utf8'));
    await page.$eval('#scrub', (e) => { e.value = '1'; e.dispatchEvent(new Event('input')); });
    await frames(page, 2);
    const banner = await page.evaluate(() => window.tracksim.hud.info.banner);
    assert.ok(banner && banner.kind === (summary.outcome === 'success' || summary.outcome === 'failure' ? summary.outcome : 'other'), JSON.stringify({ banner, outcome: summary.outcome }));
    assert.ok((await page.evaluate(() => window.tracksim.events)).filter((e) => e.kind === 'outcome').length >= 1);
    await page.screenshot({ path: path.join(artifacts, 'compare.png') });
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

test('a course session: the live score from the server, a reload reconnects and drives on, the trainee in the sessions table', async () => {
  const out = path.join(tmp, 'sessions', 'course-stairs');
  const drive = start(['drive', 'scenarios/course_stairs.toml', '--port', '0', '--out', out, '--no-plot', '--wait-for-page',
    '--trainee', 'Test Trainee', '--reconnect-grace', '20']);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const { page } = await openDrive(ctx, url);
    assert.equal(await page.evaluate(() => window.tracksim.role), 'driver');
    // The server's fields: the score of the course (run/course.rs), the warnings' data.
    const s0 = await page.evaluate(() => window.tracksim.state);
    assert.equal(s0.course.name, 'stairs to the landing', JSON.stringify(s0.course));
    assert.equal(s0.course.repetitions_required, 1);
    assert.ok(s0.course.gates_total >= 1 && s0.course.next_gate === 0, JSON.stringify(s0.course));
    assert.equal(s0.tilt_limit_deg, 70);
    assert.equal(s0.slip.length, s0.belt_speed.length);
    assert.equal(typeof s0.stall, 'boolean');
    assert.equal(s0.driver.connected, true);
    // The stairs begin 0.9 m ahead of the start (scenarios/course_stairs.toml: rise 0.15 m).
    assert.ok(Math.abs(s0.ahead.step_m - 0.15) < 0.02, JSON.stringify(s0.ahead));
    await page.waitForFunction(() => /stairs to the landing/.test(document.getElementById('course').textContent), null, { timeout: 10000 });
    assert.match(await page.evaluate(() => document.getElementById('course').textContent), /reps\s+0 \/ 1/);
    // Drive a little, then reload the page: it reconnects with its token and drives on.
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction(() => window.tracksim.state.forward_mps > 0.2, null, { timeout: 30000 });
    await page.keyboard.up('ArrowUp');
    await page.reload();
    await page.waitForFunction(() => window.tracksim?.state && window.tracksim.role === 'driver' && window.tracksim.state.driver.reconnects === 1, null, { timeout: 30000 });
    const x1 = await page.evaluate(() => window.tracksim.state.pose[0]);
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction((x) => window.tracksim.state.pose[0] > x + 0.05, x1, { timeout: 30000 });
    await page.keyboard.up('ArrowUp');
    await page.screenshot({ path: path.join(artifacts, 'course-live.png') });
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
  const summary = JSON.parse(fs.readFileSync(path.join(out, 'summary.json'), 'utf8'));
  assert.equal(summary.trainee, 'Test Trainee');
  assert.equal(summary.course.name, 'stairs to the landing');
  assert.ok(summary.events.some((e) => e.kind === 'outcome'));
  // The session in the folder's table, as CSV.
  const csv = execFileSync(bin, ['sessions', path.join(tmp, 'sessions'), '--csv'], { cwd: root }).toString();
  const [head, row] = csv.trim().split('\n');
  assert.match(head, /trainee/);
  assert.match(row, /Test Trainee/);
  assert.match(row, /stairs to the landing/);
});

test('soil (issue 30): a drive on dry sand draws its ruts live, and its replay reveals them with the clock', async () => {
  const sandOut = path.join(tmp, 'sand');
  const drive = start(['drive', 'soil/packbot_dry_sand', '--port', '0', '--out', sandOut]);
  const url = await drive.url;
  const ctx = await browser();
  try {
    const { page } = await openDrive(ctx, url);
    // Landing on the sand already presses ruts under both tracks.
    await page.waitForFunction(() => window.tracksim.ruts.count > 50, null, { timeout: 30000 });
    const n0 = await page.evaluate(() => window.tracksim.ruts.count);
    const x0 = await page.evaluate(() => window.tracksim.state.pose[0]);
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction((x) => window.tracksim.state.pose[0] > x + 0.3, x0, { timeout: 60000 });
    await page.keyboard.up('ArrowUp');
    // 0.3 m more of two 75 mm tracks on a 1 cm grid: about 450 new cells.
    const n1 = await page.evaluate(() => window.tracksim.ruts.count);
    assert.ok(n1 > n0 + 200, `ruts drawn live: ${n0} -> ${n1}`);
    const deepest = await page.evaluate(() => window.tracksim.ruts.deepest);
    assert.ok(deepest > 0.001 && deepest < 0.02, `deepest rut ${deepest} m`);
    await page.screenshot({ path: path.join(artifacts, 'soil-drive.png') });
    await page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
  const cells = fs.readFileSync(path.join(sandOut, 'ruts.csv'), 'utf8').trim().split('\n').length - 1;
  assert.ok(cells > 300, `ruts.csv has ${cells} cells`);
  const view = start(['view', sandOut, '--port', '0']);
  const viewUrl = await view.url;
  const ctx2 = await browser();
  try {
    const page = await openReplay(ctx2, viewUrl);
    // Early in the replay only the landing's ruts; at the end every cell of ruts.csv.
    await page.click('#play');
    await page.$eval('#scrub', (e) => { e.value = '0'; e.dispatchEvent(new Event('input')); });
    await page.waitForFunction(() => window.tracksim.frames > 0 && window.tracksim.replayTime < 0.05);
    await page.waitForTimeout(200);
    const early = await page.evaluate(() => window.tracksim.ruts.count);
    await page.$eval('#scrub', (e) => { e.value = '1'; e.dispatchEvent(new Event('input')); });
    await page.waitForFunction((n) => window.tracksim.ruts.count === n, cells, { timeout: 10000 });
    assert.ok(early < cells, `replay at t=0 shows ${early} of ${cells} cells`);
    await page.screenshot({ path: path.join(artifacts, 'soil-view.png') });
  } finally {
    await ctx2.close();
    view.child.kill();
  }
});

test('several robots (issue 40): a seat per trainee, each page its own robot, a watcher, the session replayed byte for byte', async () => {
  const out = path.join(tmp, 'team-drive');
  const file = 'scenarios/team/rescue_site.toml';
  const drive = start(['drive', file, '--port', '0', '--out', out, '--no-plot', '--wait-for-page']);
  const url = await drive.url;
  const ctx = await browser();
  try {
    // The first page takes the first free seat (packbot) and loads that robot's page.
    const a = await openDrive(ctx, url);
    await a.page.waitForFunction(() => window.tracksim.robot === 'packbot' && window.tracksim.role === 'driver', null, { timeout: 30000 });
    assert.match(a.page.url(), /\?robot=packbot$/);
    // A second trainee picks quince (another vehicle: its own scene); a third page watches packbot.
    const b = await openDrive(ctx, `${url}?robot=quince`);
    assert.equal(await b.page.evaluate(() => window.tracksim.role), 'driver');
    const w = await openDrive(ctx, `${url}?watch=1&robot=packbot`);
    assert.equal(await w.page.evaluate(() => window.tracksim.role), 'watcher');
    assert.equal(await w.page.evaluate(() => window.tracksim.state.robot), 'packbot');
    const sceneA = await a.page.evaluate(async () => (await (await fetch('/scene.json?robot=packbot')).json()).vehicle);
    const sceneB = await b.page.evaluate(async () => (await (await fetch('/scene.json?robot=quince')).json()).vehicle);
    assert.notDeepEqual(sceneA, sceneB, 'each robot its own vehicle');
    assert.equal(await a.page.evaluate(() => document.getElementById('robot-select').options.length), 6);
    // Both drive at once: packbot forward, quince turning.
    const xa = await a.page.evaluate(() => window.tracksim.state.pose[0]);
    const yawB = await b.page.evaluate(() => window.tracksim.state.pose[5]);
    await a.page.keyboard.down('ArrowUp');
    await b.page.keyboard.down('ArrowLeft');
    await a.page.waitForFunction((x) => window.tracksim.state.pose[0] > x + 0.1, xa, { timeout: 60000 });
    await b.page.waitForFunction((y) => window.tracksim.state.pose[5] > y + 0.1, yawB, { timeout: 60000 });
    // The watcher sees packbot move; quince's page draws packbot and the URDF PackBot as others.
    await w.page.waitForFunction((x) => window.tracksim.state.pose[0] > x + 0.1, xa, { timeout: 30000 });
    await b.page.waitForFunction(() => window.tracksim.others().length === 2, null, { timeout: 10000 });
    const others = await b.page.evaluate(() => window.tracksim.others());
    const pb = others.find((o) => o.name === 'packbot');
    assert.ok(pb && pb.position[0] > xa + 0.05, JSON.stringify(others));
    // Each drawn with its own vehicle (its scene.json), not quince's.
    assert.equal(pb.vehicle, sceneA.name, JSON.stringify(others));
    assert.notEqual(pb.vehicle, sceneB.name);
    await b.page.screenshot({ path: path.join(artifacts, 'team-drive.png') });
    await a.page.keyboard.up('ArrowUp');
    await b.page.keyboard.up('ArrowLeft');
    // The first trainee ends: their seat closes, the other drives on; the second ends the session.
    await a.page.click('#stop');
    await a.page.waitForFunction(() => window.tracksim.role === 'watcher', null, { timeout: 10000 });
    await b.page.click('#stop');
    const { code, out: printed } = await drive.exited;
    assert.equal(code, 0, printed);
    assert.deepEqual([...a.errors, ...b.errors, ...w.errors], []);
  } finally {
    await ctx.close();
    drive.child.kill();
  }
  const toml = fs.readFileSync(path.join(out, 'commands.toml'), 'utf8');
  assert.match(toml, /\[\[vehicles\]\]\nname = "packbot"/);
  const duration = toml.match(/--duration ([0-9.e-]+)/)[1];
  const again = path.join(tmp, 'team-again');
  execFileSync(bin, ['run', file, '--commands', path.join(out, 'commands.toml'), '--duration', duration, '--out', again, '--quiet', '--no-plot'], { cwd: root });
  for (const r of ['packbot', 'packbot_urdf', 'quince']) {
    assert.equal(fs.readFileSync(path.join(again, r, 'trajectory.csv'), 'utf8'), fs.readFileSync(path.join(out, r, 'trajectory.csv'), 'utf8'), `${r} replays`);
  }
  // `tracksim view` of the session's folder: every robot, each with its own vehicle.
  const view = start(['view', out, '--port', '0']);
  const vctx = await browser();
  try {
    const page = await openReplay(vctx, await view.url);
    const ghosts = await page.evaluate(() => window.tracksim.ghosts());
    const vehicles = new Set(ghosts.map((g) => g.vehicle));
    assert.equal(ghosts.length, 2, JSON.stringify(ghosts));
    assert.equal(vehicles.size, 2, `each robot its own vehicle: ${JSON.stringify(ghosts)}`);
    await page.screenshot({ path: path.join(artifacts, 'team-view.png') });
  } finally {
    await vctx.close();
    view.child.kill();
  }
});

/** Starts `tracksim drive ARGS --port 0 --out DIR --speed 2` and waits for its two printed
 * URLs: the trainees' page and the instructor's (with its token). */
async function driveWithInstructor(args, dir) {
  const child = spawn(bin, ['drive', ...args, '--port', '0', '--out', dir, '--speed', '2'], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let printed = '';
  const urls = new Promise((resolve, reject) => {
    child.stdout.on('data', (d) => {
      printed += d;
      const m = printed.match(/open (http:\/\/127\.0\.0\.1:\d+\/) in a browser/);
      const i = printed.match(/instructor open (http:\/\/127\.0\.0\.1:\d+\/\?instructor=[0-9a-f]{32})/);
      if (m && i) resolve([m[1], i[1]]);
    });
    child.on('exit', (code) => reject(new Error(`tracksim drive exited ${code}: ${printed}`)));
  });
  const exited = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
  const [url, instructorUrl] = await urls;
  return { child, exited, url, instructorUrl, output: () => printed };
}

test('two trainees (issue 43): the instructor resets one robot, a trainee resets their own with Backspace, the other drives on each time; the session replays byte for byte, attempts included', async () => {
  const dir = path.join(tmp, 'team-reset');
  const file = 'scenarios/team/race_step.toml';
  const { child, exited, url, instructorUrl, output } = await driveWithInstructor([file, '--no-plot'], dir);
  const ctx = await browser();
  try {
    const red = await openDrive(ctx, `${url}?robot=red`);
    const blue = await openDrive(ctx, `${url}?robot=blue`);
    const teacher = await openDrive(ctx, `${instructorUrl}&robot=blue`);
    await teacher.page.waitForFunction(() => window.tracksim.role === 'instructor' && window.tracksim.robot === 'blue' && document.getElementById('i-reset'), null, { timeout: 30000 });
    await red.page.bringToFront();
    await red.page.keyboard.down('ArrowUp');
    await blue.page.bringToFront();
    await blue.page.keyboard.down('ArrowUp');
    await blue.page.waitForFunction(() => window.tracksim.state.pose[0] > 0.2, null, { timeout: 60000 });
    await red.page.waitForFunction(() => window.tracksim.state.pose[0] > 0.2, null, { timeout: 60000 });
    await blue.page.keyboard.up('ArrowUp');
    // The instructor resets blue (the robot their page follows): blue is back at its start
    // (x 0, y -0.7 m), red drives on.
    const redBefore = await red.page.evaluate(() => window.tracksim.state.pose[0]);
    await teacher.page.click('#i-reset');
    await blue.page.waitForFunction(() => Math.abs(window.tracksim.state.pose[0]) < 0.02 && Math.abs(window.tracksim.state.pose[1] + 0.7) < 0.02, null, { timeout: 20000 });
    const blueT = await blue.page.evaluate(() => window.tracksim.state.t);
    await red.page.waitForFunction((t) => window.tracksim.state.t > t + 0.3, blueT, { timeout: 20000 });
    const redAfter = await red.page.evaluate(() => window.tracksim.state.pose[0]);
    assert.ok(redAfter > redBefore + 0.05, `red drives on: x ${redBefore} -> ${redAfter}`);
    // Blue drives again; red's trainee presses Backspace: red alone is back at its start
    // (x 0, y +0.7 m), blue drives on.
    await blue.page.bringToFront();
    await blue.page.keyboard.down('ArrowUp');
    await blue.page.waitForFunction(() => window.tracksim.state.pose[0] > 0.1, null, { timeout: 60000 });
    await red.page.bringToFront();
    await red.page.keyboard.up('ArrowUp');
    const blueBefore = await blue.page.evaluate(() => window.tracksim.state.pose[0]);
    await red.page.keyboard.press('Backspace');
    await red.page.waitForFunction(() => Math.abs(window.tracksim.state.pose[0]) < 0.02 && Math.abs(window.tracksim.state.pose[1] - 0.7) < 0.02, null, { timeout: 20000 });
    const redT = await red.page.evaluate(() => window.tracksim.state.t);
    await blue.page.waitForFunction((t) => window.tracksim.state.t > t + 0.3, redT, { timeout: 20000 });
    const blueAfter = await blue.page.evaluate(() => window.tracksim.state.pose[0]);
    assert.ok(blueAfter > blueBefore + 0.05, `blue drives on: x ${blueBefore} -> ${blueAfter}`);
    await blue.page.keyboard.up('ArrowUp');
    await teacher.page.click('#i-end');
    assert.equal(await exited, 0, output());
    assert.deepEqual([...red.errors, ...blue.errors, ...teacher.errors], []);
  } finally {
    await ctx.close();
    child.kill();
  }
  const toml = fs.readFileSync(path.join(dir, 'commands.toml'), 'utf8');
  assert.equal((toml.match(/reset = true/g) ?? []).length, 2, toml);
  for (const f of ['trajectory.csv', 'summary.json', 'scene.json', 'controls.csv']) {
    assert.ok(fs.existsSync(path.join(dir, 'blue/attempts/1', f)), `blue/attempts/1/${f}`);
    assert.ok(fs.existsSync(path.join(dir, 'red/attempts/1', f)), `red/attempts/1/${f}`);
  }
  assert.ok(!fs.existsSync(path.join(dir, 'red/attempts/2')), 'red was reset once');
  const redEvents = JSON.parse(fs.readFileSync(path.join(dir, 'red/attempts/1/summary.json'), 'utf8')).events;
  assert.ok(redEvents.some((e) => e.detail.startsWith("red's driver reset")), JSON.stringify(redEvents));
  const summary = JSON.parse(fs.readFileSync(path.join(dir, 'blue/summary.json'), 'utf8'));
  assert.deepEqual(summary.attempts.map((a) => a.folder), ['attempts/1', '.']);
  const duration = toml.match(/--duration ([0-9.e-]+)/)[1];
  const again = path.join(tmp, 'team-reset-again');
  execFileSync(bin, ['run', file, '--commands', path.join(dir, 'commands.toml'), '--duration', duration, '--out', again, '--quiet', '--no-plot'], { cwd: root });
  for (const r of ['red', 'blue', 'blue/attempts/1', 'red/attempts/1']) {
    assert.equal(fs.readFileSync(path.join(again, r, 'trajectory.csv'), 'utf8'), fs.readFileSync(path.join(dir, r, 'trajectory.csv'), 'utf8'), `${r} replays`);
  }
  // The review of blue steps through its two attempts.
  const view = start(['view', path.join(dir, 'blue'), '--port', '0']);
  const vctx = await browser();
  try {
    const page = await openReplay(vctx, `${await view.url}?attempt=1`);
    assert.deepEqual(await page.evaluate(() => window.tracksim.attempts), [1, 2]);
  } finally {
    await vctx.close();
    view.child.kill();
  }
  // The review of the whole team: the solid robot (blue, first by name) replays both its
  // attempts, and its events, course score and outcome are those of the attempt under way.
  const teamView = start(['view', dir, '--port', '0']);
  const tctx = await browser();
  try {
    const page = await openReplay(tctx, await teamView.url);
    assert.deepEqual(await page.evaluate(() => window.tracksim.runs), ['blue', 'red']);
    const parts = await page.evaluate(() => window.tracksim.parts);
    assert.deepEqual(parts.map((p) => p.attempt), [1, 2]);
    assert.equal(parts[0].from_s, 0);
    const reset = parts[1].from_s;
    const first = JSON.parse(fs.readFileSync(path.join(dir, 'blue/attempts/1/summary.json'), 'utf8'));
    assert.ok(Math.abs(reset - first.sim_time_s) < 0.011, `attempt 2 starts where attempt 1 ended: ${reset} ${first.sim_time_s}`);
    const events = await page.evaluate(() => window.tracksim.events);
    assert.ok(events.some((e) => e.detail.startsWith('the instructor reset blue') && e.t_s <= reset + 1e-9), JSON.stringify(events));
    assert.ok(events.some((e) => e.t_s > reset), JSON.stringify(events));
    const [before, after] = await page.evaluate((t) => [window.tracksim.courseAt(t - 0.1), window.tracksim.courseAt(t + 0.1)], reset);
    assert.equal(before.faults.reset, 0, JSON.stringify(before));
    assert.ok(Math.abs(before.elapsed_s - (reset - 0.1)) < 1e-6, JSON.stringify(before));
    assert.equal(after.faults.reset, 1, JSON.stringify(after));
    assert.ok(Math.abs(after.elapsed_s - 0.1) < 1e-6, JSON.stringify(after));
    // `?robot=red` makes red the solid robot, with its own attempts (red's driver's reset).
    const redPage = await openReplay(tctx, `${await teamView.url}?robot=red`);
    assert.deepEqual(await redPage.evaluate(() => window.tracksim.runs), ['red', 'blue']);
    const redParts = await redPage.evaluate(() => window.tracksim.parts);
    assert.deepEqual(redParts.map((p) => p.attempt), [1, 2]);
    const redReset = redParts[1].from_s;
    const redEvents = await redPage.evaluate(() => window.tracksim.events);
    assert.ok(redEvents.some((e) => e.detail.startsWith("red's driver reset") && e.t_s <= redReset + 1e-9), JSON.stringify(redEvents));
    assert.equal((await redPage.evaluate((t) => window.tracksim.courseAt(t + 0.1), redReset)).faults.reset, 1);
  } finally {
    await tctx.close();
    teamView.child.kill();
  }
});

test('view: the replay page offers the run as an MP4 that the browser plays (issue 41)', async () => {
  const dir = path.join(tmp, 'video-run');
  execFileSync(bin, ['run', 'packbot_step', '--out', dir, '--duration', '1'], { cwd: root });
  const view = start(['view', dir, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    assert.equal(await page.evaluate(() => window.tracksim.video), true);
    assert.ok(await page.isVisible('#video-link'));
    assert.equal(await page.getAttribute('#video-link', 'href'), '/video.mp4');
    // The server renders it on the first request: H.264 in MP4, played by the page's browser.
    const got = await page.evaluate(async () => {
      const r = await fetch('/video.mp4');
      const blob = await r.blob();
      const v = document.createElement('video');
      v.muted = true;
      v.src = URL.createObjectURL(blob);
      const ok = await new Promise((resolve) => {
        v.onloadeddata = () => resolve(true);
        v.onerror = () => resolve(`error ${v.error?.code} ${v.error?.message}`);
        setTimeout(() => resolve('timeout'), 30000);
      });
      let std = 0;
      if (ok === true) {
        // A frame in the middle, once the element has it.
        await new Promise((resolve) => { v.onseeked = resolve; v.currentTime = 0.5; setTimeout(resolve, 10000); });
        const c = document.createElement('canvas');
        c.width = v.videoWidth; c.height = v.videoHeight;
        const g = c.getContext('2d');
        g.drawImage(v, 0, 0);
        const d = g.getImageData(0, 0, c.width, c.height).data;
        let s = 0, s2 = 0, n = 0;
        for (let i = 0; i < d.length; i += 16) { const y = (d[i] + d[i + 1] + d[i + 2]) / 3; s += y; s2 += y * y; n++; }
        std = Math.sqrt(s2 / n - (s / n) ** 2);
      }
      return { status: r.status, type: r.headers.get('content-type'), size: blob.size, ok, w: v.videoWidth, h: v.videoHeight, duration: v.duration, std };
    });
    assert.equal(got.status, 200);
    assert.equal(got.type, 'video/mp4');
    assert.equal(got.ok, true, `the browser does not play it: ${got.ok}`);
    assert.deepEqual([got.w, got.h], [640, 480]);
    assert.ok(Math.abs(got.duration - 1.04) < 0.05, `duration ${got.duration}`);
    assert.ok(got.std > 5, `blank first frame (std ${got.std})`);
  } finally {
    await ctx.close();
    view.child.kill();
  }
});

test('review of a course run (issue 43): the course panel at the replay time, the debrief linked, sessions as trainee ghosts', async () => {
  const sessions = path.join(tmp, 'school');
  const out = path.join(sessions, 'a-climb');
  execFileSync(bin, ['run', 'scenarios/course_stairs.toml', '--out', out, '--no-plot', '--quiet', '--trainee', 'C. Climber'], { cwd: root, stdio: 'ignore' });
  const summary = JSON.parse(fs.readFileSync(path.join(out, 'summary.json'), 'utf8'));
  const gates = summary.course.events.filter((e) => e.kind === 'gate');
  assert.equal(gates.length, 2, JSON.stringify(summary.course.events));
  const view = start(['view', out, '--port', '0']);
  const url = await view.url;
  const ctx = await browser();
  try {
    const page = await openReplay(ctx, url);
    const end = await page.evaluate(() => window.tracksim.replayEnd);
    await page.click('#play'); // paused
    const at = async (t) => {
      await page.$eval('#scrub', (e, f) => { e.value = String(f); e.dispatchEvent(new Event('input')); }, t / end);
      await frames(page, 2);
      return { t: await page.evaluate(() => window.tracksim.replayTime), text: await page.textContent('#course'), c: await page.evaluate(() => window.tracksim.replayCourse) };
    };
    // Before the first gate, between the two, at the end.
    const early = await at(gates[0].t_s / 2);
    const middle = await at((gates[0].t_s + gates[1].t_s) / 2);
    const last = await at(end);
    assert.equal(early.c.gates_passed, 0, JSON.stringify(early.c));
    assert.equal(middle.c.gates_passed, 1, JSON.stringify(middle.c));
    assert.equal(last.c.gates_passed, 2, JSON.stringify(last.c));
    assert.match(early.text, /passed\s+0 gates/);
    assert.match(middle.text, /passed\s+1 gates/);
    assert.match(last.text, /passed\s+2 gates/);
    assert.match(early.text, /reps\s+0 \/ 1/);
    assert.match(last.text, /reps\s+1 \/ 1/);
    assert.doesNotMatch(early.text, /FINISHED/);
    assert.match(last.text, /FINISHED/);
    // The time shown is the replay time's; the score at the end is the run's.
    assert.ok(Math.abs(early.c.elapsed_s - early.t) < 1e-9, JSON.stringify({ c: early.c.elapsed_s, t: early.t }));
    assert.match(early.text, new RegExp(`time +${early.t.toFixed(1)} s`));
    assert.match(last.text, new RegExp(`score +${summary.course.score.score_s.toFixed(1)} s`));
    // The printable debrief, linked from the time bar, served under a policy that runs nothing.
    assert.equal(await page.evaluate(() => window.tracksim.debrief), true);
    assert.equal(await page.getAttribute('#debrief-link', 'href'), '/run/debrief.html');
    assert.ok(await page.isVisible('#debrief-link'));
    const got = await page.evaluate(async () => { const r = await fetch('/run/debrief.html'); return { status: r.status, type: r.headers.get('content-type'), csp: r.headers.get('content-security-policy'), text: await r.text() }; });
    assert.equal(got.status, 200);
    assert.match(got.type, /text\/html/);
    assert.match(got.csp, /sandbox/);
    assert.match(got.text, /C\. Climber/);
    assert.ok(got.text.includes(`${summary.course.score.score_s.toFixed(2)} s`));
    const dp = await ctx.newPage();
    await dp.goto(new URL('/run/debrief.html', url).href);
    assert.equal(await dp.locator('svg.map .gate').count(), 2);
    await dp.pdf?.({ path: path.join(artifacts, 'debrief.pdf') }).catch(() => {});
    await dp.screenshot({ path: path.join(artifacts, 'debrief.png'), fullPage: true });
    await page.screenshot({ path: path.join(artifacts, 'review-course.png') });
  } finally {
    await ctx.close();
    view.child.kill();
  }
  // A folder of sessions: every run a ghost named by its trainee (summary.json), not its folder.
  const other = path.join(sessions, 'b-climb');
  fs.cpSync(out, other, { recursive: true });
  const s2 = JSON.parse(fs.readFileSync(path.join(other, 'summary.json'), 'utf8'));
  s2.trainee = 'D. Driver';
  fs.writeFileSync(path.join(other, 'summary.json'), JSON.stringify(s2));
  const view2 = start(['view', sessions, '--port', '0']);
  const url2 = await view2.url;
  const ctx2 = await browser();
  try {
    const page = await openReplay(ctx2, url2);
    assert.deepEqual(await page.evaluate(() => window.tracksim.runs), ['a-climb', 'b-climb']);
    const ghosts = await page.evaluate(() => window.tracksim.ghosts());
    assert.equal(ghosts.length, 1);
    assert.equal(ghosts[0].name, 'D. Driver');
    assert.equal(ghosts[0].folder, 'b-climb');
    const legend = await page.textContent('#legend');
    assert.match(legend, /trainees.*C\. Climber.*D\. Driver/);
    assert.doesNotMatch(legend, /a-climb|b-climb/);
  } finally {
    await ctx2.close();
    view2.child.kill();
  }
});

test('the instructor (issue 43): pause stops simulated time, a track stop, a video drop and a low-friction patch, a reset keeps the attempt', async () => {
  const dir = path.join(tmp, 'instructor');
  const { child, exited, url, instructorUrl, output } = await driveWithInstructor(['scenarios/packbot_flat.toml'], dir);
  // The trainee's page does not get the instructor's token.
  const served = await (await fetch(`${url}session.json`)).text();
  assert.ok(!served.includes(instructorUrl.split('=')[1]), served);
  const ctx = await browser();
  try {
    const errors = [];
    const trainee = await ctx.newPage();
    trainee.on('pageerror', (e) => errors.push(String(e)));
    await trainee.goto(url);
    await trainee.waitForFunction(() => window.tracksim?.state && window.tracksim.role === 'driver', null, { timeout: 60000 })
      .catch((e) => { throw new Error(`${e.message}; page errors: ${errors.join(' | ') || 'none'}`); });
    const teacher = await ctx.newPage();
    teacher.on('pageerror', (e) => errors.push(String(e)));
    await teacher.goto(instructorUrl);
    await teacher.waitForFunction(() => window.tracksim?.role === 'instructor' && document.getElementById('i-pause'), null, { timeout: 60000 });
    await trainee.bringToFront();
    await trainee.keyboard.down('ArrowUp');
    await trainee.waitForFunction(() => window.tracksim.state.t > 1 && window.tracksim.state.forward_mps > 0.1, null, { timeout: 60000 });
    await trainee.keyboard.up('ArrowUp');
    // Pause: simulated time stands still on both pages, the trainee's HUD says so.
    await teacher.click('#i-pause');
    await trainee.waitForFunction(() => window.tracksim.state.paused === true, null, { timeout: 20000 });
    const t0 = await trainee.evaluate(() => window.tracksim.state.t);
    await new Promise((r) => setTimeout(r, 1000));
    assert.equal(await trainee.evaluate(() => window.tracksim.state.t), t0, 'simulated time moved while paused');
    assert.match(await trainee.evaluate(() => document.getElementById('hud').textContent), /PAUSED by the instructor/);
    await teacher.click('#i-pause');
    await trainee.waitForFunction((t) => window.tracksim.state.paused === false && window.tracksim.state.t > t + 0.2, t0, { timeout: 20000 });
    // A track stop: in the state and on the instructor's HUD.
    await teacher.selectOption('#instructor div:nth-child(3) select', 'stopped');
    await teacher.waitForFunction(() => window.tracksim.state.faults?.track?.includes('stopped'), null, { timeout: 20000 });
    // The HUD is redrawn on its own frames (slower in a loaded headless browser): wait for it.
    await teacher.waitForFunction(() => /faults +track \w+ stopped/.test(document.getElementById('hud').textContent), null, { timeout: 20000 });
    // A low-friction patch put under the robot from the panel: in the state, drawn on both
    // pages (a wet patch is visible in reality), listed on the instructor's HUD.
    await teacher.fill('#i-patch-mu', '0.15');
    await teacher.click('#i-patch-put');
    for (const p of [trainee, teacher]) {
      await p.waitForFunction(() => window.tracksim.patch?.friction === 0.15 && window.tracksim.patchDrawn > 0 && window.tracksim.state.faults.patch?.size_m[0] === 2, null, { timeout: 20000 });
    }
    await teacher.waitForFunction(() => /low-friction patch 0\.15 \(2\.0 x 2\.0 m/.test(document.getElementById('hud').textContent), null, { timeout: 20000 });
    await trainee.screenshot({ path: path.join(artifacts, 'instructor-patch-trainee.png') });
    // The video drops: the trainee sees NO SIGNAL, the instructor everything.
    await teacher.evaluate(() => window.tracksim.instructor.fault({ video: 'dropped' }));
    await trainee.waitForFunction(() => window.tracksim.noSignal === true, null, { timeout: 20000 });
    assert.equal(await trainee.evaluate(() => getComputedStyle(document.getElementById('nosignal')).display), 'flex');
    await teacher.waitForFunction(() => window.tracksim.state.faults.video === 'dropped', null, { timeout: 20000 });
    assert.equal(await teacher.evaluate(() => window.tracksim.noSignal), false);
    await trainee.screenshot({ path: path.join(artifacts, 'instructor-no-signal.png') });
    await teacher.screenshot({ path: path.join(artifacts, 'instructor.png') });
    // A reset: a second attempt.
    await teacher.click('#i-reset');
    await trainee.waitForFunction(() => window.tracksim.state.attempt === 2 && window.tracksim.noSignal === false, null, { timeout: 20000 });
    await trainee.waitForFunction(() => window.tracksim.state.t > 0.5, null, { timeout: 20000 });
    await teacher.click('#i-end');
    assert.equal(await exited, 0, output());
    assert.deepEqual(errors, []);
  } finally {
    await ctx.close();
    child.kill();
  }
  const first = path.join(dir, 'attempts/1');
  for (const f of ['trajectory.csv', 'summary.json', 'commands.toml', 'controls.csv', 'scene.json']) {
    assert.ok(fs.existsSync(path.join(first, f)), `attempts/1/${f}`);
  }
  const commands = fs.readFileSync(path.join(first, 'commands.toml'), 'utf8');
  assert.match(commands, /= "stopped"/);
  assert.match(commands, /video = "dropped"/);
  assert.match(commands, /friction = 0\.15/);
  const summary = JSON.parse(fs.readFileSync(path.join(dir, 'summary.json'), 'utf8'));
  assert.deepEqual(summary.attempts.map((a) => a.folder), ['attempts/1', '.']);
  const kinds = JSON.parse(fs.readFileSync(path.join(first, 'summary.json'), 'utf8')).events.map((e) => e.kind);
  for (const k of ['pause', 'resume', 'fault', 'reset']) assert.ok(kinds.includes(k), `${k} in ${kinds}`);
  // The first attempt replays byte for byte.
  const again = path.join(tmp, 'school-replay');
  execFileSync(bin, ['run', 'scenarios/packbot_flat.toml', '--commands', path.join(first, 'commands.toml'),
    '--duration', String(JSON.parse(fs.readFileSync(path.join(first, 'summary.json'), 'utf8')).sim_time_s), '--out', again, '--no-plot'], { cwd: root, stdio: 'ignore' });
  assert.ok(fs.readFileSync(path.join(again, 'trajectory.csv')).equals(fs.readFileSync(path.join(first, 'trajectory.csv'))), 'attempt 1 does not replay byte for byte');
  // The review steps through the attempts.
  const view = start(['view', dir, '--port', '0']);
  const vctx = await browser();
  try {
    const page = await openReplay(vctx, `${await view.url}?attempt=1`);
    assert.equal(await page.evaluate(() => window.tracksim.attempt), 1);
    assert.deepEqual(await page.evaluate(() => window.tracksim.attempts), [1, 2]);
    assert.equal(await page.evaluate(() => document.querySelectorAll('#attempt option').length), 2);
    // The patch put in attempt 1 is drawn in its replay from the time it was put, not before.
    const put = JSON.parse(fs.readFileSync(path.join(first, 'scene.json'), 'utf8')).patches;
    assert.equal(put.length, 1);
    assert.equal(put[0].patch.friction, 0.15);
    await scrubTo(page, put[0].t_s / 2);
    assert.equal(await page.evaluate(() => window.tracksim.patchDrawn), 0);
    await scrubTo(page, put[0].t_s + 0.5 * (await page.evaluate(() => window.tracksim.replayEnd) - put[0].t_s));
    assert.equal(await page.evaluate(() => window.tracksim.patch?.friction), 0.15);
    assert.ok((await page.evaluate(() => window.tracksim.patchDrawn)) > 0);
  } finally {
    await vctx.close();
    view.child.kill();
  }
});

// The Python package (a learning environment's render_mode="human" page is served by the
// environment): the venv scripts/test-python.sh makes, or TRACKSIM_PYTHON.
const python = process.env.TRACKSIM_PYTHON || path.join(root, '.venv-ci/bin/python');
const noPython = fs.existsSync(python) ? false : `needs the Python package: run scripts/test-python.sh (it makes ${python}) or set TRACKSIM_PYTHON`;

test('a learning environment\'s human-mode page (issue 44): watch-only, no drive controls, no driver status, the belts shown and running', { skip: noPython }, async () => {
  const child = spawn(python, [path.join(here, 'human_env.py'), '150'], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let printed = '';
  const url = await new Promise((resolve, reject) => {
    child.stdout.on('data', (d) => {
      printed += d;
      const m = printed.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    });
    child.on('exit', (code) => reject(new Error(`human_env.py exited ${code}: ${printed}`)));
  });
  const ctx = await browser();
  try {
    const { page, errors } = await openDrive(ctx, url);
    // The server says the session is watch-only; the page watches.
    const session = await page.evaluate(async () => (await fetch('/session.json')).json());
    assert.equal(session.watch_only, true, JSON.stringify(session));
    assert.equal(session.token, null);
    assert.equal(await page.evaluate(() => window.tracksim.watchOnly), true);
    assert.equal(await page.evaluate(() => window.tracksim.role), 'watcher');
    assert.equal(await page.evaluate(() => window.tracksim.state.driver), null, 'no driver in a watch-only state');
    // No drive controls: the drive help and its End session button are not shown, the watch help is.
    const shown = (sel) => page.evaluate((s) => { const e = document.querySelector(s); return !!e && e.getClientRects().length > 0; }, sel);
    assert.equal(await shown('#help-drive'), false);
    assert.equal(await shown('#stop'), false);
    assert.equal(await shown('#help-watch'), true);
    // Drive keys do nothing (no control is sent: the server would refuse it with an error).
    await page.keyboard.down('ArrowUp');
    await page.waitForTimeout(500);
    await page.keyboard.up('ArrowUp');
    // The belts: a HUD line per track with its commanded speed (turning: they differ), and the
    // grousers drawn moving with the belts.
    const tracks = await page.evaluate(async () => (await (await fetch('/scene.json')).json()).vehicle.tracks.map((t) => t.name));
    assert.ok(tracks.length >= 2, JSON.stringify(tracks));
    const before = await page.evaluate(() => ({ t: window.tracksim.state.t, belt: window.tracksim.state.belt_position, g: window.tracksim.grouser(0) }));
    await page.waitForFunction((t) => window.tracksim.state.t > t + 1, before.t, { timeout: 30000 });
    await page.waitForTimeout(200); // a frame drawn from the newer state
    const after = await page.evaluate(() => ({ belt: window.tracksim.state.belt_position, speed: window.tracksim.state.belt_speed, g: window.tracksim.grouser(0) }));
    after.belt.forEach((b, i) => assert.ok(b > before.belt[i] + 0.1, `belt ${tracks[i]} runs: ${before.belt[i]} -> ${b}`));
    assert.ok(after.speed.every((v) => v > 0.05), JSON.stringify(after.speed));
    assert.notEqual(after.speed[0], after.speed[1], 'turning: the belts differ');
    assert.ok(before.g && after.g, 'grousers drawn');
    const moved = Math.hypot(...after.g.map((x, k) => x - before.g[k]));
    assert.ok(moved > 0.005, `the drawn grousers run with the belt: moved ${moved} m`);
    const hud = await page.evaluate(() => document.getElementById('hud').textContent);
    for (const n of tracks) assert.match(hud, new RegExp(`belt\\s+${n} -?[0-9.]+ m/s commanded, at -?[0-9.]+ m`), hud);
    assert.match(hud, /WATCHING a learning environment/, hud);
    // The speed and slip of an environment that records no samples come from its simulation.
    const speed = Number(hud.match(/speed\s+(-?[0-9.]+) m\/s forward/)?.[1]);
    assert.ok(speed > 0.05, `the robot's speed is shown: ${hud}`);
    const slip = await page.evaluate(() => window.tracksim.state.slip);
    assert.equal(slip.length, tracks.length, JSON.stringify(slip));
    assert.doesNotMatch(hud, /set speeds|DRIVING|another page drives/, hud);
    // Nothing on the page says a driver is missing, nor offers driving.
    const text = await page.evaluate(() => document.body.innerText);
    assert.doesNotMatch(text, /disconnected|End session|forward \/ back/i, text);
    assert.equal(await shown('#driver-banner'), false);
    await page.screenshot({ path: path.join(artifacts, 'human-watch.png') });
    assert.deepEqual([...errors, ...await page.evaluate(() => window.tracksim.errors)], []);
  } finally {
    await ctx.close();
    child.kill();
  }
});
