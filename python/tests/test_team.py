"""Several robots in one world from Python (issue 40): the Simulation's robots selected by name,
each with its own controls and state, and the PettingZoo parallel environment, checked by
PettingZoo's own ``parallel_api_test`` and run to its end."""

import json

import numpy as np
import pytest
from pettingzoo.test import parallel_api_test

import tracksim
from tracksim.team_env import OBSERVATION_SIZE, TeamParallelEnv
from conftest import SCENARIOS, run_cli

CORRIDOR = SCENARIOS / "team" / "corridor_head_on.toml"
CONVOY = SCENARIOS / "team" / "convoy.toml"


def test_each_robot_is_selected_by_name_and_driven_on_its_own():
    sim = tracksim.Simulation(str(CORRIDOR))
    assert sim.robot_names == ["west", "east"] and sim.selected == "west"
    sim.select("east")
    sim.set_belt_speeds([0.3, 0.3])
    sim.step(1000)
    east = sim.observe()["position_m"][0]
    sim.select(0)
    west = sim.observe()["position_m"][0]
    # East drove 0.3 m towards -x in 1 s; west, not commanded, stayed at its start.
    assert east == pytest.approx(1.2 - 0.3, abs=0.01)
    assert west == pytest.approx(-1.2, abs=1e-3)
    with pytest.raises(KeyError, match="its robots: west, east"):
        sim.select("north")


def test_the_team_environment_passes_pettingzoos_parallel_api_test():
    env = TeamParallelEnv(tracksim.Scenario(str(CONVOY)), control_hz=5.0, max_time_s=4.0)
    parallel_api_test(env, num_cycles=30)


def test_a_team_episode_runs_to_its_end_with_one_entry_per_robot():
    env = TeamParallelEnv(str(CORRIDOR), control_hz=10.0)
    obs, infos = env.reset(seed=1)
    assert set(obs) == {"west", "east"} and obs["west"].shape == (OBSERVATION_SIZE,)
    # The neighbour is ahead of each robot, 2.4 m away, in its own heading frame.
    assert obs["west"][12] == pytest.approx(2.4, abs=0.01)
    assert obs["east"][12] == pytest.approx(2.4, abs=0.01)
    total = {a: 0.0 for a in env.possible_agents}
    steps = 0
    while env.agents:
        actions = {a: np.array([0.6, 0.0], dtype=np.float32) for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        for a, r in rewards.items():
            total[a] += r
        steps += 1
    # The corridor's 8 s at 10 Hz; nobody's outcome was decided, so all are truncated.
    assert steps == 80 and not any(terms.values()) and all(truncs.values())
    # Each drove at 0.3 m/s until they met near the middle, then they pushed: the progress
    # each was rewarded is its own distance along its heading.
    for a in env.possible_agents:
        assert total[a] == pytest.approx(infos[a]["progress_m"], abs=1e-6)
    assert 0.5 < total["west"] + total["east"] < 2.4 - 0.6


def test_a_team_file_runs_from_the_cli_with_a_folder_per_robot(tmp_path):
    p = run_cli("run", str(CONVOY), "--out", str(tmp_path), "--quiet", "--no-plot")
    assert p.returncode == 0, p.stderr
    team = json.loads((tmp_path / "team.json").read_text())
    assert team["outcome"] == "success" and team["rule"] == "all"
    assert [r["name"] for r in team["robots"]] == ["leader", "second", "third"]
    for r in team["robots"]:
        assert (tmp_path / r["name"] / "trajectory.csv").is_file()
        assert r["outcome"] == "success"


def test_a_one_robot_front_end_refuses_a_team_file():
    with pytest.raises(Exception, match="runs one robot"):
        tracksim.TracksimEnv(str(CORRIDOR))
