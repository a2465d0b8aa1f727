"""The training physics (``tracksim.TRAINING_PHYSICS``) as Scenario overrides: checked like the
file's keys, recorded in the scenario, and the same vehicle on flat ground."""

import numpy as np
import pytest

import tracksim
from conftest import SCENARIOS

FLAT = str(SCENARIOS / "packbot_flat.toml")


def test_overrides_reach_the_compiled_scenario():
    sc = tracksim.Scenario(FLAT, **tracksim.TRAINING_PHYSICS)
    assert sc.info(0)["solver_iterations"] == 2
    assert tracksim.Scenario(FLAT).info(0)["solver_iterations"] == 4
    clustered = tracksim.Scenario(FLAT, method="okada2020_clustered")
    assert clustered.info(0)["method"] == "okada2020_clustered"
    assert tracksim.Scenario(FLAT).info(0)["method"] == "okada2020"


def test_bad_overrides_name_the_key_and_the_fix():
    with pytest.raises(ValueError, match=r'method: unknown track method "okada2021" '
                                         r'\(did you mean "okada2020"\?\)'):
        tracksim.Scenario(FLAT, method="okada2021")
    with pytest.raises(ValueError, match="solver_iterations must be at least 1"):
        tracksim.Scenario(FLAT, solver_iterations=0)


def run_flat(scenario, seconds=4.0):
    """Forward speed over the last 2 s of `seconds` (m/s) of PackBot driven at 0.3 m/s."""
    env = tracksim.TracksimEnv(scenario)
    env.reset(seed=0)
    n = int(seconds / env.control_period_s)
    xs = []
    for _ in range(n):
        _, _, term, trunc, info = env.step(np.array([0.6, 0.0], np.float32))
        xs.append(info["progress_m"])
        assert not (term or trunc)
    k = int(2.0 / env.control_period_s)
    speed = (xs[-1] - xs[-1 - k]) / (k * env.control_period_s)
    return speed


def test_training_physics_drives_like_the_validated_physics_on_flat_ground():
    # A belt at 0.3 m/s on friction 0.6 barely slips: both settings must carry the body at the
    # belt speed within 1 % (the validated default measures 0.2992 m/s over 10 s).
    v_default = run_flat(FLAT)
    v_training = run_flat(tracksim.Scenario(FLAT, **tracksim.TRAINING_PHYSICS))
    assert v_default == pytest.approx(0.3, rel=0.01)
    assert v_training == pytest.approx(v_default, rel=0.01)


def test_a_task_takes_the_training_physics():
    import gymnasium

    env = gymnasium.make("tracksim/PackBotSteps-v0", physics=tracksim.TRAINING_PHYSICS)
    assert env.unwrapped.scenario.info(0)["solver_iterations"] == 2
    venv = tracksim.tasks.make_vector("tracksim/PackBotSteps-v0", 2,
                                      physics=tracksim.TRAINING_PHYSICS_CLUSTERED)
    obs, _ = venv.reset(seed=[1, 2])
    assert np.all(np.isfinite(obs))

