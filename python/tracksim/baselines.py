"""Scripted baselines of the task suite (:mod:`tracksim.tasks`): the first controller a
robotics engineer would write for each terrain, straight ahead at a fixed speed with a fixed
flipper pose, or a pose switched on the body's pitch. Their success rates over held-out seeds
are in docs/TASKS.md (``python/examples/baselines.py`` measures them).

A policy maps observation vectors (the default ``observation="vector"``, one row per
environment, or a single vector) to normalised twist actions ``[forward, yaw_rate,
flipper_left, flipper_right]`` in [-1, 1], under the environment's default scaling
(``max_forward_mps`` 0.5 m/s, ``flipper_range_rad`` +-60 deg) unless told otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

#: Index of the pitch (rad, REP 103: negative is nose up) in the observation vector.
PITCH = 1


@dataclass(frozen=True)
class ScriptedPolicy:
    """Straight ahead at ``forward_mps`` (no yaw rate) with both flippers at ``flipper_deg``
    (positive raises the tips); if ``tilted_flipper_deg`` is set, the flippers go to that
    angle while the body is pitched more than ``tilt_threshold_deg`` either way (on stairs or
    a slope) and back when it levels out.

    ``max_forward_mps`` and ``flipper_range_deg`` must match the environment's
    ``max_forward_mps`` and ``flipper_range_rad`` (the defaults do).
    """

    forward_mps: float
    flipper_deg: float
    tilted_flipper_deg: Optional[float] = None
    tilt_threshold_deg: float = 10.0
    max_forward_mps: float = 0.5
    flipper_range_deg: Sequence[float] = (-60.0, 60.0)

    def _flipper_action(self, deg):
        lo, hi = self.flipper_range_deg
        return np.clip(2.0 * (np.asarray(deg, dtype=np.float64) - lo) / (hi - lo) - 1.0, -1, 1)

    def __call__(self, obs) -> np.ndarray:
        """Actions for ``obs`` (shape ``(obs_dim,)`` or ``(n, obs_dim)``), float32, same
        leading shape, 4 entries each (twist and two flippers)."""
        obs = np.asarray(obs, dtype=np.float64)
        single = obs.ndim == 1
        obs = np.atleast_2d(obs)
        n = obs.shape[0]
        deg = np.full(n, float(self.flipper_deg))
        if self.tilted_flipper_deg is not None:
            tilted = np.abs(obs[:, PITCH]) > math.radians(self.tilt_threshold_deg)
            deg = np.where(tilted, float(self.tilted_flipper_deg), deg)
        a = np.zeros((n, 4), dtype=np.float32)
        a[:, 0] = np.clip(self.forward_mps / self.max_forward_mps, -1.0, 1.0)
        a[:, 2] = a[:, 3] = self._flipper_action(deg)
        return a[0] if single else a


#: The scripted baseline of every task id.
BASELINES = {
    # Full speed, flippers level: nothing in the way but the lane's edges.
    "tracksim/PackBotFlat-v0": ScriptedPolicy(forward_mps=0.4, flipper_deg=0.0),
    # Flippers raised to meet the battens' edges.
    "tracksim/PackBotBattens-v0": ScriptedPolicy(forward_mps=0.3, flipper_deg=35.0),
    "tracksim/PackBotBollards-v0": ScriptedPolicy(forward_mps=0.3, flipper_deg=35.0),
    # packbot_stairs' commands as a reflex: 35 deg to reach the first nosing, 20 deg on the flight.
    "tracksim/PackBotStairsUp-v0": ScriptedPolicy(forward_mps=0.3, flipper_deg=35.0,
                                                  tilted_flipper_deg=20.0),
    # Slowly, flippers lowered ahead of the tracks to carry the nose over the edges.
    "tracksim/PackBotStairsDown-v0": ScriptedPolicy(forward_mps=0.2, flipper_deg=-30.0),
    "tracksim/PackBotSteps-v0": ScriptedPolicy(forward_mps=0.3, flipper_deg=35.0),
    "tracksim/PackBotSlope-v0": ScriptedPolicy(forward_mps=0.3, flipper_deg=20.0),
}


def baseline(task_id: str) -> ScriptedPolicy:
    """The scripted baseline of ``task_id``; ``KeyError`` naming the ids for any other."""
    try:
        return BASELINES[task_id]
    except KeyError:
        raise KeyError(f"no baseline for {task_id!r}: the tasks are {', '.join(BASELINES)}") \
            from None
