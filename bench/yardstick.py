"""The fixed yardstick of issue 29.5: MuJoCo's 4-wheel PackBot (`bench/mujoco/bench.py`'s
`mj_wheels4`, 10 s on flat ground at 0.3 m/s), its real-time factor in CPU time of this process,
for dividing a tracksim env-step rate measured in the same window:
yardstick ratio = env steps/s x 0.05 s / MuJoCo RTF (one core each).

    bench/mujoco/.venv/bin/python bench/yardstick.py [--repeat 3]
"""
import argparse
import json
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "mujoco"))
import bench  # noqa: E402  (bench/mujoco/bench.py: the models)
import mujoco  # noqa: E402


def rtf(duration=10.0):
    m, d, r = bench.build("mj_wheels4")
    bench.drive(m, d, r, bench.SPEED)
    steps = int(round(duration / bench.DT))
    t0 = time.process_time()
    mujoco.mj_step(m, d, nstep=steps)
    return d.time / (time.process_time() - t0)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    print(json.dumps({"mj_wheels4_rtf": statistics.median(rtf() for _ in range(a.repeat))}))
