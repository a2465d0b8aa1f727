"""tracksim: tracked robots with real grousers (Okada et al., ICRA 2020) on Rapier, from Python.

- :class:`Scenario`: a scenario file, loaded and checked (``ScenarioError`` names file, key, fix);
- :class:`Simulation`: one simulation stepped with controls (GIL released while stepping), its
  state (``observe``) and its vehicle's sensors (``sensor_names``, ``sensors()``,
  ``sensor(name)``, ``sensor_axes(name)``);
- :class:`TracksimEnv`: a Gymnasium environment (``config={"observation": "dict"}`` adds the
  sensors to the observation); :class:`TracksimVectorEnv`: N of them stepped on Rust threads
  behind Gymnasium's ``VectorEnv`` API;
- :class:`TeamVectorEnv`: many worlds of several robots (``[[vehicles]]``) stepped together on
  Rust threads, the vector form of :class:`tracksim.team_env.TeamParallelEnv` (PettingZoo);
- :class:`ProgressReward`: the default reward (progress, tilt and effort penalties), replaceable;
- the task suite (:mod:`tracksim.tasks`, docs/TASKS.md): ``gymnasium.make("tracksim/PackBotFlat-v0")``
  and the other ids, registered on import; :mod:`tracksim.baselines` their scripted policies;
  :func:`bundled_path` finds a bundled scenario from the installed package.

Units are SI (m, s, rad); frames follow REP 103 (x forward, y left, z up).

``TRAINING_PHYSICS`` is the faster physics for learning PackBot tasks, as ``Scenario(path,
**TRAINING_PHYSICS)``: 2 solver iterations instead of 4. It is not the validated default:
BENCHMARKS.md ("Env steps per core") says what was shown equal (success rates and climbing
times of fixed policies over 100 held-out seeds of the steps tasks, flat-ground speed) and what
it does not keep (Quince needs its 8 iterations; the paper's Table IV is validated with the
default only).
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
    write_video,
)
from .env import ProgressReward, TracksimEnv

#: Scenario overrides of the training physics for PackBot tasks (BENCHMARKS.md "Env steps per
#: core": its speed-up and what was shown equal to the validated default).
TRAINING_PHYSICS = {"solver_iterations": 2}
#: The training physics with grousers clustered in fours (``okada2020_clustered``): about twice
#: the env steps per core of the validated default on flat ground, the same success rates on
#: the steps tasks, but climbs about 8 % slower (BENCHMARKS.md "Env steps per core").
TRAINING_PHYSICS_CLUSTERED = {"method": "okada2020_clustered", "solver_iterations": 2}
from .vector import TracksimVectorEnv
from .team_vector import TeamVectorEnv
from . import tasks as _tasks

_tasks.register_all()

__all__ = [
    "EnvCore",
    "ProgressReward",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "TRAINING_PHYSICS",
    "TRAINING_PHYSICS_CLUSTERED",
    "TracksimEnv",
    "TeamVectorEnv",
    "TracksimVectorEnv",
    "UnstableError",
    "VecEnvCore",
    "__version__",
    "bundled_names",
    "bundled_path",
    "write_video",
]


#: Submodules loaded on first use (``tracksim.dataset`` after ``import tracksim``, issue 64):
#: each needs packages of its own (pyarrow, Ray, PettingZoo) that ``import tracksim`` does not.
_LAZY_SUBMODULES = ("dataset", "baselines", "ray_vector", "ray_sweep", "ray_ensemble", "team_env")


def __getattr__(name):
    if name in _LAZY_SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

