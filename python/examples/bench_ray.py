"""The Ray paths against the native vector env on 2 local CPUs, interleaved in one run, on flat
ground (scenarios/packbot_flat.toml, PackBot 510) and on the stairs
(scenarios/packbot_stairs.toml, PackBot 510 with flippers), 20 Hz control (one env step = 50 ms
= 50 physics steps of 1 ms), forward 0.3 m/s, flippers at the middle of their range.

    python python/examples/bench_ray.py [--envs 4] [--rounds 3] [--sweep-runs 4]

Each round times, in this order and for each scenario, whole episodes from the same seeds
(every configuration simulates exactly the same thing: results do not depend on the split):
- native: ``tracksim.TracksimVectorEnv``, ``--envs`` envs on 2 Rust threads, then on 1;
- ray: ``tracksim.ray_vector.RayVectorEnv``, the same envs in 2 Ray actors of 1 thread each;
- sweeps: ``--sweep-runs`` runs of the file (its own commands, run folders written) as
  ``tracksim.dataset.sweep(jobs=2)`` and as ``tracksim.ray_sweep.ray_sweep(shards=2)``,
  counted in env-step equivalents (simulated s / 0.05 s).
Prints env steps/s per configuration and round, then the medians and the ratios to the native
env with 2 threads. Ray runs on ``ray.init(num_cpus=2)`` (its start-up is not timed).
"""

import argparse
import os
import pathlib
import shutil
import statistics
import tempfile
import time

import numpy as np

import tracksim
from tracksim import dataset

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIOS = {"flat": ROOT / "scenarios" / "packbot_flat.toml",
             "stairs": ROOT / "scenarios" / "packbot_stairs.toml"}
CONTROL_S = 0.05


def episode_steps(path):
    """Env steps of one whole episode of the file (its duration over the control period)."""
    sc = tracksim.Scenario(str(path))
    return int(round(sc.info(sc.file_seed)["duration_s"] / CONTROL_S))


def timed_episode(env, n, steps):
    """Env steps/s of ``steps`` vector steps of ``env`` (``n`` envs) from seed 0."""
    env.reset(seed=0)
    a = np.zeros((n, env.single_action_space.shape[0]), np.float32)
    a[:, 0] = 0.6
    t = time.perf_counter()
    for _ in range(steps):
        env.step(a)
    return steps * n / (time.perf_counter() - t)


def timed_sweep(fn, path, runs):
    out = tempfile.mkdtemp(prefix="bench_ray_")
    try:
        t = time.perf_counter()
        fn(path, out)
        wall = time.perf_counter() - t
    finally:
        shutil.rmtree(out, ignore_errors=True)
    return runs * episode_steps(path) / wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envs", type=int, default=4, help="environments per vector env")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--sweep-runs", type=int, default=4, help="runs per sweep (0: no sweeps)")
    ap.add_argument("--steps", type=int, default=0,
                    help="vector steps timed per configuration (default: one whole episode)")
    args = ap.parse_args()
    import ray

    from tracksim.ray_sweep import ray_sweep
    from tracksim.ray_vector import RayVectorEnv

    print(f"cores available: {os.cpu_count()}, load average before: {os.getloadavg()[0]:.2f}",
          flush=True)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    results = {}
    try:
        for r in range(args.rounds):
            for name, path in SCENARIOS.items():
                steps = args.steps or episode_steps(path)
                # The Ray env's 2 actors take the 2 Ray CPUs: made (not timed) and ended here.
                envs = {
                    "native, 2 threads": tracksim.TracksimVectorEnv(path, args.envs, threads=2),
                    "ray, 2 actors x 1 thread": RayVectorEnv(path, args.envs, num_actors=2),
                    "native, 1 thread": tracksim.TracksimVectorEnv(path, args.envs, threads=1),
                }
                for label, env in envs.items():
                    sps = timed_episode(env, args.envs, steps)
                    results.setdefault((name, label), []).append(sps)
                    print(f"round {r} {name:6s} {label:36s} {sps:8.1f} env steps/s "
                          f"(load {os.getloadavg()[0]:.2f})", flush=True)
                    env.close()
                if args.sweep_runs:
                    p = str(path)
                    for label, fn in (
                        ("sweep, jobs=2", lambda p, o: dataset.sweep(
                            p, o, runs=args.sweep_runs, seed=0, jobs=2)),
                        ("ray_sweep, 2 shards", lambda p, o: ray_sweep(
                            p, o, runs=args.sweep_runs, shards=2, seed=0)),
                    ):
                        sps = timed_sweep(fn, p, args.sweep_runs)
                        results.setdefault((name, label), []).append(sps)
                        print(f"round {r} {name:6s} {label:36s} {sps:8.1f} env steps/s "
                              f"(equivalent; load {os.getloadavg()[0]:.2f})", flush=True)
    finally:
        ray.shutdown()
    print(f"\nmedians over {args.rounds} rounds ({args.envs} envs; ratios to native 2 threads "
          f"of the same scenario; per core = / 2, native 1 thread / 1)")
    for name in SCENARIOS:
        ref = statistics.median(results[(name, "native, 2 threads")])
        for (n, label), v in results.items():
            if n != name:
                continue
            m = statistics.median(v)
            cores = 1 if label == "native, 1 thread" else 2
            print(f"{name:6s} {label:36s} {m:8.1f} env steps/s {m / cores:8.1f} per core "
                  f"ratio {m / ref:5.2f}")


if __name__ == "__main__":
    main()
