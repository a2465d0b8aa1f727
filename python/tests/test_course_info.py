"""A course's score in the environments' info: the step's ``info["course"]`` (one env) and the
``course_*`` arrays (the vector env), as the run's ``summary.json`` scores it."""

import json

import numpy as np

import tracksim
from conftest import SCENARIOS, run_cli

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


def test_a_whole_episode_ends_with_the_score_the_cli_gives_its_recorded_controls(tmp_path):
    """Run to its end (the robot stalls at the first riser, its flippers level, until the
    scenario's 30 s run out, the course's time limit too: the run ends first, so the course is
    ``not_completed``, as a ``tracksim run`` that ends there says): the last step's
    ``info["course"]`` is the score ``tracksim run`` gives the episode's recorded controls, an
    independent front end of the same course, not the tracker's live ``running``."""
    rec = tmp_path / "episodes"
    env = tracksim.TracksimEnv(COURSE, config={"record_dir": rec})
    env.reset(seed=0)
    steps = 0
    while True:
        _, _, term, trunc, info = env.step(forward(env))
        steps += 1
        if term or trunc:
            break
    t = env._core.time
    env.close()
    c = info["course"]
    assert not c["finished"] and c["status"] == "not_completed", c
    assert c["gates_passed"] == 1 and abs(c["elapsed_s"] - 30.0) < 0.06, c
    (ep,) = [p for p in rec.iterdir() if p.is_dir()]
    out = tmp_path / "cli"
    r = run_cli("run", COURSE, "--commands", ep / "commands.toml", "--duration", repr(t),
                "--out", out, "--no-plot", "--quiet")
    assert r.returncode == 0, r.stderr
    cli = json.loads((out / "summary.json").read_text())["course"]
    for k in ("status", "finished", "gates_passed", "repetitions_done", "elapsed_s",
              "penalty_s"):
        assert cli[k] == c[k], (k, cli[k], c[k])
    assert cli["score"]["score_s"] == c["score_s"]
    assert cli["faults"] == c["faults"]


def test_the_vector_envs_terminating_step_reports_the_ended_episodes_score():
    """Gymnasium's next-step autoreset: the step that ends an episode carries that episode's
    score, closed as its recording has it (``not_completed``, not the live ``running``); the
    next step (the autoreset) a fresh course."""
    vec = tracksim.TracksimVectorEnv(COURSE, 1)
    vec.reset(seed=0)
    a = np.zeros((1,) + vec.single_action_space.shape, dtype=np.float32)
    a[0, 0] = 0.5
    while True:
        _, _, term, trunc, infos = vec.step(a)
        if term[0] or trunc[0]:
            break
    assert infos["course_status"][0] == "not_completed", infos
    assert infos["course_gates_passed"][0] == 1
    _, _, _, _, infos = vec.step(a)
    assert infos["autoreset"][0]
    assert infos["course_status"][0] == "running" and infos["course_gates_passed"][0] == 0
