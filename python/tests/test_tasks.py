"""The task suite (tracksim.tasks): every id makes with gymnasium.make and passes check_env,
resets deterministically with its randomised values in their ranges, the files come from the
installed package, and the scripted baseline ends episodes as the terrain says it must."""

import math
import os
import pathlib
import subprocess
import sys

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tracksim
from tracksim.baselines import BASELINES, baseline
from tracksim.tasks import TASKS, task

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

IDS = [t.id for t in TASKS]


def test_the_suite_is_registered_on_import():
    assert IDS == ["tracksim/PackBotFlat-v0", "tracksim/PackBotBattens-v0",
                   "tracksim/PackBotBollards-v0", "tracksim/PackBotStairsUp-v0",
                   "tracksim/PackBotStairsDown-v0", "tracksim/PackBotSteps-v0",
                   "tracksim/PackBotSlope-v0"]
    for t in TASKS:
        spec = gymnasium.spec(t.id)
        assert spec.max_episode_steps == round(t.duration_s / 0.05)
        assert t.id in BASELINES
    with pytest.raises(KeyError, match="PackBotFlat-v0"):
        task("tracksim/PackBotFlatt-v0")


@pytest.mark.parametrize("task_id", IDS)
def test_every_id_makes_and_passes_check_env(task_id):
    env = gymnasium.make(task_id, config={"grid_shape": (3, 3)})
    assert env.spec.id == task_id
    inner = env.unwrapped
    assert isinstance(inner, tracksim.TracksimEnv)
    assert inner.observation_space.shape == (10 + 2 + 4 + 9,)  # the config passed through
    # The file's duration is the task's (max_episode_steps is computed from it).
    assert inner.scenario.info(0)["duration_s"] == pytest.approx(task(task_id).duration_s)
    check_env(inner, skip_render_check=True)


@pytest.mark.parametrize("task_id", IDS)
def test_reset_is_deterministic_and_randomised_within_ranges(task_id):
    env = gymnasium.make(task_id)
    obs_a, info_a = env.reset(seed=10007)
    obs_b, info_b = env.reset(seed=10007)
    np.testing.assert_array_equal(obs_a, obs_b)
    assert info_a["randomized"] == info_b["randomized"]
    a = np.zeros(env.action_space.shape, np.float32)
    a[0] = 0.5
    steps_a = [env.step(a)[0] for _ in range(3)]
    env.reset(seed=10007)
    steps_b = [env.step(a)[0] for _ in range(3)]
    np.testing.assert_array_equal(np.array(steps_a), np.array(steps_b))
    _, info_c = env.reset(seed=10008)
    assert info_c["randomized"] != info_a["randomized"]
    if tomllib is None:
        pytest.skip("tomllib needs Python 3.11 to read the ranges")
    path = pathlib.Path(env.unwrapped.scenario.path)
    ranges = tomllib.loads(path.read_text())["randomize"]
    assert set(ranges) == set(info_a["randomized"])
    for seed in range(10000, 10020):
        values = env.unwrapped.scenario.sample(seed)
        for name, table in ranges.items():
            lo, hi = table["uniform"]
            assert lo <= values[name] <= hi, (task_id, seed, name, values[name])


def test_tasks_resolve_from_the_installed_package(tmp_path):
    """From a folder outside the source tree, with a fresh data folder: the id's file is the
    package's own, extracted there (with its vehicle)."""
    code = ("import gymnasium, tracksim; "
            "e = gymnasium.make('tracksim/PackBotBattens-v0'); e.reset(seed=1); "
            "print(e.unwrapped.scenario.path)")
    env = dict(os.environ, TRACKSIM_DATA_DIR=str(tmp_path / "data"))
    env.pop("PYTHONPATH", None)
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    path = pathlib.Path(r.stdout.strip())
    assert path == tmp_path / "data" / "scenarios" / "tasks" / "packbot_battens.toml"
    assert (tmp_path / "data" / "vehicles" / "packbot510_flippers.toml").is_file()
    with pytest.raises(ValueError, match="bundled_names"):
        tracksim.bundled_path("tasks/no_such_task")
    assert "tasks/packbot_stairs_down" in tracksim.bundled_names()


def run_episode(task_id, seed):
    env = gymnasium.make(task_id)
    obs, info = env.reset(seed=seed)
    policy = baseline(task_id)
    while True:
        obs, _, term, trunc, step_info = env.step(policy(obs))
        if term or trunc:
            return info["randomized"], step_info


def test_flat_baseline_succeeds_straight_and_leaves_the_lane_when_skewed():
    """Straight ahead from the start pose: the body's origin crosses the lane's edge (0.6 m
    from its centre line) before x = 3 m exactly when |y0 + 3 m tan(yaw0)| > 0.6 m (with
    margins of 0.15 m either side for the drift while the tracks spin up)."""
    sc = tracksim.Scenario(tracksim.bundled_path("tasks/packbot_flat"))

    def lateral_at_goal(seed):
        v = sc.sample(seed)
        return abs(v["start_y_m"] + 3.0 * math.tan(math.radians(v["start_yaw_deg"])))

    seeds = range(20000, 20200)
    inside = next(s for s in seeds if lateral_at_goal(s) < 0.3)
    outside = next(s for s in seeds if lateral_at_goal(s) > 0.75)
    _, info = run_episode("tracksim/PackBotFlat-v0", inside)
    assert info["outcome"] == "success", info
    _, info = run_episode("tracksim/PackBotFlat-v0", outside)
    assert info["outcome"] == "failure" and "left the terrain" in info["reason"], info


def test_make_vec_gives_the_native_vector_env_with_the_ids_episodes():
    """`gymnasium.make_vec(id, n)` is the registered vector entry point: the native vector env
    on Rust threads (not a SyncVectorEnv of Python envs), stepping the same episodes as
    `tasks.make_vector` with the same seeds, bit for bit."""
    import gymnasium

    venv = gymnasium.make_vec("tracksim/PackBotSteps-v0", 3)
    assert isinstance(venv.unwrapped, tracksim.TracksimVectorEnv)
    assert venv.num_envs == 3 and venv.unwrapped.threads >= 1
    ref = tracksim.tasks.make_vector("tracksim/PackBotSteps-v0", 3, threads=1)
    a, _ = venv.reset(seed=5)
    b, _ = ref.reset(seed=5)
    act = np.tile(np.array([0.6, 0.0, 0.2, 0.2], np.float32), (3, 1))
    for _ in range(10):
        a, ra, *_ = venv.step(act)
        b, rb, *_ = ref.step(act)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(ra, rb)
    venv.close()
    ref.close()


def test_make_vec_refuses_a_time_limit_shorter_than_the_scenario():
    with pytest.raises(ValueError, match="max_episode_steps=5: .*duration"):
        gymnasium.make_vec("tracksim/PackBotSteps-v0", 2, max_episode_steps=5)
