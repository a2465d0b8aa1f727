"""Success rate of every task's scripted baseline (tracksim.baselines) over held-out seeds, with
the native vector env (one episode per environment, all stepped together on Rust threads).

    python python/examples/baselines.py --episodes 50 --seed 10000 --threads 2

Prints, per task: the success rate, how the failures ended (timeout, tipped over, left the
terrain), the mean time to success, and the wall time; ``--json`` prints one JSON line per
task. ``--tasks`` picks some ids (or their short names: ``Flat``, ``StairsUp``, ...).
"""

import argparse
import collections
import json
import time

import numpy as np

import tracksim
from tracksim.baselines import baseline
from tracksim.tasks import TASKS, make_vector


def failure_kind(reason: str) -> str:
    """A failure's reason in one word."""
    for key, kind in (("timeout", "timeout"), ("tipped", "tipped"), ("left the terrain", "off"),
                      ("unstable", "unstable")):
        if key in reason:
            return kind
    return "other"


def evaluate(task_id, episodes, seed, threads):
    """Runs ``episodes`` episodes of ``task_id`` (seeds ``seed``...) under its baseline; returns
    a dict of the results."""
    t0 = time.time()
    env = make_vector(task_id, episodes, threads=threads)
    policy = baseline(task_id)
    obs, _ = env.reset(seed=list(range(seed, seed + episodes)))
    outcome, reason, t_end = [""] * episodes, [""] * episodes, np.zeros(episodes)
    steps = 0
    while any(o == "" for o in outcome):
        obs, _, term, trunc, info = env.step(policy(obs))
        steps += 1
        for i in np.flatnonzero(term | trunc):
            if outcome[i] == "":
                outcome[i], reason[i] = info["outcome"][i], info["reason"][i]
                t_end[i] = steps * env.control_period_s
    ok = np.array([o == "success" for o in outcome])
    kinds = collections.Counter(failure_kind(r) for o, r in zip(outcome, reason)
                                if o != "success")
    return {"task": task_id, "episodes": episodes, "first_seed": seed,
            "success_rate": float(ok.mean()),
            "failures": dict(sorted(kinds.items())),
            "mean_success_time_s": float(t_end[ok].mean()) if ok.any() else None,
            "env_steps": steps * episodes, "wall_s": round(time.time() - t0, 1)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--episodes", type=int, default=50)
    ap.add_argument("--seed", type=int, default=10000, help="first held-out seed")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--tasks", nargs="*", default=None,
                    help="ids or short names (Flat, Battens, ...); default: all")
    ap.add_argument("--json", action="store_true", help="one JSON line per task")
    args = ap.parse_args()
    ids = [t.id for t in TASKS]
    if args.tasks:
        wanted = []
        for name in args.tasks:
            match = [i for i in ids if i == name or i == f"tracksim/PackBot{name}-v0"]
            if not match:
                ap.error(f"--tasks: no task {name!r}; the tasks are {', '.join(ids)}")
            wanted += match
        ids = wanted
    t0 = time.time()
    if not args.json:
        print(f"tracksim {tracksim.__version__}: {args.episodes} episodes per task from seed "
              f"{args.seed}, {args.threads} threads")
    for task_id in ids:
        r = evaluate(task_id, args.episodes, args.seed, args.threads)
        if args.json:
            print(json.dumps(r), flush=True)
        else:
            t = r["mean_success_time_s"]
            print(f"{task_id:32s} success {r['success_rate']:.2f}  failures {r['failures']}  "
                  f"mean time to success {'-' if t is None else f'{t:.1f} s'}  "
                  f"({r['env_steps']} env-steps, {r['wall_s']} s)", flush=True)
    if not args.json:
        print(f"total wall time {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
