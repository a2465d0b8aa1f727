"""A learning environment watched in the browser (web/tests/e2e.test.mjs, issue 44): a
`TracksimEnv` of `scenarios/packbot_flat.toml` (its episodes made 300 s long, so that none ends
while the page is looked at) with render_mode="human", driven forward and turning at real time
(render_speed 1) so that the page sees its belts run, for at most `argv[1]` seconds of wall
time (default 120) or until killed. Prints the page's URL (the environment's own line, at its
first step)."""

import pathlib
import sys
import tempfile
import time

import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[2]
limit_s = float(sys.argv[1]) if len(sys.argv) > 1 else 120.0
flat = (ROOT / "scenarios" / "packbot_flat.toml").read_text()
long = (flat.replace('"../vehicles/', f'"{ROOT / "vehicles"}/')
        .replace("duration_s = 10.0", "duration_s = 300.0"))
assert long != flat and "300.0" in long, "packbot_flat.toml changed: update this script"
scenario = pathlib.Path(tempfile.mkdtemp()) / "packbot_flat_long.toml"
scenario.write_text(long)
env = tracksim.TracksimEnv(str(scenario), render_mode="human", render_speed=1.0)
env.reset(seed=0)
action = np.zeros(env.action_space.shape, np.float32)
action[:2] = [0.6, 0.2]  # forward, turning left (twist actions): the belts differ
start = time.monotonic()
while time.monotonic() - start < limit_s:
    _, _, terminated, truncated, _ = env.step(action)
    if terminated or truncated:
        env.reset()
env.close()
