"""The accuracy frontier (issue 58): `tracksim validate --accuracy` at each solver setting, and
the CPU time per simulated second of the Table II case (packbot_flat, 10 s) at that setting,
timed in interleaved rounds (setting A, B, C, ..., then again) with the median of the rounds.

    python3 bench/accuracy_frontier.py --tracksim target/release/tracksim --out bench_out/frontier \
        --settings 1:4 0.5:4 1:8 2:8 4:8 --rounds 3

A setting is `DT_MS:ITERATIONS` (stabilization passes: each file's, 2). Prints a markdown table:
the setting, CPU s per simulated s (median, and the ratio to the first setting), the rows that
pass, and the rows that fail by name. Writes frontier.md and frontier.json into --out, and each
setting's full report (report.md, JSON) under --out/<setting>/.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys


def cpu_of(cmd):
    """Runs cmd; returns the child's user+system CPU seconds."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tracksim", required=True)
    ap.add_argument("--root", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--out", required=True)
    ap.add_argument("--settings", nargs="+", default=["1:4", "0.5:4", "1:8", "2:8", "4:8"])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--skip-suite", action="store_true", help="time only")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    flat = os.path.join(a.root, "scenarios", "packbot_flat.toml")
    settings = []
    for s in a.settings:
        dt_ms, it = s.split(":")
        settings.append((s, float(dt_ms) / 1e3, int(it)))

    cpu = {s: [] for s, _, _ in settings}
    for _ in range(a.rounds):
        for s, dt, it in settings:
            cmd = [a.tracksim, "run", flat, "--out", os.path.join(a.out, "flat_" + s.replace(":", "_")),
                   "--no-plot", "--quiet", "--dt", repr(dt), "--solver-iterations", str(it)]
            cpu[s].append(cpu_of(cmd) / 10.0)

    results = []
    for s, dt, it in settings:
        row = {"setting": s, "dt_s": dt, "iterations": it, "cpu_s_per_sim_s": cpu[s],
               "median_cpu_s_per_sim_s": statistics.median(cpu[s])}
        if not a.skip_suite:
            d = os.path.join(a.out, s.replace(":", "_"))
            p = subprocess.run([a.tracksim, "validate", "--accuracy", "--json", "--out", d,
                                "--dt", repr(dt), "--iterations", str(it)],
                               capture_output=True, text=True)
            rep = json.loads(p.stdout)
            rows = [(c["name"], c["passed"], c["measured"]) for c in rep["cases"]]
            rows += [("Table IV " + t["name"], t["passed"], "")
                     for t in rep["table_iv"]]
            row["passed"] = [n for n, ok, _ in rows if ok]
            row["failed"] = [(n, m) for n, ok, m in rows if not ok]
        results.append(row)
        print(s, row["median_cpu_s_per_sim_s"], len(row.get("failed", [])), file=sys.stderr)

    base = results[0]["median_cpu_s_per_sim_s"]
    lines = ["| setting (dt ms : iterations) | CPU s per sim s, Table II (median of %d) | x first | rows passed | rows failed |" % a.rounds,
             "|---|---:|---:|---:|---|"]
    for r in results:
        m = r["median_cpu_s_per_sim_s"]
        failed = "; ".join(f"{n}" for n, _ in r.get("failed", [])) or "none"
        npass = len(r.get("passed", []))
        ntot = npass + len(r.get("failed", []))
        lines.append(f"| {r['setting']} | {m:.4f} | {m / base:.2f} | {npass}/{ntot} | {failed} |")
    md = "\n".join(lines) + "\n"
    print(md)
    with open(os.path.join(a.out, "frontier.md"), "w") as f:
        f.write(md)
    with open(os.path.join(a.out, "frontier.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
