"""Env steps per second per core of two builds of the Python package, interleaved (A B, B A,
...) in one run: `bench/env_steps.py` run by each interpreter (each a venv with one build).

    python bench/ab_env_steps.py PYTHON_A PYTHON_B PAIRS [--cases flat,stairs,quince]
                                 [--steps 60] [--args-a "..."] [--args-b "..."]

`--args-a`/`--args-b` are passed to that build's env_steps.py (e.g. `--args-b '--physics
{"method": "okada2020_clustered", "solver_iterations": 2}'` to compare a physics setting).

Prints, per case, the median env steps/s of A and B, the ratio of medians (B / A) and the
median of the per-pair ratios, with the 1-minute load average after each pair.
"""
import argparse
import json
import os
import shlex
import statistics as st
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def once(python, cases, steps, extra):
    r = subprocess.run([python, os.path.join(HERE, "env_steps.py"), "--cases", cases,
                        "--steps", str(steps), "--json"] + shlex.split(extra),
                       check=True, capture_output=True, text=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("pairs", type=int)
    ap.add_argument("--cases", default="flat,stairs,quince")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--args-a", default="")
    ap.add_argument("--args-b", default="")
    args = ap.parse_args()
    res = {"a": [], "b": []}
    loads = [os.getloadavg()[0]]
    for i in range(args.pairs):
        for who in (["a", "b"] if i % 2 == 0 else ["b", "a"]):
            py = args.a if who == "a" else args.b
            cfg = args.args_a if who == "a" else args.args_b
            res[who].append(once(py, args.cases, args.steps, cfg))
        loads.append(os.getloadavg()[0])
    print("load average (1 min) after each pair:", " ".join(f"{x:.2f}" for x in loads))
    print(f"{'case':8} {'A steps/s':>10} {'B steps/s':>10} {'B/A medians':>12} "
          f"{'median B/A per pair':>20} {'min..max':>12}")
    for c in args.cases.split(","):
        a = [r[c] for r in res["a"]]
        b = [r[c] for r in res["b"]]
        per = [y / x for x, y in zip(a, b)]
        print(f"{c:8} {st.median(a):10.1f} {st.median(b):10.1f} {st.median(b) / st.median(a):12.2f} "
              f"{st.median(per):20.2f} {min(per):5.2f}..{max(per):5.2f}")


if __name__ == "__main__":
    main()
