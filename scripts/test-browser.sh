#!/usr/bin/env bash
# End-to-end test of `tracksim drive` / `tracksim view` in headless Chromium (issue 12), from a
# clean clone: installs Debian's chromium if missing (apt-get, as root), the pinned
# playwright-core (npm ci, no browser download), builds the release binary and runs
# web/tests/e2e.test.mjs with node's test runner. Screenshots: web/tests/artifacts/.
# The test of a learning environment's page (render_mode="human") runs the Python package
# of .venv-ci (made by scripts/test-python.sh, which CI runs first) or of TRACKSIM_PYTHON.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v chromium >/dev/null 2>&1; then
    echo "installing chromium (apt-get) ..."
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
# TRACKSIM_BIN may name an already built binary (CI passes the optimised dev-profile one the
# tests built); otherwise build the release binary.
if [[ -z "${TRACKSIM_BIN:-}" ]]; then
    cargo build --release -p tracksim-cli
    target="${CARGO_TARGET_DIR:-target}"
    export TRACKSIM_BIN="$PWD/$target/release/tracksim"
    [[ "$target" = /* ]] && export TRACKSIM_BIN="$target/release/tracksim"
fi
export CHROMIUM="$(command -v chromium)"
cd web/tests
# playwright-core downloads no browser; skip any download hook all the same.
PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund
node --test e2e.test.mjs
