"""The Gymnasium environment: check_env, spaces, termination, truncation, the reward."""

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tracksim
from conftest import SCENARIOS, SHORT_FLAT

STEP = SCENARIOS / "random" / "packbot_step_random.toml"


@pytest.mark.parametrize("scenario, config", [
    (SCENARIOS / "packbot_flat.toml", None),
    (STEP, {"action": "belts", "grid_shape": (3, 2)}),
    (SCENARIOS / "packbot_stairs.toml", {"control_period_s": 0.02}),
])
def test_check_env_passes(scenario, config):
    env = tracksim.TracksimEnv(scenario, config=config)
    check_env(env, skip_render_check=True)


def test_spaces_follow_the_vehicle_and_config():
    env = tracksim.TracksimEnv(SCENARIOS / "packbot_stairs.toml", config={"grid_shape": (4, 3)})
    assert env.action_space.shape == (4,)  # forward, yaw rate, two flippers
    # attitude, height, velocities; 2 flippers; 4 tracks (2 main, 2 on the flippers); 4x3 grid
    assert env.observation_space.shape == (10 + 2 + 4 + 12,)
    assert len(env.obs_names) == env.observation_space.shape[0]
    assert env.control_period_s == pytest.approx(0.05)
    with pytest.raises(ValueError, match="unknown environment setting"):
        tracksim.TracksimEnv(SCENARIOS / "packbot_flat.toml", config={"period": 0.1})


def test_truncated_at_the_duration(write_scenario):
    env = tracksim.TracksimEnv(write_scenario(SHORT_FLAT % "0.5"))
    env.reset(seed=0)
    flags = [env.step(np.array([1.0, 0.0], np.float32))[2:4] for _ in range(10)]
    assert flags[-1] == (False, True) and all(f == (False, False) for f in flags[:-1])


def test_terminated_on_the_outcome_and_progress_is_rewarded():
    env = tracksim.TracksimEnv(STEP)
    obs, info = env.reset(seed=2)
    assert info["randomized"]["step_height_m"] < 0.14
    total, done, n = 0.0, False, 0
    while not done:
        obs, r, term, trunc, info = env.step(np.array([0.6, 0.0], np.float32))
        total += r
        done = term or trunc
        n += 1
    assert term and info["outcome"] in ("success", "failure"), info
    assert total == pytest.approx(info["progress_m"], rel=1e-6)
    # A step terrain is in the grid ahead at the start: heights above the ground level.
    assert n < 160


def test_reward_is_replaceable_and_penalties_apply(write_scenario):
    p = write_scenario(SHORT_FLAT % "1.0")
    plain = tracksim.TracksimEnv(p)
    taxed = tracksim.TracksimEnv(p, reward=tracksim.ProgressReward(energy_penalty=10.0))
    const = tracksim.TracksimEnv(p, reward=lambda obs, dp, effort, period: 42.0)
    a = np.array([1.0, 0.0], np.float32)
    for e in (plain, taxed, const):
        e.reset(seed=0)
    r = [e.step(a)[1] for e in (plain, taxed, const)]
    assert r[1] == pytest.approx(r[0] - 10.0 * 0.5 * 0.05)
    assert r[2] == 42.0
