"""The Python API over the stepping API: load, step with controls, observe, reset, errors."""

import threading
import time

import numpy as np
import pytest

import tracksim
from conftest import SCENARIOS, SHORT_FLAT, run_cli


def test_simulation_drives_forward_with_twist_and_belts():
    sim = tracksim.Simulation(SCENARIOS / "packbot_flat.toml", seed=0)
    assert sim.track_names == ["left", "right"]
    assert sim.dt == pytest.approx(0.001)
    sim.set_twist(0.3, 0.0)
    sim.step(1000)
    o = sim.observe()
    assert sim.time == pytest.approx(1.0)
    assert o["position_m"].shape == (3,) and o["rpy_rad"].shape == (3,)
    assert 0.2 < o["position_m"][0] < 0.35, o
    np.testing.assert_allclose(o["belt_speed_mps"], [0.3, 0.3], atol=0.02)
    # Per-track belts: left slower than right turns left (REP 103: yaw grows).
    sim.reset(seed=0)
    sim.set_belt_speeds([0.1, 0.3])
    sim.step(1000)
    assert sim.observe()["rpy_rad"][2] > 0.05
    with pytest.raises(ValueError, match="expected 2 belt speeds"):
        sim.set_belt_speeds([0.1])


def test_flippers_move_to_their_targets():
    sim = tracksim.Simulation(SCENARIOS / "packbot_stairs.toml")
    assert len(sim.flipper_names) == 2
    sim.set_flipper_angles([0.5, 0.5])
    sim.step(1500)
    np.testing.assert_allclose(sim.observe()["flipper_angle_rad"], [0.5, 0.5], atol=0.05)


def test_reset_with_a_seed_reproduces_the_run_bit_for_bit():
    sim = tracksim.Simulation(SCENARIOS / "packbot_turn.toml", seed=5)
    runs = []
    for _ in range(2):
        sim.reset(seed=5)
        sim.set_twist(0.3, 0.4)
        sim.step(500)
        o = sim.observe()
        runs.append(np.concatenate([o["position_m"], o["rpy_rad"], o["linvel_mps"]]))
    assert sim.seed == 5
    np.testing.assert_array_equal(runs[0], runs[1])


def test_step_releases_the_gil():
    sim = tracksim.Simulation(SCENARIOS / "packbot_flat.toml")
    sim.set_twist(0.3, 0.0)
    t = threading.Thread(target=sim.step, args=(4000,))
    ticks = 0
    t.start()
    while t.is_alive():
        ticks += 1
        time.sleep(0.001)
    t.join()
    # With the GIL held for the whole 4000 steps the main thread could not tick in between.
    assert ticks > 20, ticks


def test_bad_file_raises_the_cli_message(write_scenario):
    p = write_scenario(SHORT_FLAT % "1.0" + "[outcome]\nmax_tilt_deg = -5.0\n", "bad.toml")
    with pytest.raises(tracksim.ScenarioError) as e:
        tracksim.Scenario(p)
    msg = str(e.value)
    assert str(p) in msg and "outcome.max_tilt_deg" in msg, msg
    assert isinstance(e.value, ValueError)
    # The same words as the command line's `error: ...`.
    r = run_cli("run", p, "--quiet", "--no-plot", "--out", p.parent / "out")
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip() == f"error: {msg}".strip()


def test_missing_file_and_unknown_key_are_scenario_errors(write_scenario):
    with pytest.raises(tracksim.ScenarioError, match="no_such.toml"):
        tracksim.Simulation("no_such.toml")
    p = write_scenario(SHORT_FLAT % "1.0" + "[outcome]\nsucess_x_m = 1.0\n")
    with pytest.raises(tracksim.ScenarioError, match="unknown key `sucess_x_m`: did you mean `success_x_m`"):
        tracksim.Scenario(p)


def test_terrain_heights_by_ray_casts():
    sim = tracksim.Simulation(SCENARIOS / "packbot_step.toml")
    h = sim.terrain_heights([0.0, 1.0, 1.5], [0.0, 0.0, 0.0])
    np.testing.assert_allclose(h, [0.0, 0.10, 0.10], atol=1e-4)


def test_submodules_are_reachable_after_import_tracksim():
    """Issue 64: `import tracksim; tracksim.dataset` was an AttributeError (it needed `import
    tracksim.dataset`); the submodules load on first use, and a name that is none stays an
    AttributeError."""
    assert tracksim.dataset.__name__ == "tracksim.dataset"
    assert callable(tracksim.dataset.ensemble)
    with pytest.raises(AttributeError):
        tracksim.no_such_module
