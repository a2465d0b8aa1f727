"""``[randomize]`` in a file of several robots: the team environments draw per episode seed, a
sweep writes a folder per robot and their figures, Parquet per robot (docs/TEAMS.md)."""

import json

import pytest

import tracksim
from tracksim import dataset
from tracksim.team_env import TeamParallelEnv
from tracksim.team_vector import TeamVectorEnv
from conftest import SCENARIOS, run_cli

RACE = SCENARIOS / "random" / "team_race_step_random.toml"


@pytest.fixture
def short_race(tmp_path):
    """The random race cut to 1.5 s (the vehicle path made absolute)."""
    text = RACE.read_text().replace("duration_s = 14.0", "duration_s = 1.5").replace(
        'file = "../../vehicles/', f'file = "{(SCENARIOS.parent / "vehicles").as_posix()}/')
    p = tmp_path / "race.toml"
    p.write_text(text)
    return p


def test_each_episode_of_the_team_env_draws_from_its_seed():
    env = TeamParallelEnv(str(RACE))
    scenario = tracksim.Scenario(str(RACE))
    gaps = []
    for seed in (3, 4, 3):
        obs, infos = env.reset(seed=seed)
        drawn = scenario.sample(seed)
        assert infos["red"] == {"seed": seed, "randomized": drawn}
        assert infos["blue"]["randomized"] == drawn
        gap = drawn["lane_gap_m"]
        assert 1.2 <= gap <= 1.6
        # Observation entries 12, 13: the nearest robot in the robot's heading frame. Both face
        # +x, red at +gap/2 and blue at -gap/2: blue is gap to red's right, red gap to blue's left.
        assert obs["red"][12:14] == pytest.approx([0.0, -gap], abs=1e-4)
        assert obs["blue"][12:14] == pytest.approx([0.0, gap], abs=1e-4)
        gaps.append(gap)
    assert gaps[0] == gaps[2] != gaps[1]


def test_the_team_vector_env_reports_each_worlds_values():
    v = TeamVectorEnv(str(RACE), 3, threads=1)
    scenario = tracksim.Scenario(str(RACE))
    obs, infos = v.reset(seed=10)
    for i in range(3):
        drawn = v.randomized(i)
        assert drawn == scenario.sample(10 + i) == infos["blue"]["randomized"][i]
        assert obs["red"][i, 13] == pytest.approx(-drawn["lane_gap_m"], abs=1e-4)
    v.close()


def test_a_team_sweep_has_a_folder_and_figures_per_robot(tmp_path, short_race):
    lines = dataset.sweep(short_race, tmp_path / "s", runs=3, seed=5, jobs=2)
    assert [l["index"] for l in lines] == [0, 1, 2]
    for line in lines:
        run = tmp_path / "s" / line["dir"]
        assert [r["name"] for r in line["robots"]] == ["red", "blue"]
        assert line["progress_m"] is None and line["final_pose"] == [None] * 6
        assert line["params"] == tracksim.Scenario(short_race).sample(line["seed"])
        team = json.loads((run / "team.json").read_text())
        assert team["seed"] == line["seed"] and team["randomized"] == line["params"]
        for k, r in enumerate(line["robots"]):
            assert r["final_pose"][:3] == team["robots"][k]["final_pose"][:3]
            assert (run / r["name"] / "trajectory.csv").is_file()
        # Red (0.35 m/s) got farther than blue (0.30 m/s) in 1.5 s, each in its own lane.
        red, blue = line["robots"]
        assert red["progress_m"] > blue["progress_m"] > 0.3
        assert red["final_pose"][1] == pytest.approx(line["params"]["lane_gap_m"] / 2, abs=0.02)
    # `tracksim run FILE --seed S` writes a sweep run of seed S again, byte for byte.
    seed = lines[1]["seed"]
    p = run_cli("run", str(short_race), "--seed", str(seed), "--out", str(tmp_path / "r"),
                "--quiet", "--no-plot")
    assert p.returncode == 0, p.stderr
    for name in ("red", "blue"):
        assert (tmp_path / "r" / name / "trajectory.csv").read_bytes() == \
            (tmp_path / "s" / lines[1]["dir"] / name / "trajectory.csv").read_bytes()


def test_a_team_sweep_as_parquet_per_robot(tmp_path, short_race):
    pq = pytest.importorskip("pyarrow.parquet")
    dataset.sweep(short_race, tmp_path / "s", runs=2, seed=0)
    written = dataset.to_parquet(tmp_path / "s")
    assert len(written) == 2 * 2 + 1
    t = pq.read_table(tmp_path / "s" / "runs" / "run-000001" / "blue" / "trajectory.parquet")
    assert set(t.column("robot").to_pylist()) == {"blue"}
    assert set(t.column("seed").to_pylist()) == {1}
    m = pq.read_table(tmp_path / "s" / "manifest.parquet").to_pylist()
    assert [r["red.outcome"] for r in m] == ["completed", "completed"]
    assert m[1]["blue.final_y_m"] == pytest.approx(-m[1]["param.lane_gap_m"] / 2, abs=0.02)
    assert m[0]["final_x_m"] is None  # the world has no one pose
