#!/usr/bin/env bash
# Regenerates crates/tracksim/tests/golden/trajectories.txt (the golden trajectory hashes).
# Only for a deliberate physics change: say why in the commit that updates the file.
set -euo pipefail
cd "$(dirname "$0")/.."
TRACKSIM_UPDATE_GOLDEN=1 cargo test -p tracksim --test suite golden::
git diff --stat -- crates/tracksim/tests/golden/trajectories.txt
