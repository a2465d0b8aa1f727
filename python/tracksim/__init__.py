"""tracksim: tracked robots with real grousers (Okada et al., ICRA 2020) on Rapier, from Python.

- :class:`Scenario`: a scenario file, loaded and checked (``ScenarioError`` names file, key, fix);
- :class:`Simulation`: one simulation stepped with controls (GIL released while stepping), its
  state (``observe``) and its vehicle's sensors (``sensor_names``, ``sensors()``,
  ``sensor(name)``, ``sensor_axes(name)``);
- :class:`TracksimEnv`: a Gymnasium environment (``config={"observation": "dict"}`` adds the
  sensors to the observation); :class:`TracksimVectorEnv`: N of them stepped on Rust threads
  behind Gymnasium's ``VectorEnv`` API;
- :class:`ProgressReward`: the default reward (progress, tilt and effort penalties), replaceable.

Units are SI (m, s, rad); frames follow REP 103 (x forward, y left, z up).

``TRAINING_PHYSICS`` is the faster physics for learning, as ``Scenario(path,
**TRAINING_PHYSICS)``: grousers clustered in fours (``okada2020_clustered``) and 2 solver
iterations. It is not the validated default: docs/LEARNING.md says what was shown equal (success
rates of policies on the steps tasks) and what it does not keep (the paper's Table IV with
Quince is validated with the default only).
"""

from ._tracksim import (
    EnvCore,
    Scenario,
    ScenarioError,
    Simulation,
    UnstableError,
    VecEnvCore,
    __version__,
)
from .env import ProgressReward, TracksimEnv

#: Scenario overrides of the training physics (about 1.8x the env steps per core of the
#: validated default on flat ground: BENCHMARKS.md "Env steps per core").
TRAINING_PHYSICS = {"method": "okada2020_clustered", "solver_iterations": 2}
from .vector import TracksimVectorEnv

__all__ = [
    "EnvCore",
    "ProgressReward",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "TRAINING_PHYSICS",
    "TracksimEnv",
    "TracksimVectorEnv",
    "UnstableError",
    "VecEnvCore",
    "__version__",
]
