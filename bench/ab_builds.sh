#!/usr/bin/env bash
# Two builds of tracksim side by side (issue 44's build levers, BENCHMARKS.md "Issue 44 on a
# quiet machine"): N rounds of `tracksim bench --repeat 1 --methods okada2020,wheels4 --cases
# packbot`, alternating binary A and binary B, each round's microseconds a step printed.
#   bash bench/ab_builds.sh 9 target/release/tracksim /path/to/other/tracksim
set -euo pipefail
n="$1"; a="$2"; b="$3"
for _ in $(seq 1 "$n"); do
  for x in A B; do
    bin="$a"; [ "$x" = B ] && bin="$b"
    "$bin" bench --repeat 1 --methods okada2020,wheels4 --cases packbot --json 2>/dev/null | python3 -c "
import json,sys
d=json.load(sys.stdin)
print('$x', ' '.join(f\"{m['name']}={m['us_per_step']:.1f}\" for m in d['cases'][0]['methods']))
"
  done
done
