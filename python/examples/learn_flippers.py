"""Cross-entropy search over a 3-parameter flipper policy for PackBot 510 at random steps
(scenarios/random/packbot_flippers_step_random.toml: height 0.12-0.24 m, edge 0.5-0.9 m,
friction 0.6-0.9), with numpy and the native vector env only.

Policy (normalised flipper action, both flippers alike, forward at 0.6 * 0.5 m/s):
    flipper = clip(w0 + w1 * nose_up_pitch_rad + w2 * step_ahead_m / 0.1, -1, 1)
where step_ahead_m is the rise of the terrain 0.3-0.4 m ahead (the observation grid's first
two rows) since the start. The baseline is the same policy with w = 0 (flippers level).

    python python/examples/learn_flippers.py --pop 8 --iters 4 --episodes 8 --test-episodes 24

Prints the success rate of the baseline and of the learned policy on held-out seeds (the
training seeds are 0..episodes-1, the test seeds start at 10000), and the learned weights.
"""

import argparse
import json
import pathlib
import time

import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios" / "random" / "packbot_flippers_step_random.toml"
CONFIG = {"grid_shape": (4, 1), "grid_spacing_m": (0.1, 0.1), "grid_ahead_m": 0.3}


def success_rate(weights, seeds, threads):
    """Success rate of every weight vector (rows of `weights`) over the same episode seeds."""
    weights = np.atleast_2d(weights)
    k, e = len(weights), len(seeds)
    env = tracksim.TracksimVectorEnv(SCENARIO, k * e, threads=threads, config=CONFIG)
    names = env.obs_names
    grid = [names.index(f"terrain_{i}_0_m") for i in (0, 1)]
    obs, _ = env.reset(seed=[s for _ in range(k) for s in seeds])
    z0 = obs[:, grid].mean(axis=1)  # terrain ahead at the start: the ground
    w = np.repeat(weights, e, axis=0)
    outcome = [""] * (k * e)
    while any(o == "" for o in outcome):
        ahead = (obs[:, grid].mean(axis=1) - z0) / 0.1
        fl = np.clip(w[:, 0] + w[:, 1] * (-obs[:, 1]) + w[:, 2] * ahead, -1, 1)
        a = np.zeros((k * e, 4), np.float32)
        a[:, 0] = 0.6
        a[:, 2] = a[:, 3] = fl
        obs, _, term, trunc, info = env.step(a)
        for i in np.flatnonzero(term | trunc):
            if outcome[i] == "":
                outcome[i] = info["outcome"][i]
    ok = np.array([o == "success" for o in outcome]).reshape(k, e)
    return ok.mean(axis=1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pop", type=int, default=8, help="candidates per iteration")
    ap.add_argument("--elite", type=int, default=2, help="candidates kept per iteration")
    ap.add_argument("--iters", type=int, default=4)
    ap.add_argument("--episodes", type=int, default=8, help="training episodes per candidate")
    ap.add_argument("--test-episodes", type=int, default=24)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0, help="seed of the search's own sampling")
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    args = ap.parse_args()
    t0 = time.time()
    rng = np.random.default_rng(args.seed)
    mean, std = np.zeros(3), np.array([0.5, 1.0, 0.5])
    train = list(range(args.episodes))
    best = (np.zeros(3), -1.0)
    for it in range(args.iters):
        cand = mean + std * rng.standard_normal((args.pop, 3))
        score = success_rate(cand, train, args.threads)
        order = np.argsort(-score, kind="stable")
        elite = cand[order[: args.elite]]
        mean, std = elite.mean(axis=0), elite.std(axis=0) + 0.05
        if score[order[0]] > best[1]:
            best = (cand[order[0]], float(score[order[0]]))
        if not args.json:
            print(f"iteration {it}: best training success {score[order[0]]:.2f}, "
                  f"mean {score.mean():.2f}, weights {np.round(cand[order[0]], 3).tolist()}",
                  flush=True)
    test = list(range(10000, 10000 + args.test_episodes))
    rates = success_rate(np.stack([np.zeros(3), best[0]]), test, args.threads)
    result = {"baseline_success": float(rates[0]), "learned_success": float(rates[1]),
              "weights": best[0].tolist(), "test_episodes": args.test_episodes,
              "train_episodes": args.episodes, "pop": args.pop, "iters": args.iters,
              "wall_s": round(time.time() - t0, 1)}
    if args.json:
        print(json.dumps(result))
    else:
        print(f"held-out success rate over {args.test_episodes} episodes: flippers level "
              f"{rates[0]:.2f}, learned policy {rates[1]:.2f} "
              f"(weights {np.round(best[0], 3).tolist()}, {result['wall_s']} s)")


if __name__ == "__main__":
    main()
