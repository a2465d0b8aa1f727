"""Issue 24: the checks are the library's, so Python gets the Rust messages (with the key) as
ValueError; a sweep of a file without [randomize] warns that its runs will be identical."""

import numpy as np
import pytest

import tracksim
from tracksim import _tracksim, dataset
from conftest import SCENARIOS, SHORT_FLAT


def test_env_settings_are_checked_by_the_library():
    with pytest.raises(ValueError, match="did you mean `control_period_s`") as e:
        tracksim.TracksimEnv(SCENARIOS / "packbot_flat.toml", config={"period": 0.1})
    assert not isinstance(e.value, tracksim.ScenarioError)
    assert "`no_terrain_m`" in str(e.value)  # the whole list of settings
    with pytest.raises(ValueError) as e:
        tracksim.TracksimEnv(SCENARIOS / "packbot_flat.toml",
                             config={"grid_shape": (2.5, 3), "control_period_s": -1.0,
                                     "action": "tank"})
    msg = str(e.value)
    for key in ("grid_shape: expected two whole numbers", "control_period_s: must be",
                "action: \"tank\" is not an action mode"):
        assert key in msg, msg
    # Lists are pairs too.
    env = tracksim.TracksimEnv(SCENARIOS / "packbot_flat.toml", config={"grid_shape": [2, 2]})
    assert env.observation_space.shape == (10 + 2 + 4,)


def test_array_lengths_are_checked_by_the_library():
    sim = tracksim.Simulation(SCENARIOS / "packbot_stairs.toml")
    with pytest.raises(ValueError, match="flipper_angles: expected 2 flipper angles"):
        sim.set_flipper_angles([0.5])
    with pytest.raises(ValueError, match=r"belt_speeds\[0\]: must be a finite number"):
        sim.set_belt_speeds([float("nan")] + [0.0] * (len(sim.track_names) - 1))
    with pytest.raises(ValueError, match="ys: expected one y per x"):
        sim.terrain_heights([0.0, 1.0], [0.0])
    core = tracksim.EnvCore(tracksim.Scenario(SCENARIOS / "packbot_flat.toml"), 0, None)
    with pytest.raises(ValueError, match="action: expected 2 actions"):
        core.step([0.5])


def test_vector_env_arrays_are_checked_by_the_library(write_scenario):
    p = write_scenario(SHORT_FLAT % "0.3")
    with pytest.raises(ValueError, match="num_envs: must be from 1"):
        _tracksim.VecEnvCore(str(p), 0)
    v = _tracksim.VecEnvCore(str(p), 2)
    # Was an UnstableError before the check moved into the library.
    with pytest.raises(ValueError, match=r"seeds: expected 2 seeds \(one per environment\), got 3"):
        v.reset(seeds=[1, 2, 3])
    with pytest.raises(ValueError, match=r"actions: expected shape \(2, 2\)"):
        v.step(np.zeros((1, 4), np.float32))
    obs, info = v.step(np.zeros((2, 2), np.float32))
    assert obs.shape == (2, v.obs_dim)


def test_sweep_plans_are_checked_by_the_library(tmp_path, write_scenario):
    p = write_scenario(SHORT_FLAT % "0.2")
    with pytest.raises(ValueError, match="shard: shard 2 of 2"):
        dataset.sweep(p, tmp_path / "a", runs=2, shard=(2, 2))
    with pytest.raises(ValueError, match="runs: must be from 1"):
        dataset.sweep(p, tmp_path / "b", runs=0)
    with pytest.raises(ValueError, match="jobs: must be from 1"):
        dataset.sweep(p, tmp_path / "c", runs=1, jobs=0)
    with pytest.warns(UserWarning, match="its 2 runs will be identical"):
        lines = dataset.sweep(p, tmp_path / "d", runs=2)
    assert len(lines) == 2
