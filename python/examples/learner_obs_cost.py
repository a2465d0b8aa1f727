"""What the learner's observation costs per step (issue 29): CPU time per step of
`TracksimEnv` on the PackBot stairs with the default state vector and with
`observation="learner"` (64 x 64 elevation map), and the learner update's own wall time.

    python python/examples/learner_obs_cost.py [STEPS]
"""

import sys
import time
from pathlib import Path

import numpy as np

import tracksim

STAIRS = Path(__file__).resolve().parents[2] / "scenarios" / "packbot_stairs.toml"


def main(steps: int = 100) -> None:
    action = np.array([0.6, 0.0, 0.3, 0.3], np.float32)
    for obs in ("vector", "learner"):
        env = tracksim.TracksimEnv(STAIRS, config={"observation": obs})
        env.reset(seed=0)
        t0 = time.process_time()
        for _ in range(steps):
            env.step(action)
        cpu_ms = (time.process_time() - t0) / steps * 1e3
        updates, us = env._core.learner_cost_us
        extra = f", learner update {us / 1e3:.2f} ms wall ({updates} updates)" if updates else ""
        print(f"{obs:8s} {cpu_ms:.2f} ms CPU per step{extra}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100)
