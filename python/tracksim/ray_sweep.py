"""A sweep fanned out as Ray tasks: one task per shard, each running ``tracksim.dataset.sweep``
on its shard (the simulation itself in Rust, GIL released), then the shards merged.

    import ray, tracksim.ray_sweep
    ray.init(num_cpus=2)          # or ray.init(address="auto") on a cluster
    lines = tracksim.ray_sweep.ray_sweep("scenarios/random/packbot_step_random.toml",
                                         "out/sweep", runs=100, shards=8)

On a cluster ``out`` must be a folder every node can write (a shared file system); each
shard writes its own run folders, atomically, so a retried task resumes where it stopped.
"""

from __future__ import annotations

import os
from typing import Dict, List, Optional, Sequence

from . import dataset


def _shard(scenario_path: str, out: str, runs: int, seed: Optional[int], grid, index: int,
           count: int) -> int:
    lines = dataset.sweep(scenario_path, out, runs=runs, seed=seed, grid=grid,
                          shard=(index, count), jobs=1, resume=True)
    return len(lines)


def ray_sweep(scenario: os.PathLike, out: os.PathLike, runs: int = 10, shards: int = 2,
              seed: Optional[int] = None, grid: Optional[Dict[str, Sequence[float]]] = None,
              num_cpus_per_task: float = 1.0) -> List[dict]:
    """Runs ``runs`` runs of ``scenario`` as ``shards`` Ray tasks writing into ``out``, merges
    them into ``out/manifest.jsonl`` and returns its lines (the same as one unsharded
    ``tracksim sweep``). Needs ``ray.init()`` first."""
    import ray

    task = ray.remote(num_cpus=num_cpus_per_task, max_retries=2)(_shard)
    scenario = os.path.abspath(os.fspath(scenario))
    out = os.path.abspath(os.fspath(out))
    refs = [task.remote(scenario, out, runs, seed, grid, i, shards) for i in range(shards)]
    ray.get(refs)
    dataset.merge([out], out)
    return dataset.load_manifest(out)
