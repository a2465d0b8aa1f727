"""Issue 16.4: CPU time of two tracksim binaries, interleaved (A B, B A, ...), 10 s runs.

Usage: python3 bench/ab_cpu_time.py BINARY_A BINARY_B PAIRS
Each run is `BINARY run SCENARIO --method M --duration 10 --quiet --no-plot`; its CPU time
(user + system, getrusage of the child, world building included) is recorded. Prints, per
case, the medians, the ratio of medians (A / B) and the median of the per-pair ratios, with
the 1-minute load average after each pair. CPU time is less disturbed than wall time by other
processes on a shared machine.
"""
import os
import resource
import statistics as st
import subprocess
import sys
import tempfile

A, B, N = sys.argv[1], sys.argv[2], int(sys.argv[3])
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = tempfile.mkdtemp()
CASES = [
    ("packbot_flat", "okada2020"),
    ("packbot_flat", "okada2020_no_grousers"),
    ("packbot_flat", "wheels4"),
    ("quince_flat", "okada2020"),
]


def cpu_seconds(binary, scenario, method):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(
        [binary, "run", os.path.join(ROOT, "scenarios", scenario + ".toml"), "--method", method,
         "--duration", "10", "--quiet", "--no-plot", "--out", OUT],
        check=True,
    )
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


res = {c: {"a": [], "b": []} for c in CASES}
loads = [os.getloadavg()[0]]
for i in range(N):
    order = ["a", "b"] if i % 2 == 0 else ["b", "a"]
    for sc, m in CASES:
        for who in order:
            res[(sc, m)][who].append(cpu_seconds(A if who == "a" else B, sc, m))
    loads.append(os.getloadavg()[0])
print("load average (1 min) after each pair:", " ".join(f"{x:.2f}" for x in loads))
print(f"{'scenario':14} {'method':22} {'A CPU s':>8} {'B CPU s':>8} {'A/B of medians':>15} "
      f"{'median A/B per pair':>20} {'min..max':>13}")
for (sc, m), v in res.items():
    r = [a / b for a, b in zip(v["a"], v["b"])]
    print(f"{sc:14} {m:22} {st.median(v['a']):8.3f} {st.median(v['b']):8.3f} "
          f"{st.median(v['a']) / st.median(v['b']):15.4f} {st.median(r):20.4f} "
          f"{min(r):.3f}..{max(r):.3f}")
