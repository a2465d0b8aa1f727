"""The task suite: PackBot 510 with flippers on the terrains of the flipper-robot benchmark
FTR-Bench (flat, battens, bollards, stairs up, stairs down) plus steps and slopes, each a
bundled, randomised scenario file registered with Gymnasium under a ``tracksim/...-v0`` id on
``import tracksim``::

    env = gymnasium.make("tracksim/PackBotStairsUp-v0", config={"grid_shape": (8, 3)})

The scenario files are embedded in the compiled module and resolved by name
(:func:`tracksim.bundled_path`), so the ids work from an installed wheel. Success and failure
conditions, randomised ranges and the scripted baselines' success rates: docs/TASKS.md.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any, Callable, Optional

from ._tracksim import bundled_path

#: The environment's default control period (s): ``max_episode_steps`` of every id is the
#: task's duration over it. With another ``control_period_s`` in ``config`` the environment
#: still truncates at the scenario's duration; pass ``max_episode_steps=`` to
#: ``gymnasium.make`` so that Gymnasium's ``TimeLimit`` does not end episodes first.
DEFAULT_CONTROL_PERIOD_S = 0.05


@dataclass(frozen=True)
class Task:
    """One task of the suite.

    ``id``: the Gymnasium id; ``scenario``: the bundled scenario's name
    (:func:`tracksim.bundled_names`); ``terrain``: in words; ``duration_s``: the scenario's
    ``simulation.duration_s`` (the episode's length in simulated seconds, checked against the
    file by the tests).
    """

    id: str
    scenario: str
    terrain: str
    duration_s: float

    @property
    def max_episode_steps(self) -> int:
        """Control periods of the default length (:data:`DEFAULT_CONTROL_PERIOD_S`) in one
        episode."""
        return int(math.ceil(self.duration_s / DEFAULT_CONTROL_PERIOD_S - 1e-9))

    def path(self) -> str:
        """The scenario file (extracted from the installed package on first use)."""
        return bundled_path(self.scenario)


#: Every task, in the order of docs/TASKS.md.
TASKS = (
    Task("tracksim/PackBotFlat-v0", "tasks/packbot_flat", "flat lane 1.2 m wide", 15.0),
    Task("tracksim/PackBotBattens-v0", "tasks/packbot_battens", "three battens across the path",
         20.0),
    Task("tracksim/PackBotBollards-v0", "tasks/packbot_bollards",
         "three rows of posts (pile field)", 20.0),
    Task("tracksim/PackBotStairsUp-v0", "tasks/packbot_stairs_up", "four stairs up", 20.0),
    Task("tracksim/PackBotStairsDown-v0", "tasks/packbot_stairs_down",
         "four stairs down from a landing", 20.0),
    Task("tracksim/PackBotSteps-v0", "random/packbot_flippers_step_random", "one step up", 8.0),
    Task("tracksim/PackBotSlope-v0", "tasks/packbot_slope", "an incline of 10-40 deg", 20.0),
)

#: The tasks by id.
BY_ID = {t.id: t for t in TASKS}


def task(task_id: str) -> Task:
    """The task of ``task_id``; ``KeyError`` naming the ids for any other."""
    try:
        return BY_ID[task_id]
    except KeyError:
        raise KeyError(f"no task {task_id!r}: the tasks are {', '.join(BY_ID)}") from None


def _scenario(path: str, physics: Optional[dict]):
    """The scenario file ``path``, with the Scenario overrides ``physics`` (e.g.
    :data:`tracksim.TRAINING_PHYSICS`) if given."""
    from ._tracksim import Scenario

    return Scenario(path, **physics) if physics else path


def make_env(scenario: str, config: Optional[dict] = None,
             reward: Optional[Callable[..., Any]] = None, render_mode: Optional[str] = None,
             physics: Optional[dict] = None, **kwargs):
    """The entry point of every id: a :class:`tracksim.TracksimEnv` on the bundled scenario
    ``scenario`` (a name of :func:`tracksim.bundled_names`); ``physics`` are Scenario
    overrides (``tracksim.TRAINING_PHYSICS``: faster, shown equal on the steps tasks; default:
    the validated physics of the file); ``config``, ``reward``, ``render_mode`` and any other
    keyword pass through to it."""
    from .env import TracksimEnv

    return TracksimEnv(_scenario(bundled_path(scenario), physics), config=config,
                       reward=reward, render_mode=render_mode, **kwargs)


def register_all() -> None:
    """Registers every task's id with Gymnasium (done on ``import tracksim``; ids already
    registered are left alone)."""
    import gymnasium

    for t in TASKS:
        if t.id in gymnasium.registry:
            continue
        gymnasium.register(id=t.id, entry_point="tracksim.tasks:make_env",
                           vector_entry_point="tracksim.tasks:make_vector_env",
                           kwargs={"scenario": t.scenario},
                           max_episode_steps=t.max_episode_steps,
                           disable_env_checker=False)


def make_vector_env(num_envs: int, scenario: str, max_episode_steps: Optional[int] = None,
                    threads: Optional[int] = None, config: Optional[dict] = None,
                    reward: Optional[Callable[..., Any]] = None,
                    physics: Optional[dict] = None, **kwargs):
    """The vector entry point of every id: ``gymnasium.make_vec(id, num_envs)`` gives the
    native :class:`tracksim.TracksimVectorEnv` (``num_envs`` episodes on Rust threads, results
    bit-identical whatever ``threads`` is; default one thread per core, at most one per
    environment), not Gymnasium's ``SyncVectorEnv`` of Python environments.

    The native environment truncates at the scenario's duration. ``max_episode_steps``
    (Gymnasium passes the id's: the duration over the control period) is accepted when it does
    not end episodes earlier than that; a smaller one is refused with the fix, since the
    environments would otherwise run on past Gymnasium's time limit. ``render_mode`` and the
    other keywords of :class:`tracksim.TracksimVectorEnv` pass through."""
    from .vector import TracksimVectorEnv

    sc = _scenario(bundled_path(scenario), physics)
    if threads is None:
        threads = max(1, min(int(num_envs), os.cpu_count() or 1))
    env = TracksimVectorEnv(sc, num_envs, threads=threads, config=config, reward=reward,
                            **kwargs)
    if max_episode_steps is not None:
        steps = env.scenario.duration_s / env.control_period_s
        if max_episode_steps < math.floor(steps + 1e-9):
            env.close()
            raise ValueError(
                f"max_episode_steps={max_episode_steps}: the vector environment ends episodes "
                f"at the scenario's duration ({env.scenario.duration_s:g} s = {steps:g} "
                f"control periods of {env.control_period_s:g} s); shorten the episodes with "
                f"the scenario's simulation.duration_s, or use vectorization_mode='sync'")
    return env


def make_vector(task_id: str, num_envs: int, threads: int = 1, config: Optional[dict] = None,
                reward: Optional[Callable[..., Any]] = None, physics: Optional[dict] = None):
    """``num_envs`` episodes of the task ``task_id`` on Rust threads
    (:class:`tracksim.TracksimVectorEnv`; it truncates at the scenario's duration itself);
    ``physics`` as in :func:`make_env`."""
    from .vector import TracksimVectorEnv

    return TracksimVectorEnv(_scenario(task(task_id).path(), physics), num_envs,
                             threads=threads, config=config, reward=reward)
