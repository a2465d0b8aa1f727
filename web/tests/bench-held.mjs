// Real time held (issue 28.7, BENCHMARKS.md): a paced `tracksim drive` session driven from the
// 3-D page in headless Chromium (software WebGL) while a `nice -n 19` busy loop takes a core,
// on the bundled stairs with flippers and on Quince at its step. The page drives as a trainee
// would (forward held, the flippers set as the scenario's own commands set them); every wall
// second the test reads the page's latest state. Reported per run: the paced RTF of each wall
// second (min, median), the largest lag of the simulated clock behind the wall clock, the
// compute RTF (simulated time over stepping time alone: the headroom), the frames the page drew.
// The clock is read by a watcher connection in a Web Worker of the page (not delayed by the
// page's own rendering).
// Runs are interleaved: without load, with load, without, with, ...
// Usage: TRACKSIM_BIN=... node bench-held.mjs [DURATION_S] [REPEATS]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launchChromium } from './chromium.mjs';

const here = path.dirname(new URL(import.meta.url).pathname);
const root = path.resolve(here, '../..');
const bin = process.env.TRACKSIM_BIN || path.join(root, 'target/release/tracksim');
const duration = Number(process.argv[2] || 30);
const repeats = Number(process.argv[3] || 2);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'tracksim-held-'));

// What the page does: keys held, and flipper key presses at simulated times.
const cases = [
  { file: 'scenarios/packbot_stairs.toml', hold: 'ArrowUp', presses: [[0, 'r', 7], [6, 'f', 3]] }, // 35 deg, then 20 deg
  { file: 'scenarios/quince_step_240.toml', hold: 'ArrowUp', presses: [[0, 'r', 9]] }, // front pair 45 deg
];

async function one(c, load, i) {
  const out = path.join(tmp, `${path.basename(c.file, '.toml')}-${load ? 'load' : 'quiet'}-${i}`);
  const busy = load ? spawn('nice', ['-n', '19', 'sh', '-c', 'while :; do :; done'], { stdio: 'ignore' }) : null;
  const child = spawn(bin, ['drive', c.file, '--port', '0', '--duration', String(duration), '--wait-for-page',
    '--no-plot', '--out', out], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let text = '';
  const url = new Promise((resolve) => child.stdout.on('data', (d) => {
    text += d;
    const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
    if (m) resolve(m[0]);
  }));
  const exited = new Promise((resolve) => child.on('exit', resolve));
  const ctx = await launchChromium(tmp, { width: 1280, height: 720 });
  const page = await ctx.newPage();
  await page.goto(await url);
  await page.waitForFunction(() => window.tracksim?.state, null, { timeout: 60000 });
  // In the page: the key held, the flipper presses at their simulated times, and a reading
  // of (wall time, simulated time, frames drawn) every 250 ms.
  await page.evaluate(({ hold, presses }) => {
    const key = (type, k) => window.dispatchEvent(new KeyboardEvent(type, { key: k }));
    key('keydown', hold);
    const pending = presses.map((p) => [...p]);
    window.__ticks = [];
    setInterval(() => {
      const st = window.tracksim.state;
      if (!st) return;
      window.__ticks.push({ wall: performance.now() / 1000, t: st.t, frames: window.tracksim.frames });
      for (const p of pending) for (; p[2] > 0 && st.t >= p[0]; p[2]--) key('keydown', p[1]);
    }, 250);
  }, { hold: c.hold, presses: c.presses });
  // A watcher connection in a Web Worker (its own thread: not delayed by the page's software
  // rendering) timestamps every state it receives: the simulation's clock against the wall.
  await page.evaluate(() => {
    const src = `const ticks = []; const ws = new WebSocket('ws://${location.host}/ws');
      ws.onmessage = (ev) => { const m = JSON.parse(ev.data); if (m.type === 'state') ticks.push([performance.now() / 1000, m.t]); };
      onmessage = () => postMessage(ticks);`;
    window.__watcher = new Worker(URL.createObjectURL(new Blob([src], { type: 'text/javascript' })));
  });
  await exited;
  const ticks = await page.evaluate(() => window.__ticks);
  const watched = await page.evaluate(() => new Promise((resolve) => {
    window.__watcher.onmessage = (e) => resolve(e.data);
    window.__watcher.postMessage('ticks');
  }));
  await ctx.close();
  if (busy) busy.kill();
  const s = JSON.parse(fs.readFileSync(path.join(out, 'summary.json'), 'utf8'));
  // Paced RTF of each wall second, and the lag of the simulated clock behind the wall clock
  // since the first state (what a trainee feels as the robot falling behind), from the
  // watcher's timestamps.
  const rtfs = [];
  let lag = 0;
  for (let k = 0, j = 0; k < watched.length; k++) {
    const [w, t] = watched[k];
    while (j < k && w - watched[j + 1][0] >= 1) j++;
    if (w - watched[j][0] >= 1) rtfs.push((t - watched[j][1]) / (w - watched[j][0]));
    lag = Math.max(lag, (w - watched[0][0]) - (t - watched[0][1]));
  }
  const fps = ticks.length > 1 ? (ticks.at(-1).frames - ticks[0].frames) / (ticks.at(-1).wall - ticks[0].wall) : 0;
  return { file: c.file, load, rtfs, lag, compute: s.real_time_factor, paced: s.paced_real_time_factor, fps, x: s.final_pose.x, z: s.final_pose.z };
}

const med = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const rows = [];
for (let i = 0; i < repeats; i++) for (const c of cases) for (const load of [false, true]) {
  const r = await one(c, load, i);
  rows.push(r);
  console.log(`${path.basename(r.file)} ${load ? 'load ' : 'quiet'} paced RTF per second min ${Math.min(...r.rtfs).toFixed(3)} median ${med(r.rtfs).toFixed(3)}, ` +
    `largest lag ${r.lag.toFixed(3)} s, whole session paced ${r.paced.toFixed(3)}, compute RTF ${r.compute.toFixed(2)}, page ${r.fps.toFixed(1)} frames/s, ` +
    `final x ${r.x.toFixed(2)} z ${r.z.toFixed(2)} m`);
}
for (const c of cases) for (const load of [false, true]) {
  const xs = rows.filter((r) => r.file === c.file && r.load === load);
  console.log(`median ${path.basename(c.file)} ${load ? 'with a nice-d core of load' : 'quiet                     '}: ` +
    `compute RTF ${med(xs.map((r) => r.compute)).toFixed(2)}, worst second ${Math.min(...xs.flatMap((r) => r.rtfs)).toFixed(3)}, ` +
    `largest lag ${Math.max(...xs.map((r) => r.lag)).toFixed(3)} s, page ${med(xs.map((r) => r.fps)).toFixed(1)} frames/s`);
}
