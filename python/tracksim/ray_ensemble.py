"""An ensemble fanned out as Ray tasks (docs/ENSEMBLE.md): one task per shard of members, each
running ``tracksim.dataset.ensemble`` on its shard (the simulation in Rust, GIL released),
then the shards' reports joined in Rust (``tracksim.dataset.ensemble_merge``): the same
members, verdict and spreads as one ``tracksim run --ensemble N`` on one machine.

    import ray, tracksim.ray_ensemble
    ray.init(num_cpus=2)          # or ray.init(address="auto") on a cluster
    report = tracksim.ray_ensemble.ray_ensemble("scenarios/packbot_stairs.toml",
                                                members=256, shards=32)
    print(report["verdict"])      # "S 256/256" or "marginal 201/256"

With ``out``, each member's run folder is written there (on a cluster: a folder every node
can write) and the merged ``ensemble.json`` / ``ensemble.csv`` beside them.
"""

from __future__ import annotations

import os
from typing import Optional

from . import dataset


def _shard(scenario_path: str, members: int, out: Optional[str], seed: int, start_mm: float,
           yaw_deg: float, keep_order: bool, jobs: int, index: int, count: int) -> dict:
    return dataset.ensemble(scenario_path, members=members, out=out, seed=seed,
                            start_mm=start_mm, yaw_deg=yaw_deg, keep_order=keep_order,
                            jobs=jobs, shard=(index, count))


def ray_ensemble(scenario: os.PathLike, members: int = 16, shards: int = 2,
                 out: Optional[os.PathLike] = None, seed: int = 0, start_mm: float = 1.0,
                 yaw_deg: float = 0.05, keep_order: bool = False,
                 num_cpus_per_task: float = 1.0) -> dict:
    """Runs the ensemble of ``members`` members of ``scenario`` as ``shards`` Ray tasks (each
    on ``num_cpus_per_task`` threads, retried up to twice) and returns the joined report, as
    :func:`tracksim.dataset.ensemble` returns it. Needs ``ray.init()`` first."""
    import ray

    shards = max(1, min(int(shards), int(members)))
    jobs = max(1, int(num_cpus_per_task))
    task = ray.remote(num_cpus=num_cpus_per_task, max_retries=2)(_shard)
    scenario = os.path.abspath(os.fspath(scenario))
    out_dir = None if out is None else os.path.abspath(os.fspath(out))
    refs = [task.remote(scenario, int(members), out_dir, int(seed), float(start_mm),
                        float(yaw_deg), bool(keep_order), jobs, i, shards)
            for i in range(shards)]
    return dataset.ensemble_merge(ray.get(refs), out_dir)
