"""Env steps per second per core of the learning environments, for A/B comparisons of builds.

    python bench/env_steps.py [--cases flat,stairs,quince] [--steps 100] [--envs 8]
                              [--threads 1] [--json]

One Rust thread (`--threads N`: N), `TracksimVectorEnv` of `--envs` environments (the figure
`bench_vector.py` reports as "native TracksimVectorEnv, 8 envs, 1 thread(s)"), 20 Hz control (50 ms per env step),
default observation (state vector with the 5 x 3 terrain grid) and twist actions:
- flat:   PackBot 510 (40 grousers per track) on flat ground, forward 0.3 m/s turning 0.1 rad/s
          (`scenarios/packbot_flat.toml`, the action of bench_vector.py);
- stairs: PackBot 510 with flippers at the bundled stairs (`scenarios/packbot_stairs.toml`),
          forward 0.3 m/s, flippers at +18 deg (episodes that end are reset, as in training);
- quince: Quince (main tracks and four sub-tracks, 40 + 4 x 22 grousers) on flat ground
          (`scenarios/quince_flat.toml`), forward 0.3 m/s.
Only stepping is timed (one warm-up step first), in CPU time of the process (all its threads:
`time.process_time`), so that other work on a shared machine disturbs the figure less than it
would wall time; `--json` also gives each case's wall-clock rate as `CASE@wall`.
`bench/ab_env_steps.py` runs two builds of the package side by side, interleaved.
"""

import argparse
import json
import pathlib
import time

import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[1]
CASES = {
    "flat": ("packbot_flat.toml", [0.6, 0.1]),
    "stairs": ("packbot_stairs.toml", [0.6, 0.0, 0.3, 0.3]),
    "quince": ("quince_flat.toml", None),
}


def rate(case, steps, envs, config, physics, threads=1):
    """Env steps per CPU second (all the process's threads) and per wall second."""
    file, action = CASES[case]
    path = str(ROOT / "scenarios" / file)
    scenario = tracksim.Scenario(path, **physics) if physics else path
    env = tracksim.TracksimVectorEnv(scenario, envs, threads=threads, config=config)
    if action is None:
        action = [0.6] + [0.0] * (env.single_action_space.shape[0] - 1)
    a = np.tile(np.array(action, np.float32), (envs, 1))
    env.reset(seed=0)
    env.step(a)  # warm-up
    t, w = time.process_time(), time.perf_counter()
    for _ in range(steps):
        env.step(a)
    return steps * envs / (time.process_time() - t), steps * envs / (time.perf_counter() - w)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default="flat,stairs,quince")
    ap.add_argument("--steps", type=int, default=100, help="vector steps timed per case")
    ap.add_argument("--envs", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1, help="Rust threads stepping the envs")
    ap.add_argument("--config", default="{}", help="env config as JSON (e.g. a method)")
    ap.add_argument("--physics", default="{}",
                    help="Scenario overrides as JSON, e.g. tracksim.TRAINING_PHYSICS")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    config = json.loads(args.config)
    physics = json.loads(args.physics)
    out = {}
    for c in args.cases.split(","):
        out[c], out[f"{c}@wall"] = rate(c, args.steps, args.envs, config, physics, args.threads)
    if args.json:
        print(json.dumps(out))
    else:
        for c in args.cases.split(","):
            print(f"{c:8s} {out[c]:8.1f} env steps/s per CPU second, {out[c + '@wall']:8.1f} per "
                  f"wall second ({args.threads} thread(s))")


if __name__ == "__main__":
    main()
