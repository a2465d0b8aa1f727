"""Ensemble verdicts from Python (issue 38): the same members and verdict as the CLI's
``tracksim run --ensemble``, and bad sizes refused naming the setting."""

import json

import pytest

from tracksim import dataset
from conftest import SCENARIOS, run_cli

STEP = SCENARIOS / "packbot_step.toml"


def test_ensemble_matches_the_cli_member_by_member(tmp_path):
    r = dataset.ensemble(STEP, members=3, out=tmp_path / "py", seed=5, jobs=2)
    assert r["verdict"] == "S 3/3" and r["success_fraction"] == 1.0
    assert [m["member"]["index"] for m in r["members"]] == [0, 1, 2]
    # Member 0 is the file as written; the others are perturbed within +-1 mm and +-0.05 deg.
    assert r["members"][0]["member"]["dx_m"] == 0.0
    for m in r["members"][1:]:
        assert abs(m["member"]["dx_m"]) <= 1e-3 and abs(m["member"]["dyaw_deg"]) <= 0.05
    assert (tmp_path / "py" / "member-002" / "trajectory.csv").is_file()
    p = run_cli("run", str(STEP), "--ensemble", "3", "--ensemble-seed", "5", "--out",
                str(tmp_path / "cli"), "--quiet")
    assert p.returncode == 0, p.stderr
    cli = json.loads((tmp_path / "cli" / "ensemble.json").read_text())
    for a, b in zip(r["members"], cli["members"]):
        assert a["member"] == b["member"]
        assert a["final_pose"] == b["final_pose"] and a["outcome_time_s"] == b["outcome_time_s"]
    for k in (0, 1, 2):
        name = f"member-{k:03d}/trajectory.csv"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_bad_ensemble_sizes_are_refused_naming_the_setting():
    with pytest.raises(ValueError, match="ensemble-start-mm"):
        dataset.ensemble(STEP, members=2, start_mm=500.0)
    with pytest.raises(ValueError, match="--ensemble"):
        dataset.ensemble(STEP, members=1)


def test_an_ensemble_of_several_robots_from_python(tmp_path):
    """A file of several robots (the bundled race): the winner's and each robot's verdicts,
    each robot's own start offsets, and the same members as the CLI's byte for byte."""
    race = SCENARIOS / "team" / "race_step.toml"
    r = dataset.ensemble(race, members=2, out=tmp_path / "py", seed=3, jobs=2)
    assert r["verdict"] == "S 2/2"
    assert r["winner_verdict"] == "red 2/2" and r["winners"] == [["red", 2]]
    assert [v["name"] for v in r["robot_verdicts"]] == ["red", "blue"]
    m1 = r["members"][1]
    red, blue = m1["member"]["robots"]
    assert red["dx_m"] == m1["member"]["dx_m"] and blue["dx_m"] != red["dx_m"]
    assert [x["name"] for x in m1["robots"]] == ["red", "blue"] and m1["winner"] == "red"
    assert any(k == "vehicles[1].vehicle.x_m" for k, _ in m1["keys"])
    p = run_cli("run", str(race), "--ensemble", "2", "--ensemble-seed", "3", "--out",
                str(tmp_path / "cli"), "--quiet")
    assert p.returncode == 0, p.stderr
    for robot in ("red", "blue"):
        name = f"member-001/{robot}/trajectory.csv"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
