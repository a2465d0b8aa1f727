"""The learning example runs end to end on a short budget and reports success rates."""

import json
import pathlib
import subprocess
import sys

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "learn_flippers.py"


def test_cross_entropy_example_on_a_short_budget():
    r = subprocess.run([sys.executable, EXAMPLE, "--pop", "2", "--elite", "1", "--iters", "1",
                        "--episodes", "1", "--test-episodes", "2", "--json"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout.strip().splitlines()[-1])
    for k in ("baseline_success", "learned_success"):
        assert res[k] in (0.0, 0.5, 1.0)
    assert len(res["weights"]) == 3
