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
import { chromium } from 'playwright-core';

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
  return chromium.launchPersistentContext(fs.mkdtempSync(path.join(tmp, 'profile-')), {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    viewport: { width: 1000, height: 640 },
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  });
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
    await page.keyboard.press('v');
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
