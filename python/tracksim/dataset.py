"""Datasets from sweeps: run a (sharded) sweep, merge shards, read the manifest, and convert
trajectories to Parquet (with pyarrow, installed separately: ``pip install pyarrow``).

A sweep folder holds ``runs/run-NNNNNN/`` (``summary.json``, ``trajectory.csv``, ``run.json``)
and ``manifest.jsonl`` (or ``manifest-shard-I-of-N.jsonl`` for a shard): one JSON object per
run with ``index``, ``seed``, ``params`` (the ``[randomize]`` values), ``outcome``, ``reason``,
``outcome_time_s``, ``sim_time_s``, ``progress_m``, ``distance_m``, ``final_pose``,
``max_tilt_rad``. A scenario of several robots (``[[vehicles]]``) writes each robot's folder
``runs/run-NNNNNN/NAME/`` and ``team.json``; its line's outcome is the world's, its
``progress_m``, ``distance_m``, ``final_pose`` and ``max_tilt_rad`` are ``None``, and ``robots``
lists each robot's ``name``, ``outcome``, ``reason``, ``outcome_time_s``, ``progress_m``,
``distance_m``, ``final_pose``, ``max_tilt_rad``.
"""

from __future__ import annotations

import json
import os
import pathlib
from typing import Dict, Iterable, List, Optional, Sequence, Tuple, Union

from . import _tracksim
from .env import as_scenario

PathLike = Union[str, os.PathLike]


def sweep(scenario, out: PathLike, runs: int = 10, seed: Optional[int] = None,
          grid: Optional[Dict[str, Sequence[float]]] = None,
          shard: Optional[Tuple[int, int]] = None, jobs: int = 1,
          resume: bool = False) -> List[dict]:
    """Runs the sweep (or shard ``(index, count)`` of it) into ``out``, as ``tracksim sweep``;
    returns the shard's manifest lines."""
    axes = [(k, [float(v) for v in vs]) for k, vs in (grid or {}).items()]
    lines = _tracksim.sweep(as_scenario(scenario), os.fspath(out), int(runs),
                            None if seed is None else int(seed), axes, shard, int(jobs),
                            bool(resume))
    return [json.loads(s) for s in lines]


def ensemble(scenario, members: int = 16, out: Optional[PathLike] = None, seed: int = 0,
             start_mm: float = 1.0, yaw_deg: float = 0.05, keep_order: bool = False,
             jobs: int = 0, shard: Optional[Tuple[int, int]] = None) -> dict:
    """Runs the scenario (at its file's seed) as an ensemble of ``members`` perturbed runs, as
    ``tracksim run --ensemble`` (docs/ENSEMBLE.md): member 0 as written, the others with the
    start moved up to ``start_mm`` in x and y, turned up to ``yaw_deg`` and the solver's order
    changed. Returns the report: ``verdict`` ("S 16/16", "marginal 9/16"),
    ``success_fraction``, ``success_time_s`` (min, median, max) and ``members`` (each with its
    perturbation, outcome, final pose and the file keys that reproduce it). A file of several
    robots moves each robot's start on its own; the report adds ``winner_verdict``,
    ``winners``, ``robot_verdicts`` and per member ``winner`` and ``robots``.

    ``shard=(i, n)`` runs only the members ``k`` with ``k % n == i`` (one task of a distributed
    ensemble, see ``tracksim.ray_ensemble``); its report holds those members, and
    :func:`ensemble_merge` joins the shards' reports."""
    text = _tracksim.ensemble(as_scenario(scenario), int(members),
                              None if out is None else os.fspath(out), int(seed),
                              float(start_mm), float(yaw_deg), bool(keep_order), int(jobs),
                              None if shard is None else (int(shard[0]), int(shard[1])))
    return json.loads(text)


def ensemble_merge(reports: Iterable[dict], out: Optional[PathLike] = None) -> dict:
    """Joins the reports of an ensemble's shards (:func:`ensemble` with ``shard``) into the
    ensemble's report, verdict and spreads recomputed; writes ``ensemble.json`` and
    ``ensemble.csv`` into ``out`` if given. Shards of different ensembles, or a member in two
    shards, are refused with a ``ValueError``."""
    text = _tracksim.ensemble_merge([json.dumps(r) for r in reports],
                                    None if out is None else os.fspath(out))
    return json.loads(text)


def merge(dirs: Iterable[PathLike], out: PathLike) -> int:
    """Merges sweep folders into ``out`` (runs and ``manifest.jsonl``); returns the run count."""
    return _tracksim.merge([os.fspath(d) for d in dirs], os.fspath(out))


def load_manifest(path: PathLike) -> List[dict]:
    """The manifest lines of a sweep folder (its ``manifest.jsonl``) or of a ``.jsonl`` file."""
    p = pathlib.Path(path)
    if p.is_dir():
        p = p / "manifest.jsonl"
    return [json.loads(line) for line in p.read_text().splitlines() if line.strip()]


_POSE = ("x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad")


def to_parquet(sweep_dir: PathLike) -> List[pathlib.Path]:
    """Writes ``trajectory.parquet`` beside every run's ``trajectory.csv`` (same columns, plus
    ``run`` and ``seed``; a run of several robots: beside each robot's ``NAME/trajectory.csv``,
    plus ``robot``), and ``manifest.parquet`` (params flattened to ``param.NAME``, final pose to
    ``final_x_m`` ..., a robot's figures to ``NAME.outcome``, ``NAME.final_x_m`` ...)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    root = pathlib.Path(sweep_dir)
    lines = load_manifest(root)
    written = []
    for line in lines:
        robots = [r["name"] for r in line.get("robots", [])]
        for name in robots or [None]:
            csv = root / line["dir"] / (name or "") / "trajectory.csv"
            if not csv.exists():
                continue
            t = pacsv.read_csv(csv)
            t = t.append_column("run", pa.array([line["index"]] * t.num_rows, pa.int64()))
            t = t.append_column("seed", pa.array([line["seed"]] * t.num_rows, pa.uint64()))
            if name is not None:
                t = t.append_column("robot", pa.array([name] * t.num_rows, pa.string()))
            dst = csv.with_suffix(".parquet")
            pq.write_table(t, dst)
            written.append(dst)
    rows = []
    for line in lines:
        row = {k: v for k, v in line.items() if k not in ("params", "final_pose", "robots")}
        row.update({f"param.{k}": v for k, v in line["params"].items()})
        for k, v in zip(_POSE, line["final_pose"]):
            row[f"final_{k}"] = v
        for r in line.get("robots", []):
            name = r["name"]
            row.update({f"{name}.{k}": v for k, v in r.items()
                        if k not in ("name", "final_pose")})
            for k, v in zip(_POSE, r["final_pose"]):
                row[f"{name}.final_{k}"] = v
        rows.append(row)
    pq.write_table(pa.Table.from_pylist(rows), root / "manifest.parquet")
    written.append(root / "manifest.parquet")
    return written
