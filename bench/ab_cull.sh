#!/usr/bin/env bash
# Issue 44: what the cull of speculative contacts saves, same binary, interleaved. For each
# bundled scenario named (relative to scenarios/, without .toml) that turns
# `cull_speculative_contacts` on, runs a copy with it off (A) and the file as bundled (B), N
# pairs, and prints the median CPU seconds (user + sys) of each, their ratio B / A, the
# per-pair ratios and both outcomes.
#   bash bench/ab_cull.sh 5 packbot_stairs tasks/packbot_stairs_up course_stairs
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${TRACKSIM_BIN:-$root/target/debug/tracksim}"
n="$1"; shift
work="$(mktemp -d)"; trap 'rm -rf "$work"; rm -f "$root"/scenarios/_ab_off_*.toml "$root"/scenarios/*/_ab_off_*.toml' EXIT
for f in "$@"; do
  src="$root/scenarios/$f.toml"
  grep -q '^cull_speculative_contacts = true' "$src" || { echo "$f does not turn the cull on" >&2; exit 2; }
  # beside the original, so that its relative paths hold
  off="$(dirname "$src")/_ab_off_$(basename "$f").toml"
  sed 's/^cull_speculative_contacts = true/cull_speculative_contacts = false/' "$src" > "$off"
  for _ in $(seq "$n"); do
    /usr/bin/time -f "$f A %U %S" "$bin" run "$off" --out "$work/A" --no-plot >/dev/null 2>>"$work/times"
    /usr/bin/time -f "$f B %U %S" "$bin" run "$src" --out "$work/B" --no-plot >/dev/null 2>>"$work/times"
  done
  rm -f "$off"
  for k in A B; do
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(sys.argv[2], sys.argv[3], j['outcome'], j.get('outcome_time_s'))" "$work/$k/summary.json" "$f" "$k"
  done
done
python3 - "$work/times" <<'P'
import statistics as s, sys
d = {}
for line in open(sys.argv[1]):
    p = line.split()
    if len(p) == 4:
        d.setdefault(p[0], {}).setdefault(p[1], []).append(float(p[2]) + float(p[3]))
for f, v in d.items():
    a, b = s.median(v["A"]), s.median(v["B"])
    pr = [y / x for x, y in zip(v["A"], v["B"])]
    print(f"{f}: off {a:.2f} s, on {b:.2f} s CPU (medians of {len(v['A'])}), on/off {b / a:.3f}, "
          f"per-pair {min(pr):.3f}-{max(pr):.3f}")
P
