// Review of a finished run in `tracksim view` (issue 28): the trainee's inputs over time (a
// strip under the time bar, from controls.csv, or the belt commands of trajectory.csv), the
// run's events (stall episodes and the largest tilt from trajectory.csv, the outcome from
// summary.json, gates and faults from summary.json's course.events) as markers on the time bar.

import { StallDetector, tiltDeg } from '/hud.js';

const num = (x) => typeof x === 'number' && Number.isFinite(x);
/** Window of the forward speed's mean in the stall rule, s (as the live state's forward_mps). */
const STALL_MEAN_S = 0.1;

/** Events of a run, sorted by time: [{t_s, kind, detail}]. `traj` is a parsed CSV. */
export function computeEvents(traj, summary, trackNames) {
  const ev = [];
  const c = (n) => traj.col(n);
  const [it, ix, iy, iyaw, iroll, ipitch] = ['t_s', 'x_m', 'y_m', 'yaw_rad', 'roll_rad', 'pitch_rad'].map(c);
  const cmd = trackNames.map((n) => c(`belt_cmd_${n}_mps`)).filter((i) => i >= 0);
  // summary.json's events (run/events.rs: the stall rule the live HUD uses, the largest
  // tilt) when the run has them; else found here from trajectory.csv.
  const known = Array.isArray(summary?.events) ? summary.events : null;
  for (const e of known ?? []) {
    if (!num(e.t_s) || e.kind === 'outcome') continue;
    ev.push({ t_s: e.t_s, kind: e.kind === 'largest_tilt' ? 'tilt' : String(e.kind), detail: String(e.detail ?? ''), ...(num(e.t_end_s) ? { t_end_s: e.t_end_s } : {}) });
  }
  // Stall episodes: belts commanded, the robot not moving (its forward speed a mean over
  // STALL_MEAN_S, as the live state's), for a second or more.
  if (!known && cmd.length && ix >= 0 && iy >= 0 && iyaw >= 0) {
    const det = new StallDetector();
    let open = null, j = 0;
    for (const r of traj.rows) {
      while (j < traj.rows.length - 1 && traj.rows[j + 1][it] <= r[it] - STALL_MEAN_S + 1e-9) j++;
      const q = traj.rows[j], span = r[it] - q[it];
      const fwd = span > 0 ? ((r[ix] - q[ix]) * Math.cos(r[iyaw]) + (r[iy] - q[iy]) * Math.sin(r[iyaw])) / span : 0;
      const st = det.update(r[it], cmd.map((i) => r[i]), fwd);
      if (st && !open) { open = { t_s: det.since, kind: 'stall', detail: '' }; ev.push(open); }
      if (!st && open) { open.t_end_s = r[it]; open.detail = `stalled ${(r[it] - open.t_s).toFixed(1)} s`; open = null; }
    }
    if (open) {
      open.t_end_s = traj.rows[traj.rows.length - 1][it];
      open.detail = `stalled to the end (${(open.t_end_s - open.t_s).toFixed(1)} s)`;
    }
  }
  // The largest tilt.
  if (!known && iroll >= 0 && ipitch >= 0 && traj.rows.length) {
    let best = null;
    for (const r of traj.rows) { const a = tiltDeg(r[iroll], r[ipitch]); if (!best || a > best.a) best = { a, t: r[it] }; }
    ev.push({ t_s: best.t, kind: 'tilt', detail: `largest tilt ${best.a.toFixed(1)} deg` });
  }
  // The course's gates and faults.
  for (const e of summary?.course?.events ?? []) {
    const t = e.t_s ?? e.t;
    if (num(t)) ev.push({ t_s: t, kind: String(e.kind ?? 'event'), detail: String(e.detail ?? '') });
  }
  // The outcome.
  if (summary && num(summary.outcome_time_s) && summary.outcome) {
    ev.push({ t_s: summary.outcome_time_s, kind: 'outcome', detail: `${summary.outcome}: ${summary.outcome_reason ?? ''}` });
  }
  ev.sort((a, b) => a.t_s - b.t_s);
  return ev;
}

/** Marker colour of an event kind. */
export function eventColour(kind) {
  if (kind === 'stall') return '#f0a830';
  if (kind === 'tilt') return '#e060e0';
  if (kind === 'outcome') return '#ffffff';
  if (/fault|tip|reset|touch|penalty/.test(kind)) return '#e23b3b';
  if (/gate|lap|rep/.test(kind)) return '#40c0ff';
  return '#cccccc';
}

