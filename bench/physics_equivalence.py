"""Is the training physics (``tracksim.TRAINING_PHYSICS``: 2 solver iterations instead of 4, or
another setting given with ``--physics``) the same physics on a learning task as the validated
default (``okada2020``, the file's iterations)? Success rates of fixed policies over the same held-out seeds, both
settings, with a two-proportion z-test per policy.

    python bench/physics_equivalence.py [--episodes 100] [--threads 2] [--tasks 2,3]
        [--physics '{"method": "okada2020_clustered"}']

Tasks: the steps task (``scenarios/random/packbot_flippers_step_random.toml``, PackBot 510 with
flippers, steps 0.12-0.24 m) and the step without flippers
(``scenarios/random/packbot_step_random.toml``, 0.06-0.14 m). Policies: forward at 0.3 m/s with
the flippers held at -30, 0, +30 deg (normalised -0.5, 0, +0.5 of +-60 deg) on the first; forward
at 0.3 m/s on the second. A single run's outcome near the limit of a climb flips with any change
of the arithmetic (the bundled stairs succeed or stall with 2, 3, 4 iterations by turns), so
"equal" is stated over seeds: equal success rates within sampling noise (|z| < 2), equal mean
time to success within its standard error.
"""
import argparse
import json
import math
import pathlib
import time

import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[1]
TASKS = [
    ("steps, flippers -30 deg", "random/packbot_flippers_step_random.toml", [0.6, 0.0, -0.5, -0.5]),
    ("steps, flippers 0 deg", "random/packbot_flippers_step_random.toml", [0.6, 0.0, 0.0, 0.0]),
    ("steps, flippers +30 deg", "random/packbot_flippers_step_random.toml", [0.6, 0.0, 0.5, 0.5]),
    ("step, no flippers", "random/packbot_step_random.toml", [0.6, 0.0]),
]


def episodes(file, action, physics, seeds, threads):
    """Outcome and time of one episode per seed with a constant action."""
    sc = tracksim.Scenario(str(ROOT / "scenarios" / file), **physics)
    env = tracksim.TracksimVectorEnv(sc, len(seeds), threads=threads)
    env.reset(seed=list(seeds))
    a = np.tile(np.array(action, np.float32), (len(seeds), 1))
    outcome, t_end = [""] * len(seeds), [0.0] * len(seeds)
    steps = 0
    while any(o == "" for o in outcome):
        _, _, term, trunc, info = env.step(a)
        steps += 1
        for i in np.flatnonzero(term | trunc):
            if outcome[i] == "":
                outcome[i] = info["outcome"][i]
                t_end[i] = steps * env.control_period_s
    return outcome, t_end


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--episodes", type=int, default=100)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--physics", default=None,
                    help="the setting compared with the validated one, as JSON Scenario "
                         "overrides (default tracksim.TRAINING_PHYSICS)")
    ap.add_argument("--tasks", default=None,
                    help="comma-separated row numbers of the task table to run (default all)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    other = json.loads(args.physics) if args.physics else tracksim.TRAINING_PHYSICS
    tasks = TASKS if args.tasks is None else [TASKS[int(i)] for i in args.tasks.split(",")]
    print(f"validated physics against {other}", flush=True)
    seeds = list(range(10000, 10000 + args.episodes))
    rows = []
    for name, file, action in tasks:
        res = {}
        for label, physics in (("validated", {}), ("training", other)):
            t0 = time.process_time()
            out, t = episodes(file, action, physics, seeds, args.threads)
            ok = [o == "success" for o in out]
            ts = [x for x, s in zip(t, ok) if s]
            res[label] = {"success": sum(ok) / len(ok), "n": len(ok),
                          "time_mean_s": float(np.mean(ts)) if ts else math.nan,
                          "time_se_s": float(np.std(ts) / math.sqrt(len(ts))) if ts else math.nan,
                          "cpu_s": time.process_time() - t0}
        p1, p2, n = res["validated"]["success"], res["training"]["success"], args.episodes
        p = (p1 + p2) / 2
        se = math.sqrt(max(p * (1 - p) * 2 / n, 1e-12))
        rows.append({"task": name, **{f"{k}_{l}": v for l in res for k, v in res[l].items()},
                     "z": (p2 - p1) / se})
    if args.json:
        print(json.dumps(rows))
        return
    print(f"{'task / policy':26} {'validated':>9} {'training':>9} {'z':>6} "
          f"{'t validated s':>14} {'t training s':>13} {'CPU ratio':>9}")
    for r in rows:
        print(f"{r['task']:26} {r['success_validated']:9.2f} {r['success_training']:9.2f} "
              f"{r['z']:6.2f} {r['time_mean_s_validated']:7.2f}+-{r['time_se_s_validated']:.2f} "
              f"{r['time_mean_s_training']:7.2f}+-{r['time_se_s_training']:.2f} "
              f"{r['cpu_s_validated'] / r['cpu_s_training']:9.2f}")


if __name__ == "__main__":
    main()
