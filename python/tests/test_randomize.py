"""`[randomize]`: values drawn from the seed, reproducible, in range, checked like every key."""

import numpy as np
import pytest

import tracksim
from conftest import SCENARIOS, SHORT_FLAT

STEP = SCENARIOS / "random" / "packbot_step_random.toml"


def test_values_are_reproducible_from_the_seed_and_in_range():
    sc = tracksim.Scenario(STEP)
    draws = [sc.sample(s) for s in range(40)]
    assert draws[3] == tracksim.Scenario(STEP).sample(3)
    assert len({d["step_height_m"] for d in draws}) == 40
    for d in draws:
        assert 0.06 <= d["step_height_m"] <= 0.14
        assert 0.4 <= d["friction"] <= 0.8
        assert -10 <= d["start_yaw_deg"] <= 10
    # The values reach the world: the step is as high as drawn.
    sim = tracksim.Simulation(sc, seed=7)
    d = sim.randomized
    assert d == sc.sample(7)
    x = d["step_edge_x_m"] + 0.5
    assert sim.terrain_heights([x], [0.0])[0] == pytest.approx(d["step_height_m"], abs=1e-4)
    assert np.degrees(sim.observe()["rpy_rad"][2]) == pytest.approx(d["start_yaw_deg"], abs=0.05)


def test_same_seed_same_trajectory_other_seed_other_world():
    def run(seed):
        sim = tracksim.Simulation(STEP, seed=seed)
        sim.set_twist(0.3, 0.0)
        sim.step(400)
        o = sim.observe()
        return np.concatenate([o["position_m"], o["rpy_rad"]])

    np.testing.assert_array_equal(run(11), run(11))
    assert not np.array_equal(run(11), run(12))


def test_a_fixed_scenario_is_the_same_for_every_seed():
    def run(seed):
        sim = tracksim.Simulation(SCENARIOS / "packbot_step.toml", seed=seed)
        sim.set_twist(0.3, 0.0)
        sim.step(300)
        return sim.observe()["position_m"]

    assert tracksim.Scenario(SCENARIOS / "packbot_step.toml").sample(3) == {}
    np.testing.assert_array_equal(run(1), run(2))


@pytest.mark.parametrize("table, key, words", [
    ('[randomize.f]\nuniform = [0.2, 0.1]\nkey = "terrain.ground.friction"\n',
     "randomize.f.uniform", "low <= high"),
    ('[randomize.f]\nuniform = [0.2, 0.4]\nkey = "terrain.boxes[0].friction"\n',
     "randomize.f.key", "name a key the scenario file holds"),
    ('[randomize.f]\nuniform = [0.2, 0.4]\n', "randomize.f", "give `key"),
    ('[randomize.f]\nuniform = [-0.5, 0.4]\nkey = "terrain.ground.friction"\n',
     "terrain.ground.friction", "at its low end"),
    ('[randomize.f]\nuniform = [0.2, 0.4]\nkey = "terrain.ground.friction"\nspread = 1\n',
     "spread", "unknown key `spread`"),
])
def test_bad_randomize_tables_name_the_key_and_the_fix(write_scenario, table, key, words):
    p = write_scenario(SHORT_FLAT % "1.0" + table)
    with pytest.raises(tracksim.ScenarioError) as e:
        tracksim.Scenario(p)
    assert str(p) in str(e.value) and key in str(e.value) and words in str(e.value), str(e.value)
