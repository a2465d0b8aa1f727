#!/usr/bin/env bash
# Same-run benchmark of tracksim against MuJoCo (issue 16): installs the pinned MuJoCo from PyPI
# into bench/mujoco/.venv (once), builds the release tracksim binary and the contact_floor
# example, then runs bench.py, which times the MuJoCo models and `tracksim bench` interleaved
# in one window and prints the ratio table. Arguments go to bench.py (see `--help`).
#   bash bench/mujoco/run.sh --repeat 5 --out bench_out/mujoco
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
target="${CARGO_TARGET_DIR:-$root/target}"
if [ ! -x "$here/.venv/bin/python" ]; then
  python3 -m venv "$here/.venv"
  "$here/.venv/bin/pip" install --quiet -r "$here/requirements.txt"
fi
# one invocation: the CLI and the example then share one feature resolution (two separate
# builds recompile the library each time)
(cd "$root" && cargo build --release -p tracksim-cli -p tracksim --bins --example contact_floor)
exec "$here/.venv/bin/python" "$here/bench.py" \
  --tracksim "$target/release/tracksim" \
  --contact-floor "$target/release/examples/contact_floor" \
  --scenario "$root/scenarios/packbot_flat.toml" "$@"
