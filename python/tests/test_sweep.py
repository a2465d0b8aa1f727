"""Sweeps: shards merge to the unsharded manifest, resume, grids, Parquet, the CLI's shards."""

import json

import pytest

import tracksim
from tracksim import dataset
from conftest import SCENARIOS, run_cli

STEP = SCENARIOS / "random" / "packbot_step_random.toml"
SHORT = 'duration_s = 1.0'


@pytest.fixture
def short_step(tmp_path):
    """The random step scenario cut to 1 s (the vehicle path made absolute)."""
    text = STEP.read_text().replace("duration_s = 8.0", SHORT).replace(
        'file = "../../vehicles/', f'file = "{(SCENARIOS.parent / "vehicles").as_posix()}/')
    p = tmp_path / "step.toml"
    p.write_text(text)
    return p


def test_two_shards_merge_to_the_unsharded_manifest(tmp_path, short_step):
    whole = dataset.sweep(short_step, tmp_path / "whole", runs=5, seed=3, jobs=2)
    assert [l["index"] for l in whole] == [0, 1, 2, 3, 4]
    a = dataset.sweep(short_step, tmp_path / "a", runs=5, seed=3, shard=(0, 2))
    b = dataset.sweep(short_step, tmp_path / "b", runs=5, seed=3, shard=(1, 2))
    assert [l["index"] for l in a] == [0, 2, 4] and [l["index"] for l in b] == [1, 3]
    assert dataset.merge([tmp_path / "a", tmp_path / "b"], tmp_path / "m") == 5
    assert (tmp_path / "m" / "manifest.jsonl").read_bytes() == \
        (tmp_path / "whole" / "manifest.jsonl").read_bytes()
    for line in dataset.load_manifest(tmp_path / "m"):
        assert (tmp_path / "m" / line["dir"] / "trajectory.csv").exists()
        assert line["params"] == tracksim.Scenario(short_step).sample(line["seed"])


def test_the_cli_shards_from_slurm_and_indexed_job_variables(tmp_path, short_step):
    env = {"PATH": "/usr/bin:/bin"}
    out = tmp_path / "shared"
    for task in ("0", "1"):
        r = run_cli("sweep", short_step, "--runs", "4", "--seed", "3", "--out", out, "--quiet",
                    env={**env, "SLURM_ARRAY_TASK_ID": task, "SLURM_ARRAY_TASK_COUNT": "2"})
        assert r.returncode == 0, r.stderr
    assert (out / "manifest-shard-1-of-2.jsonl").exists()
    r = run_cli("merge", out, "--out", out)
    assert r.returncode == 0 and "4 runs merged" in r.stdout, r.stdout + r.stderr
    whole = dataset.sweep(short_step, tmp_path / "whole", runs=4, seed=3)
    assert dataset.load_manifest(out) == whole
    r = run_cli("sweep", short_step, "--runs", "4", "--out", tmp_path / "k", "--quiet",
                env={**env, "JOB_COMPLETION_INDEX": "1"})
    assert r.returncode == 2 and "--shard-count" in r.stderr, r.stderr
    r = run_cli("sweep", short_step, "--runs", "4", "--seed", "3", "--out", tmp_path / "k",
                "--quiet", "--shard-count", "2", env={**env, "JOB_COMPLETION_INDEX": "1"})
    assert r.returncode == 0, r.stderr
    assert [l["index"] for l in dataset.load_manifest(
        tmp_path / "k" / "manifest-shard-1-of-2.jsonl")] == [1, 3]


def test_resume_skips_finished_runs_and_refuses_to_overwrite(tmp_path, short_step):
    out = tmp_path / "s"
    dataset.sweep(short_step, out, runs=2, seed=0)
    stamp = (out / "runs" / "run-000000" / "summary.json").stat().st_mtime_ns
    with pytest.raises(tracksim.ScenarioError, match="--resume"):
        dataset.sweep(short_step, out, runs=2, seed=0)
    lines = dataset.sweep(short_step, out, runs=3, seed=0, resume=True)
    assert len(lines) == 3
    assert (out / "runs" / "run-000000" / "summary.json").stat().st_mtime_ns == stamp
    assert not any(p.name.startswith(".") for p in (out / "runs").iterdir())


def test_grid_fixes_named_parameters(tmp_path, short_step):
    lines = dataset.sweep(short_step, tmp_path / "g", runs=1,
                          grid={"step_height_m": [0.07, 0.12], "friction": [0.5]})
    assert [(l["params"]["step_height_m"], l["params"]["friction"]) for l in lines] == \
        [(0.07, 0.5), (0.12, 0.5)]
    with pytest.raises(tracksim.ScenarioError, match="no such \\[randomize\\] parameter"):
        dataset.sweep(short_step, tmp_path / "h", runs=1, grid={"height": [0.1]})
    with pytest.raises(tracksim.ScenarioError, match="friction"):
        dataset.sweep(short_step, tmp_path / "i", runs=1, grid={"friction": [-1.0]})


def test_trajectories_as_parquet(tmp_path, short_step):
    pq = pytest.importorskip("pyarrow.parquet")
    dataset.sweep(short_step, tmp_path / "p", runs=2, seed=0)
    files = dataset.to_parquet(tmp_path / "p")
    t = pq.read_table(files[0])
    assert "t_s" in t.column_names and t.column("run")[0].as_py() == 0
    m = pq.read_table(tmp_path / "p" / "manifest.parquet")
    assert m.num_rows == 2 and "param.step_height_m" in m.column_names
    assert json.loads((tmp_path / "p" / "runs" / "run-000001" / "run.json").read_text())["index"] == 1