/** The next (dir +1) or previous (dir -1) event from time `t`; null at either end. */
export function jumpTarget(events, t, dir) {
  if (dir > 0) return events.find((e) => e.t_s > t + 0.05) ?? null;
  for (let i = events.length - 1; i >= 0; i--) if (events[i].t_s < t - 0.25) return events[i];
  return null;
}

/**
 * The inputs' series: from controls.csv (forward and yaw commands, flipper targets) or, without
 * it, the belt commands of trajectory.csv. Lanes: [{title, series:[{name, colour, t:[], v:[]}]}].
 */
export function inputSeries(controls, traj, trackNames) {
  const col = (csv, n) => csv.col(n);
  const take = (csv, i) => ({ t: csv.rows.map((r) => r[0]), v: csv.rows.map((r) => r[i]) });
  const lanes = [];
  if (controls && controls.rows.length) {
    const motion = [];
    const f = col(controls, 'forward_mps'), y = col(controls, 'yaw_rate_rad_s');
    if (f >= 0) motion.push({ name: 'forward m/s', colour: '#5ad35a', ...take(controls, f) });
    if (y >= 0) motion.push({ name: 'yaw rad/s', colour: '#5aa8ff', ...take(controls, y) });
    lanes.push({ title: 'drive', series: motion });
    const flips = controls.head.map((h, i) => [h, i]).filter(([h]) => /^flipper_.*_target_deg$/.test(h));
    const shades = ['#f0a830', '#f06830', '#d0d040', '#e0a0ff'];
    if (flips.length) {
      lanes.push({ title: 'flipper target deg', series: flips.map(([h, i], k) => ({ name: h.replace(/^flipper_|_target_deg$/g, ''), colour: shades[k % shades.length], ...take(controls, i) })) });
    }
    const src = col(controls, 'source') >= 0 ? 'source' : col(controls, 'input') >= 0 ? 'input' : null;
    if (src) lanes.source = src;
  } else {
    const shades = ['#5ad35a', '#5aa8ff', '#f0a830', '#e060e0'];
    const belts = trackNames.map((n, k) => [n, col(traj, `belt_cmd_${n}_mps`), k]).filter(([, i]) => i >= 0);
    lanes.push({ title: 'belt commands m/s', series: belts.map(([n, i, k]) => ({ name: n, colour: shades[k % shades.length], ...take(traj, i) })) });
  }
  return lanes.filter((l) => l.series.length);
}

/** Draws the lanes over [0, end] s with a cursor at `t`. Returns the number of drawn points. */
export function drawInputs(canvas, lanes, end, t) {
  const w = canvas.clientWidth || canvas.width, h = canvas.height;
  if (canvas.width !== w) canvas.width = w;
  const g = canvas.getContext('2d');
  g.clearRect(0, 0, w, h);
  g.fillStyle = 'rgba(10,12,14,0.6)'; g.fillRect(0, 0, w, h);
  if (!lanes.length) return 0;
  const lh = h / lanes.length;
  const X = (tt) => (end > 0 ? (tt / end) * w : 0);
  let drawn = 0;
  g.font = '10px ui-monospace, monospace';
  lanes.forEach((lane, li) => {
    const top = li * lh, mid = top + lh / 2;
    let m = 1e-9;
    for (const s of lane.series) for (const v of s.v) if (num(v)) m = Math.max(m, Math.abs(v));
    g.strokeStyle = '#555'; g.lineWidth = 1; g.beginPath(); g.moveTo(0, mid); g.lineTo(w, mid); g.stroke();
    const Y = (v) => mid - (v / m) * (lh / 2 - 6); // 6 px clear of the lane's edges
    let lx = 4;
    g.fillStyle = '#bbb'; g.fillText(`${lane.title} (±${m.toPrecision(2)})`, lx, top + 10); lx += g.measureText(`${lane.title} (±${m.toPrecision(2)})`).width + 10;
    for (const s of lane.series) {
      g.strokeStyle = s.colour; g.lineWidth = 1.5; g.beginPath();
      let prev = null;
      s.t.forEach((tt, i) => {
        const v = num(s.v[i]) ? s.v[i] : 0;
        const x = X(tt), y = Y(v);
        if (prev === null) g.moveTo(x, y); else { g.lineTo(x, prev); g.lineTo(x, y); } // steps: held until the next sample
        prev = y; drawn++;
      });
      g.stroke();
      g.fillStyle = s.colour; g.fillText(s.name, lx, top + 10); lx += g.measureText(s.name).width + 8;
    }
  });
  if (num(t)) { g.fillStyle = '#fff'; g.fillRect(Math.round(X(t)), 0, 1, h); }
  return drawn;
}

