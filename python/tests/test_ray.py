"""The Ray path: a sweep fanned out as Ray tasks on 2 local CPUs merges to the plain sweep."""

import pytest

from tracksim import dataset
from test_sweep import short_step  # noqa: F401  (fixture)

ray = pytest.importorskip("ray")


def test_ray_sweep_on_two_local_cpus(tmp_path, short_step):  # noqa: F811
    from tracksim.ray_sweep import ray_sweep

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        lines = ray_sweep(short_step, tmp_path / "ray", runs=4, shards=2, seed=5)
    finally:
        ray.shutdown()
    assert lines == dataset.sweep(short_step, tmp_path / "plain", runs=4, seed=5)
