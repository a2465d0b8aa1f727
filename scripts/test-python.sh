#!/usr/bin/env bash
# The Python package from a clean clone: a venv (.venv-ci), the pinned tools, the package built
# and installed (maturin, release), the `tracksim` CLI built (the tests compare its messages and
# run its sweeps), then the pytest suite in python/tests. Needs Python >= 3.9 with venv and pip,
# and the Rust toolchain. Set PYTHON to choose the interpreter (default python3).
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-python3}"
VENV="${TRACKSIM_VENV:-.venv-ci}"
case "$VENV" in /*) ;; *) VENV="$PWD/$VENV" ;; esac  # absolute: the tests run from python/tests
[ -x "$VENV/bin/python" ] || "$PY" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r python/requirements-ci.txt
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
# The dev profile is optimised (Cargo.toml) and shares its artifacts with `cargo test
# --workspace`, so CI compiles the dependencies once; TRACKSIM_PROFILE=release for a release
# build. (The physics is the same in both: Rust does not reorder float operations.)
PROFILE="${TRACKSIM_PROFILE:-dev}"
OUTDIR=$([ "$PROFILE" = dev ] && echo debug || echo "$PROFILE")
# A CLI given in TRACKSIM_BIN (CI passes the one `cargo test --workspace` built) is used as it
# is: `cargo build -p tracksim-cli` alone resolves other dependency features than the
# workspace's test build and would compile much of the tree a second time.
if [ -z "${TRACKSIM_BIN:-}" ] || [ ! -x "$TRACKSIM_BIN" ]; then
  cargo build --profile "$PROFILE" -p tracksim-cli
  export TRACKSIM_BIN="$CARGO_TARGET_DIR/$OUTDIR/tracksim"
fi
# Build the wheel and install it (what a user gets), not an editable install.
rm -rf "$CARGO_TARGET_DIR/wheels"
"$VENV/bin/maturin" build --profile "$PROFILE" --out "$CARGO_TARGET_DIR/wheels"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$CARGO_TARGET_DIR"/wheels/tracksim-*.whl
# Run from the tests' folder so that `import tracksim` is the installed wheel, not python/.
cd python/tests
"$VENV/bin/python" -m pytest -q -p no:cacheprovider "$@"
