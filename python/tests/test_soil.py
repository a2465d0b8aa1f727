"""Deformable soil (issue 30) from Python: sinkage and thrust in `observe()`, the ruts as an
array, and a soil key swept through `[randomize]` like any other."""

import numpy as np
import pytest

import tracksim
from conftest import SCENARIOS


def bekker_sinkage(p, b=0.075, n=1.1, k_c=0.99e3, k_phi=1528.43e3):
    """Bekker's sinkage under pressure p Pa (dry sand), m."""
    return (p / (k_c / b + k_phi)) ** (1.0 / n)


def test_sand_sinks_as_bekker_says_and_leaves_ruts():
    sim = tracksim.Simulation(SCENARIOS / "soil" / "packbot_dry_sand.toml")
    sim.set_twist(0.1, 0.0)
    sinkage, load = [], []
    for _ in range(100):
        sim.step(100)
        o = sim.observe()
        if sim.time >= 8.0:
            sinkage.append(o["sinkage_m"].mean())
            load.append(o["soil_normal_n"].sum())
    assert o["sinkage_m"].shape == (2,) and o["soil_thrust_n"].shape == (2,)
    # PackBot's 127 N on two tracks of 0.075 m; the loaded length is about 0.59 m.
    p = np.mean(load) / (2 * 0.59 * 0.075)
    assert np.mean(load) == pytest.approx(127.5, rel=0.05)
    assert np.mean(sinkage) == pytest.approx(bekker_sinkage(p), rel=0.2)
    ruts = sim.ruts()
    assert ruts.shape[1] == 6 and ruts.shape[0] > 1000
    # Cells of 1 cm, 1-3 mm deep where the tracks went (x from -0.35 to 1.4 m).
    assert np.all(ruts[:, 4] == pytest.approx(0.01))
    assert 0.001 < np.median(ruts[:, 3]) < 0.003
    assert ruts[:, 0].max() > 1.0


def test_rigid_ground_has_no_soil_outputs():
    sim = tracksim.Simulation(SCENARIOS / "packbot_flat.toml")
    sim.step(10)
    assert "sinkage_m" not in sim.observe()
    assert sim.ruts().shape == (0, 6)


def test_bad_soil_key_is_named(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(
        f'[vehicle]\nfile = "{(SCENARIOS.parent / "vehicles" / "packbot510.toml").as_posix()}"\n'
        '[terrain.ground]\n[terrain.ground.soil]\npreset = "wet_sand"\n'
    )
    with pytest.raises(ValueError, match=r"terrain\.ground\.soil\.preset"):
        tracksim.Scenario(f)