/** A fault's kind from an event (its `fault` key; older runs: from its words). */
function faultKind(e) {
  if (typeof e.fault === 'string') return e.fault;
  const d = String(e.detail ?? '');
  if (/^reset/.test(d)) return 'reset';
  if (/^tip-over/.test(d)) return 'tip_over';
  if (/^touched/.test(d)) return 'touch';
  return null;
}

/**
 * The course's score at replay time `t` s, from summary.json's `course` (run/course.rs
 * `CourseScore`) and its timed events: gates passed, repetitions and their times, faults by
 * kind, penalty and score so far, as the live page showed it then. At or after the run's
 * last sample it is the final score itself. null without a course. An attempt that began
 * with a reset (its first event) counts its time from that event's time: 0 s, or the reset's
 * world time for one robot reset in a world that went on (run/course.rs `reset_at`).
 */
export function courseAt(course, t, end = Infinity) {
  if (!course || typeof course !== 'object') return null;
  if (num(end) && t >= end - 1e-9) return course;
  const total = num(course.gates_total) ? course.gates_total : null;
  const required = course.repetitions_required;
  const first = (course.events ?? [])[0];
  const start = first && first.kind === 'fault' && faultKind(first) === 'reset' && num(first.t_s) ? first.t_s : 0;
  let next = 0, passed = 0, lastEnd = start, status = 'running', penalty = 0, penaltyKnown = true;
  const reps = [];
  const faults = { reset: 0, tip_over: 0, touch: 0 };
  for (const e of course.events ?? []) {
    if (!num(e.t_s) || e.t_s > t + 1e-9) continue;
    if (e.kind === 'gate') {
      passed++;
      next = total ? (next + 1) % total : next + 1;
    } else if (e.kind === 'repetition') {
      reps.push(e.t_s - lastEnd);
      lastEnd = e.t_s;
    } else if (e.kind === 'fault') {
      const k = faultKind(e);
      if (k) faults[k] = (faults[k] ?? 0) + 1;
      if (num(e.penalty_s)) penalty += e.penalty_s; else penaltyKnown = false;
    } else if (e.kind === 'finished') {
      status = num(required) && reps.length >= required ? 'completed' : 'time_limit';
    }
  }
  const elapsed = Math.min(t - start, num(course.elapsed_s) ? course.elapsed_s : t - start);
  const time = status === 'completed' ? lastEnd - start : elapsed;
  const pen = penaltyKnown ? penalty : null;
  const nFaults = faults.reset + faults.tip_over + faults.touch;
  return {
    name: course.name,
    next_gate: next,
    gates_passed: passed,
    gates_total: total,
    repetition: num(required) ? Math.min(reps.length + 1, required) : reps.length + 1,
    repetitions_done: reps.length,
    repetitions_required: required,
    rep_times_s: reps,
    elapsed_s: elapsed,
    ...(num(course.time_limit_s) ? { time_limit_s: course.time_limit_s } : {}),
    faults,
    penalty_s: pen,
    finished: status !== 'running',
    status,
    score: { repetitions: reps.length, time_s: time, faults: nFaults, penalty_s: pen, score_s: pen === null ? null : time + pen },
    events: (course.events ?? []).filter((e) => num(e.t_s) && e.t_s <= t + 1e-9),
  };
}

/**
 * The low-friction patch on the ground at replay time `t` s (issue 43), from scene.json's
 * `patches` (output/replay.rs `ScenePatch`: every change of the run's patch in order, each
 * `{t_s, patch}` with `patch` `{centre_m, size_m, friction}` or null once removed): the patch
 * of the last change at or before `t`, null before the first or without any.
 */
export function patchAt(patches, t) {
  let now = null;
  for (const c of Array.isArray(patches) ? patches : []) {
    if (!num(c?.t_s) || c.t_s > t + 1e-9) break;
    now = c.patch ?? null;
  }
  return now;
}
