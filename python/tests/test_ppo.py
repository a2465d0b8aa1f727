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


def test_ppo_checkpoint_loads_the_same_policy_and_watch_records_episodes(tmp_path):
    """The trained agent is saved; `--load` of it with `--steps 0` evaluates the same policy
    (its action at a fixed observation and its held-out return are equal); `--watch 1` writes
    the policy's episode as a run folder with an MP4 that `tracksim run --seed` replays."""
    common = ["--envs", "2", "--threads", "2", "--rollouts", "16", "--epochs", "1",
              "--mini-batches", "1", "--test-episodes", "1", "--bins", "2", "--json"]
    r = subprocess.run([sys.executable, EXAMPLE, "--steps", "64", "--out", tmp_path / "a",
                        "--watch", "1", *common], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    a = json.loads(r.stdout.strip().splitlines()[-1])
    ckpt = pathlib.Path(a["checkpoint"])
    assert ckpt.is_file() and ckpt.parent == tmp_path / "a"
    r = subprocess.run([sys.executable, EXAMPLE, "--steps", "0", "--load", ckpt, "--out",
                        tmp_path / "b", *common], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    b = json.loads(r.stdout.strip().splitlines()[-1])
    assert b["updates"] == 0 and b["env_steps"] == 0
    assert b["policy_at_zero"] == a["policy_at_zero"]
    assert b["learned_return"] == a["learned_return"]
    # A fresh agent (another seed, no checkpoint) acts otherwise: the comparison can fail.
    r = subprocess.run([sys.executable, EXAMPLE, "--steps", "16", "--seed", "3", "--out",
                        tmp_path / "c", *common], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    assert json.loads(r.stdout.strip().splitlines()[-1])["policy_at_zero"] != a["policy_at_zero"]
    (mp4,) = a["watched"]
    ep = pathlib.Path(mp4).parent
    assert ep.name == "seed10000-ep0"
    assert pathlib.Path(mp4).read_bytes()[4:8] == b"ftyp"
    assert sorted(p.name for p in ep.parent.iterdir()) == ["seed10000-ep0"]
    for f in ("summary.json", "trajectory.csv", "commands.toml"):
        assert (ep / f).is_file(), f
    r = subprocess.run([sys.executable, EXAMPLE, "--load", tmp_path / "missing.pickle",
                        "--steps", "0", "--out", tmp_path / "d"], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode != 0 and "--load" in r.stderr
