"""Shared helpers: the repository's folders and small scenario files written for a test."""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"
VEHICLES = ROOT / "vehicles"


def cli():
    """The `tracksim` binary: $TRACKSIM_BIN, else the release build in the target folder."""
    b = os.environ.get("TRACKSIM_BIN")
    if b:
        return b
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = target / "release" / "tracksim"
    if path.exists():
        return str(path)
    found = shutil.which("tracksim")
    if found is None:
        pytest.fail("no tracksim binary: set TRACKSIM_BIN or cargo build --release -p tracksim-cli")
    return found


def run_cli(*args, **kw):
    return subprocess.run([cli(), *map(str, args)], capture_output=True, text=True, **kw)


@pytest.fixture
def write_scenario(tmp_path):
    """Writes a scenario file (TOML text, `{vehicles}` replaced by the vehicles folder)."""

    def write(text, name="s.toml"):
        p = tmp_path / name
        p.write_text(text.replace("{vehicles}", VEHICLES.as_posix()))
        return p

    return write


SHORT_FLAT = """
description = "flat, short"
[vehicle]
file = "{vehicles}/packbot510.toml"
[terrain.ground]
friction = 0.6
[simulation]
duration_s = %s
"""
