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


def test_ray_vector_env_equals_the_native_one_on_two_local_cpus():
    """The same seeds give the same episodes whether 3 envs live in one process or in 2 Ray
    actors (2 + 1), through an autoreset: 1 s control periods end the 8 s episodes at step 8,
    step 9 resets them."""
    import numpy as np

    import tracksim
    from conftest import SCENARIOS
    from tracksim.ray_vector import RayVectorEnv

    path = SCENARIOS / "random" / "packbot_flippers_step_random.toml"
    config = {"grid_shape": (2, 1), "control_period_s": 1.0}
    native = tracksim.TracksimVectorEnv(path, 3, threads=1, config=config)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        renv = RayVectorEnv(path, 3, num_actors=2, config=config)
        assert renv.sizes == [2, 1]
        assert renv.single_observation_space == native.single_observation_space
        o1, i1 = native.reset(seed=7)
        o2, i2 = renv.reset(seed=7)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(i1["seed"], i2["seed"])
        rng = np.random.default_rng(0)
        resets = 0
        for _ in range(10):
            a = rng.uniform(-1, 1, (3, 4)).astype(np.float32)
            r1, r2 = native.step(a), renv.step(a)
            for x, y in zip(r1[:4], r2[:4]):
                np.testing.assert_array_equal(x, y)
            for k in ("progress_m", "seed", "autoreset", "outcome", "reason"):
                np.testing.assert_array_equal(np.asarray(r1[4][k]), np.asarray(r2[4][k]))
            resets += int(np.sum(r1[4]["autoreset"]))
        assert resets >= 1
        with pytest.raises(ValueError, match="num_actors"):
            RayVectorEnv(path, 2, num_actors=3)
        renv.close()
    finally:
        ray.shutdown()


def test_ray_ensemble_on_two_local_cpus_is_the_local_ensemble(tmp_path):
    """An ensemble run as 2 Ray shards and joined has the members, verdict and spreads of the
    same ensemble on one machine, and writes the joined ensemble.json."""
    from conftest import SCENARIOS
    from tracksim.ray_ensemble import ray_ensemble

    step = SCENARIOS / "packbot_step.toml"
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        r = ray_ensemble(step, members=4, shards=2, out=tmp_path / "ray", seed=3)
    finally:
        ray.shutdown()
    local = dataset.ensemble(step, members=4, seed=3, jobs=2)
    assert r["verdict"] == local["verdict"] and r["requested"] == 4
    assert r["success_time_s"] == local["success_time_s"]
    assert [m["member"] for m in r["members"]] == [m["member"] for m in local["members"]]
    for a, b in zip(r["members"], local["members"]):
        assert (a["outcome"], a["outcome_time_s"], a["final_pose"]) == \
            (b["outcome"], b["outcome_time_s"], b["final_pose"])
    assert (tmp_path / "ray" / "ensemble.json").is_file()
    assert (tmp_path / "ray" / "member-003" / "trajectory.csv").is_file()


def test_ensemble_shards_join_once_each():
    from conftest import SCENARIOS

    step = SCENARIOS / "packbot_step.toml"
    a = dataset.ensemble(step, members=3, seed=1, jobs=1, shard=(0, 2))
    assert [m["member"]["index"] for m in a["members"]] == [0, 2]
    with pytest.raises(ValueError, match="member 0 is in two shards"):
        dataset.ensemble_merge([a, a])
    with pytest.raises(ValueError, match="shard"):
        dataset.ensemble(step, members=3, shard=(2, 2))
