"""Env steps per second of the native vector env (1 and 2 Rust threads) against
gymnasium.vector.AsyncVectorEnv over the single env, PackBot 510 (40 grousers per track) on
flat ground at 20 Hz control (50 ms per env step = 50 physics steps of 1 ms).

    python python/examples/bench_vector.py [--envs 8] [--steps 100]

Prints one line per configuration: env steps/s and env steps/s per core used.
"""

import argparse
import os
import pathlib
import time

import gymnasium as gym
import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIO = str(ROOT / "scenarios" / "packbot_flat.toml")


def timed(env, steps, n):
    env.reset(seed=0)
    a = np.tile(np.array([0.6, 0.1], np.float32), (n, 1))
    env.step(a)  # warm-up
    t = time.perf_counter()
    for _ in range(steps):
        env.step(a)
    return steps * n / (time.perf_counter() - t)


def make():
    return tracksim.TracksimEnv(SCENARIO)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envs", type=int, default=8, help="environments of the native vector env")
    ap.add_argument("--steps", type=int, default=100, help="vector steps timed")
    args = ap.parse_args()
    print(f"cores available: {os.cpu_count()}, load average before: {os.getloadavg()[0]:.2f}")
    rows = []
    for threads in (1, 2):
        env = tracksim.TracksimVectorEnv(SCENARIO, args.envs, threads=threads)
        rows.append((f"native TracksimVectorEnv, {args.envs} envs, {threads} thread(s)", threads,
                     timed(env, args.steps, args.envs)))
    for workers in (1, 2):
        env = gym.vector.AsyncVectorEnv([make] * workers)
        rows.append((f"gymnasium AsyncVectorEnv, {workers} subprocess(es)", workers,
                     timed(env, args.steps * args.envs // workers, workers)))
        env.close()
    single = make()
    single.reset(seed=0)
    a = np.array([0.6, 0.1], np.float32)
    t = time.perf_counter()
    for _ in range(args.steps):
        single.step(a)
    rows.append(("single TracksimEnv (no vector wrapper)", 1,
                 args.steps / (time.perf_counter() - t)))
    for name, cores, sps in rows:
        print(f"{name:55s} {sps:8.1f} env steps/s {sps / cores:8.1f} per core")


if __name__ == "__main__":
    main()
