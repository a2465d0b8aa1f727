// Real time with two drivers (issue 43, BENCHMARKS.md): a paced `tracksim drive` session of a
// two-robot file (`scenarios/team/race_step.toml`, a seat per robot), each seat driven at once
// for the whole session, either by a program's WebSocket (`ws`: the trainees' browsers on
// their own machines, the simulation machine serving states) or by a page of the 3-D view each
// in headless Chromium on the same machine (`pages`: software WebGL, 960 x 540, the worst
// case: two renderers and the simulation share its cores). Reported per run from the robots'
// summary.json: the paced real-time factor of the whole session (simulated time over wall
// time) and the compute one (over stepping time alone: the headroom); from a reading of the
// simulated clock every 250 ms by the first driver: the paced RTF of each wall second (median,
// worst) and the largest lag of the clock behind the wall.
// Usage: TRACKSIM_BIN=... node --experimental-websocket bench-team-held.mjs [DURATION_S] [REPEATS] [ws|pages|both]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launchChromium } from './chromium.mjs';

const here = path.dirname(new URL(import.meta.url).pathname);
const root = path.resolve(here, '../..');
const bin = process.env.TRACKSIM_BIN || path.join(root, 'target/release/tracksim');
const duration = Number(process.argv[2] || 20);
const repeats = Number(process.argv[3] || 2);
const modes = (process.argv[4] || 'both') === 'both' ? ['ws', 'pages'] : [process.argv[4]];
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'tracksim-team-held-'));
const file = 'scenarios/team/race_step.toml';
const seats = [['red', 0.35], ['blue', 0.3]];

function start(out) {
  const child = spawn(bin, ['drive', file, '--port', '0', '--duration', String(duration), '--wait-for-page', '--no-plot',
    '--trainee', 'red=Trainee A', '--trainee', 'blue=Trainee B', '--out', out], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let text = '';
  const ready = new Promise((resolve) => child.stdout.on('data', (d) => {
    text += d;
    const u = text.match(/http:\/\/127\.0\.0\.1:\d+\//), t = text.match(/session token ([0-9a-f]{32})/);
    if (u && t) resolve({ url: u[0], token: t[1] });
  }));
  const exited = new Promise((resolve) => child.on('exit', resolve));
  return { ready, exited };
}

/** Paced RTF per wall second and the largest lag, from [{wall, t}] readings. */
function pacing(ticks) {
  const per = [];
  let lag = 0;
  for (let i = 0, j = 0; i < ticks.length; i++) {
    while (j + 1 < i && ticks[i].wall - ticks[j + 1].wall >= 0.99) j++;
    if (ticks[i].wall - ticks[j].wall >= 0.99) per.push((ticks[i].t - ticks[j].t) / (ticks[i].wall - ticks[j].wall));
    lag = Math.max(lag, ticks[i].wall - ticks[0].wall - (ticks[i].t - ticks[0].t));
  }
  per.sort((a, b) => a - b);
  return { median: per[Math.floor(per.length / 2)] ?? NaN, worst: per[0] ?? NaN, lag };
}

async function byWebSocket({ url, token }) {
  const ticks = [];
  const base = url.replace('http://', 'ws://');
  const sockets = seats.map(([robot, v], k) => new Promise((resolve) => {
    const ws = new WebSocket(`${base}ws?session=${token}&robot=${robot}`);
    ws.onmessage = (m) => {
      const s = JSON.parse(m.data);
      if (s.type !== 'state') return;
      if (!ws.sent) { ws.send(JSON.stringify({ type: 'control', forward_mps: v, yaw_rate_rad_s: 0 })); ws.sent = true; }
      if (k === 0) {
        const wall = performance.now() / 1000;
        if (!ticks.length || wall - ticks[ticks.length - 1].wall >= 0.25) ticks.push({ wall, t: s.t });
      }
    };
    ws.onclose = resolve;
    ws.onerror = resolve;
  }));
  await Promise.all(sockets);
  return ticks;
}

async function byPages({ url }) {
  const ctx = await launchChromium(tmp, { width: 960, height: 540 });
  try {
    const pages = [];
    for (const [robot] of seats) {
      const page = await ctx.newPage();
      await page.goto(`${url}?robot=${robot}`);
      await page.waitForFunction(() => window.tracksim?.state && window.tracksim.role === 'driver', null, { timeout: 60000 });
      pages.push(page);
    }
    for (const page of pages) {
      await page.evaluate(() => {
        window.dispatchEvent(new KeyboardEvent('keydown', { key: 'ArrowUp' }));
        window.__ticks = [];
        setInterval(() => { const st = window.tracksim.state; if (st) window.__ticks.push({ wall: performance.now() / 1000, t: st.t, frames: window.tracksim.frames }); }, 250);
      });
    }
    let ticks = [], frames = 0;
    while (true) {
      try {
        ticks = await pages[0].evaluate(() => window.__ticks);
        frames = await pages[0].evaluate(() => window.tracksim.frames);
      } catch { break; }
      if (ticks.length && ticks[ticks.length - 1].t >= duration - 0.02) break;
      await new Promise((r) => setTimeout(r, 500));
    }
    ticks.frames = frames;
    return ticks;
  } finally {
    await ctx.close().catch(() => {});
  }
}

const rows = [];
for (let i = 0; i < repeats; i++) {
  for (const mode of modes) {
    const out = path.join(tmp, `${mode}-${i}`);
    const load = fs.readFileSync('/proc/loadavg', 'utf8').split(' ')[0];
    const s = start(out);
    const ready = await s.ready;
    const ticks = mode === 'ws' ? await byWebSocket(ready) : await byPages(ready);
    await s.exited;
    const sm = JSON.parse(fs.readFileSync(path.join(out, 'red', 'summary.json'), 'utf8'));
    const team = JSON.parse(fs.readFileSync(path.join(out, 'team.json'), 'utf8'));
    const p = pacing(ticks);
    const row = {
      mode, run: i, load_before: Number(load), sim_s: sm.sim_time_s,
      paced_rtf: sm.paced_real_time_factor, compute_rtf: sm.real_time_factor,
      per_second_median: p.median, per_second_worst: p.worst, largest_lag_s: p.lag,
      frames_per_s: ticks.frames ? ticks.frames / duration : null,
      trainees: team.robots.map((r) => `${r.name}=${r.trainee}`).join(' '),
    };
    rows.push(row);
    console.log(JSON.stringify(row));
  }
}
console.log('\n| drivers | run | load avg before | sim s | whole session paced RTF | compute RTF | paced RTF per wall second median / worst | largest lag s | page frames/s |');
console.log('|---|---:|---:|---:|---:|---:|---|---:|---:|');
const f = (x, d = 3) => (Number.isFinite(x) ? x.toFixed(d) : '-');
for (const r of rows) console.log(`| ${r.mode} | ${r.run} | ${f(r.load_before, 2)} | ${f(r.sim_s, 2)} | ${f(r.paced_rtf)} | ${f(r.compute_rtf, 2)} | ${f(r.per_second_median)} / ${f(r.per_second_worst)} | ${f(r.largest_lag_s, 2)} | ${f(r.frames_per_s, 1)} |`);
