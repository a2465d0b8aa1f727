#!/usr/bin/env bash
# Refreshes the vendored three.js files of the 3-D page from the npm registry. The page is
# served from the binary (include_bytes!), never from the internet at run time.
# Usage: scripts/update-three.sh [VERSION]; then set THREE_VERSION in
# crates/tracksim/src/live/assets.rs to the same version and run scripts/test-browser.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
version="${1:-0.187.0}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack "three@$version" --silent >/dev/null && tar xzf "three-$version.tgz")
dest=crates/tracksim/assets/vendor
cp "$tmp/package/build/three.module.js" "$tmp/package/build/three.core.js" \
   "$tmp/package/examples/jsm/controls/OrbitControls.js" "$dest/"
cp "$tmp/package/LICENSE" "$dest/LICENSE-three"
echo "three.js $version vendored into $dest"
