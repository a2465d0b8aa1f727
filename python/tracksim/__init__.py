"""tracksim: tracked robots with real grousers (Okada et al., ICRA 2020) on Rapier, from Python.

- :class:`Scenario`: a scenario file, loaded and checked (``ScenarioError`` names file, key, fix);
- :class:`Simulation`: one simulation stepped with controls (GIL released while stepping), its
  state (``observe``) and its vehicle's sensors (``sensor_names``, ``sensors()``,
  ``sensor(name)``, ``sensor_axes(name)``);
- :class:`TracksimEnv`: a Gymnasium environment (``config={"observation": "dict"}`` adds the
  sensors to the observation); :class:`TracksimVectorEnv`: N of them stepped on Rust threads
  behind Gymnasium's ``VectorEnv`` API;
- :class:`ProgressReward`: the default reward (progress, tilt and effort penalties), replaceable;
- the task suite (:mod:`tracksim.tasks`, docs/TASKS.md): ``gymnasium.make("tracksim/PackBotFlat-v0")``
  and the other ids, registered on import; :mod:`tracksim.baselines` their scripted policies;
  :func:`bundled_path` finds a bundled scenario from the installed package.

Units are SI (m, s, rad); frames follow REP 103 (x forward, y left, z up).
"""

from ._tracksim import (
    EnvCore,
    Scenario,
    ScenarioError,
    Simulation,
    UnstableError,
    VecEnvCore,
    __version__,
    bundled_names,
    bundled_path,
)
from .env import ProgressReward, TracksimEnv
from .vector import TracksimVectorEnv
from . import tasks as _tasks

_tasks.register_all()

__all__ = [
    "EnvCore",
    "ProgressReward",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "TracksimEnv",
    "TracksimVectorEnv",
    "UnstableError",
    "VecEnvCore",
    "__version__",
    "bundled_names",
    "bundled_path",
]
