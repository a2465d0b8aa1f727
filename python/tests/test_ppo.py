"""The PPO example (skrl, JAX backend) runs end to end on a tiny budget: a few PPO updates,
evaluation of the learned policy and of the scripted baseline on held-out seeds, the learning
curve written (CSV and PNG). Whether it learns is measured in docs/LEARNING.md, not here."""

import csv
import json
import pathlib
import subprocess
import sys

import pytest

pytest.importorskip("skrl")
pytest.importorskip("jax")

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "train_ppo.py"


def test_ppo_example_on_a_tiny_budget(tmp_path):
    # 4 envs x 16 rollout steps = 64 samples per update; 800 env steps = 200 vector steps =
    # 12 updates, and every env ends at least one episode (8 s = 160 steps at most).
    r = subprocess.run([sys.executable, EXAMPLE, "--steps", "800", "--envs", "4", "--threads",
                        "2", "--rollouts", "16", "--epochs", "2", "--mini-batches", "2",
                        "--test-episodes", "2", "--bins", "4", "--out", tmp_path, "--json"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    res = json.loads(r.stdout.strip().splitlines()[-1])
    # Whole updates: 13 x 64 = 832 env-step calls, of which one per ended episode is the
    # autoreset step (a reset, no physics: not counted as an env step).
    assert res["updates"] == 13
    assert res["train_episodes"] >= 4
    assert 832 - res["train_episodes"] <= res["env_steps"] <= 832
    for k in ("baseline_success", "learned_success"):
        assert res[k] in (0.0, 0.5, 1.0)
    png = pathlib.Path(res["png"])
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.DictReader(open(res["csv"])))
    assert rows and res["train_episodes"] == sum(int(row["episodes"]) for row in rows)
    for row in rows:
        assert 0.0 <= float(row["success_rate"]) <= 1.0


def test_ppo_example_refuses_an_unknown_task(tmp_path):
    r = subprocess.run([sys.executable, EXAMPLE, "--task", "tracksim/NoSuchTask-v0",
                        "--out", tmp_path], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0
    assert "--task" in r.stderr and "tracksim/NoSuchTask-v0" in r.stderr


def test_ppo_example_takes_a_task_by_gymnasium_id():
    """`--task ID` resolves a registered id to its env's scenario (the task suite's
    `tracksim/PackBotSteps-v0` once registered; a test id here)."""
    import gymnasium as gym

    sys.path.insert(0, str(EXAMPLE.parent))
    try:
        import train_ppo
    finally:
        sys.path.remove(str(EXAMPLE.parent))
    gym.register("tracksim_test/Steps-v0", entry_point="tracksim:TracksimEnv",
                 kwargs={"scenario": str(train_ppo.DEFAULT_TASK)})
    try:
        sc = train_ppo.resolve_task("tracksim_test/Steps-v0")
    finally:
        del gym.registry["tracksim_test/Steps-v0"]
    assert pathlib.Path(sc.path).resolve() == train_ppo.DEFAULT_TASK.resolve()
