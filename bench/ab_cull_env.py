"""Issue 44: env steps per CPU second of the learning environments with the cull of speculative
contacts (the stairs files as bundled) against without it (a copy of each file with
`cull_speculative_contacts = false`, written beside it and removed after), interleaved in one
process: the same wheel, so only the file's key differs. `TracksimVectorEnv` of 8 envs on one
Rust thread, 20 Hz control (50 physics steps of 1 ms an env step), 60 env steps per sample.

    python bench/ab_cull_env.py [PAIRS]
"""
import pathlib
import statistics as st
import sys
import time

import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[1] / "scenarios"
# file, action (None: forward 0.6, the rest 0)
CASES = {"stairs": ("packbot_stairs.toml", [0.6, 0.0, 0.3, 0.3]),
         "stairs_up_task": ("tasks/packbot_stairs_up.toml", None)}


def rate(path, action, steps=60, envs=8):
    env = tracksim.TracksimVectorEnv(str(path), envs, threads=1)
    if action is None:
        action = [0.6] + [0.0] * (env.single_action_space.shape[0] - 1)
    a = np.tile(np.array(action, np.float32), (envs, 1))
    env.reset(seed=0)
    env.step(a)  # warm-up
    t = time.process_time()
    for _ in range(steps):
        env.step(a)
    return steps * envs / (time.process_time() - t)


def main():
    pairs = int(sys.argv[1]) if len(sys.argv) > 1 else 4
    for case, (file, action) in CASES.items():
        on = ROOT / file
        off = on.with_name("_ab_off_" + on.name)
        text = on.read_text()
        assert "cull_speculative_contacts = true" in text, f"{file} does not turn the cull on"
        off.write_text(text.replace("cull_speculative_contacts = true",
                                    "cull_speculative_contacts = false"))
        try:
            r = {"on": [], "off": []}
            for i in range(pairs):
                for k in (("off", "on") if i % 2 == 0 else ("on", "off")):
                    r[k].append(rate(on if k == "on" else off, action))
        finally:
            off.unlink()
        ratios = [a / b for a, b in zip(r["on"], r["off"])]
        print(f"{case}: env steps per CPU s off {st.median(r['off']):.1f}, on {st.median(r['on']):.1f}, "
              f"ratio of medians {st.median(r['on']) / st.median(r['off']):.3f}, "
              f"per-pair {min(ratios):.3f}-{max(ratios):.3f}")


if __name__ == "__main__":
    main()
