"""Env steps per second per core of two builds of the Python package, interleaved (A B, B A,
...) in one run: `bench/env_steps.py` run by each interpreter (each a venv with one build).

    python bench/ab_env_steps.py PYTHON_A PYTHON_B PAIRS [--cases flat,stairs,quince]
                                 [--steps 60] [--envs 8] [--threads 1] [--config JSON]
                                 [--physics-a JSON] [--physics-b JSON]

`--physics-a`/`--physics-b` are Scenario overrides for that build's env_steps.py (e.g.
`--physics-b '{"solver_iterations": 2}'`, tracksim.TRAINING_PHYSICS) to compare a setting.

`--envs`, `--threads` and `--config` are env_steps.py's (environments per vector env, Rust
threads, the env config as JSON, e.g. `'{"control_period_s": 0.005}'` for short env steps).

Prints, per case, the median env steps/s (per CPU second, then `CASE@wall` per wall second) of
A and B, the ratio of medians (B / A) and the median of the per-pair ratios, with the 1-minute load average after each pair.
"""
import argparse
import json
import os
import statistics as st
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def once(python, cases, steps, physics, envs=8, threads=1, config=""):
    extra = (["--physics", physics] if physics else []) + (["--config", config] if config else [])
    r = subprocess.run([python, os.path.join(HERE, "env_steps.py"), "--cases", cases,
                        "--steps", str(steps), "--envs", str(envs), "--threads", str(threads),
                        "--json"] + extra,
                       check=True, capture_output=True, text=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("pairs", type=int)
    ap.add_argument("--cases", default="flat,stairs,quince")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--envs", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--config", default="")
    ap.add_argument("--physics-a", default="")
    ap.add_argument("--physics-b", default="")
    args = ap.parse_args()
    res = {"a": [], "b": []}
    loads = [os.getloadavg()[0]]
    for i in range(args.pairs):
        for who in (["a", "b"] if i % 2 == 0 else ["b", "a"]):
            py = args.a if who == "a" else args.b
            cfg = args.physics_a if who == "a" else args.physics_b
            res[who].append(once(py, args.cases, args.steps, cfg, args.envs, args.threads,
                                     args.config))
        loads.append(os.getloadavg()[0])
    print("load average (1 min) after each pair:", " ".join(f"{x:.2f}" for x in loads))
    print(f"{'case':8} {'A steps/s':>10} {'B steps/s':>10} {'B/A medians':>12} "
          f"{'median B/A per pair':>20} {'min..max':>12}")
    for c in [k for c in args.cases.split(",") for k in (c, f"{c}@wall")]:
        if c not in res["a"][0] or c not in res["b"][0]:
            continue  # an env_steps.py without wall-clock rates
        a = [r[c] for r in res["a"]]
        b = [r[c] for r in res["b"]]
        per = [y / x for x, y in zip(a, b)]
        print(f"{c:8} {st.median(a):10.1f} {st.median(b):10.1f} {st.median(b) / st.median(a):12.2f} "
              f"{st.median(per):20.2f} {min(per):5.2f}..{max(per):5.2f}")


if __name__ == "__main__":
    main()
