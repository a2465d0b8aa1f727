// Compute real-time factor of `tracksim drive` with and without a connected 3-D viewer
// (issue 12, BENCHMARKS.md). Each run drives scenarios/packbot_flat.toml for 10 s simulated
// with the robot at rest (no operator input); `--speed` sets the pacing. With a viewer the
// session starts when the page connects (`--wait-for-page`), so it watches the whole run. Runs are interleaved
// (none, viewer, none, viewer, ...); prints summary.json's real_time_factor (stepping alone) and
// paced_real_time_factor for each.
// Usage: TRACKSIM_BIN=... node bench-viewer.mjs [SPEED] [REPEATS]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launchChromium } from './chromium.mjs';

const here = path.dirname(new URL(import.meta.url).pathname);
const root = path.resolve(here, '../..');
const bin = process.env.TRACKSIM_BIN || path.join(root, 'target/release/tracksim');
const speed = process.argv[2] || '1';
const repeats = Number(process.argv[3] || 3);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'tracksim-bench-'));

async function one(viewer, i) {
  const out = path.join(tmp, `${viewer ? 'viewer' : 'none'}-${i}`);
  const child = spawn(bin, ['drive', 'scenarios/packbot_flat.toml', '--port', '0', '--duration', '10',
    '--speed', speed, '--no-plot', '--out', out, ...(viewer ? ['--wait-for-page'] : [])], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  let text = '';
  const url = new Promise((resolve) => child.stdout.on('data', (d) => {
    text += d;
    const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
    if (m) resolve(m[0]);
  }));
  const exited = new Promise((resolve) => child.on('exit', resolve));
  let ctx = null;
  let page = null;
  if (viewer) {
    ctx = await launchChromium(tmp);
    page = await ctx.newPage();
    await page.goto(await url);
  }
  await exited;
  const { frames, states } = page ? await page.evaluate(() => window.tracksim) : { frames: 0, states: 0 };
  if (ctx) await ctx.close();
  const s = JSON.parse(fs.readFileSync(path.join(out, 'summary.json'), 'utf8'));
  return { viewer, rtf: s.real_time_factor, paced: s.paced_real_time_factor, frames, states, wall: s.elapsed_time_s };
}

const rows = [];
for (let i = 0; i < repeats; i++) for (const v of [false, true]) rows.push(await one(v, i));
for (const r of rows) console.log(`${r.viewer ? 'viewer' : 'none  '} compute RTF ${r.rtf.toFixed(2)} paced ${r.paced.toFixed(2)} frames drawn ${r.frames}, states received ${r.states} (${(r.states / r.wall).toFixed(1)} per wall s)`);
const med = (xs) => xs.sort((a, b) => a - b)[Math.floor(xs.length / 2)];
for (const v of [false, true]) {
  const xs = rows.filter((r) => r.viewer === v);
  console.log(`median ${v ? 'with viewer   ' : 'without viewer'}: compute RTF ${med(xs.map((r) => r.rtf)).toFixed(2)}, paced ${med(xs.map((r) => r.paced)).toFixed(2)}`);
}
