"""A course's score in the environments' info: the step's ``info["course"]`` (one env) and the
``course_*`` arrays (the vector env), as the run's ``summary.json`` scores it."""

import numpy as np

import tracksim
from conftest import SCENARIOS

COURSE = SCENARIOS / "course_stairs.toml"
# The course's first gate (its start line) is crossed forwards at x = 0.2 m; the robot starts
# at x = 0 heading +x, so progress along the start heading is its x.
START_LINE_M = 0.2


def forward(env, fraction=0.5):
    """Straight ahead at ``fraction`` of the top speed, flippers at their action's centre."""
    a = np.zeros(env.action_space.shape, dtype=np.float32)
    a[0] = fraction
    return a


def test_the_course_score_follows_the_robot_over_the_start_line():
    env = tracksim.TracksimEnv(COURSE)
    env.reset(seed=0)
    seen = []
    for _ in range(60):
        _, _, term, trunc, info = env.step(forward(env))
        c = info["course"]
        seen.append((info["progress_m"], c["gates_passed"]))
        assert c["name"] == "stairs to the landing" and c["gates_total"] == 2
        assert c["status"] == "running" and not c["finished"], c
        # The course clock is the episode's (no reset), the score its time plus penalties.
        assert abs(c["elapsed_s"] - info["t_s"]) < 1e-9, (c, info["t_s"])
        assert c["faults"] == {"reset": 0, "tip_over": 0, "touch": 0}
        assert c["penalty_s"] == 0.0
        assert abs(c["score_s"] - c["elapsed_s"]) < 1e-9
        assert c["time_limit_s"] == 30.0
        assert not (term or trunc)
    # Gate 1 counts once the body is past the line, never before (a 10 mm band either side
    # for the sampling of the crossing within a 50 ms period at <= 0.2 m/s).
    for progress, passed in seen:
        if progress < START_LINE_M - 0.01:
            assert passed == 0, seen
        if progress > START_LINE_M + 0.01:
            assert passed == 1, seen
    assert seen[-1][1] == 1 and seen[0][1] == 0, seen
    assert info["course"]["next_gate"] == 1


def test_the_vector_env_reports_each_environments_course_score():
    n = 2
    vec = tracksim.TracksimVectorEnv(COURSE, n)
    lone = tracksim.TracksimEnv(COURSE)
    vec.reset(seed=7)
    lone.reset(seed=7)
    for _ in range(40):
        _, _, _, _, infos = vec.step(np.stack([forward(lone)] * n))
        _, _, _, _, info = lone.step(forward(lone))
        c = info["course"]
        # Environment 0 has the lone env's seed and actions: the same score.
        assert infos["course_gates_passed"][0] == c["gates_passed"]
        assert infos["course_score_s"][0] == c["score_s"]
        assert infos["course_status"][0] == c["status"]
    for k in ("course_gates_passed", "course_repetitions_done", "course_faults",
              "course_penalty_s", "course_score_s"):
        assert infos[k].shape == (n,), k
    assert list(infos["course_gates_passed"]) == [1, 1]
    assert list(infos["course_faults"]) == [0, 0]


def test_no_course_no_course_info():
    env = tracksim.TracksimEnv(SCENARIOS / "packbot_flat.toml")
    env.reset(seed=0)
    info = env.step(forward(env))[-1]
    assert "course" not in info
    vec = tracksim.TracksimVectorEnv(SCENARIOS / "packbot_flat.toml", 2)
    vec.reset(seed=0)
    infos = vec.step(np.stack([forward(env)] * 2))[-1]
    assert not [k for k in infos if k.startswith("course")]
