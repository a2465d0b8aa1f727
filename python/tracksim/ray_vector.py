"""A vector env whose environments live in Ray actors: each actor holds a
:class:`tracksim.TracksimVectorEnv` of its share of the environments and steps it (in Rust, the
GIL released) when the driver sends it its rows of the actions.

    import ray, tracksim.ray_vector
    ray.init(num_cpus=2)          # or ray.init(address="auto") on a cluster
    env = tracksim.ray_vector.RayVectorEnv("scenarios/packbot_flat.toml", num_envs=8,
                                           num_actors=2)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(actions)   # actions (8, action_dim)

The results equal those of one ``TracksimVectorEnv(file, num_envs)`` reset with the same seed
(environment ``i`` is seeded ``seed + i`` whichever actor holds it, and each environment's
later episodes follow from its own seed), so the actors only change where the work runs. Each
step is one round trip to every actor: worth it when an actor's share of the step costs much
more than the round trip (BENCHMARKS.md, "Ray against the native vector env").
"""

from __future__ import annotations

import os
from typing import Optional, Union

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from ._tracksim import Scenario
from .env import as_scenario

#: ``infos`` entries of ``TracksimVectorEnv.step``: arrays, then lists of strings.
_ARRAYS = ("progress_m", "progress_delta_m", "effort", "seed", "autoreset")
_LISTS = ("outcome", "reason")


class _Shard:
    """One actor's environments (a ``TracksimVectorEnv``)."""

    def __init__(self, path: str, num_envs: int, threads: int, config: Optional[dict]):
        from .vector import TracksimVectorEnv

        self.env = TracksimVectorEnv(path, num_envs, threads=threads, config=config)

    def spaces(self):
        return self.env.single_observation_space, self.env.single_action_space

    def reset(self, seeds):
        obs, info = self.env.reset(seed=seeds)
        return obs, info["seed"]

    def step(self, actions):
        obs, rew, term, trunc, info = self.env.step(actions)
        return obs, rew, term, trunc, {k: info[k] for k in _ARRAYS + _LISTS}


class RayVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` environments of one scenario split over ``num_actors`` Ray actors (the first
    ones get one more when it does not divide), each a ``TracksimVectorEnv`` stepped on
    ``threads_per_actor`` Rust threads and reserving ``num_cpus_per_actor`` Ray CPUs.

    Same API and results as :class:`tracksim.TracksimVectorEnv` with the vector observation
    (``reset(seed=s)`` seeds environment ``i`` with ``s + i``; a list gives one seed each;
    "next step" autoreset; ``infos`` with ``progress_m``, ``progress_delta_m``, ``effort``,
    ``seed``, ``autoreset``, ``outcome``, ``reason``), with the default reward. Needs
    ``ray.init()`` first; ``close()`` ends the actors.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, scenario: Union[str, os.PathLike, Scenario], num_envs: int,
                 num_actors: int = 2, threads_per_actor: int = 1, config: Optional[dict] = None,
                 num_cpus_per_actor: float = 1.0):
        import ray

        self.actors = []
        if int(num_actors) < 1 or int(num_envs) < int(num_actors):
            raise ValueError(f"num_actors must be between 1 and num_envs ({num_envs}); got "
                             f"{num_actors}")
        if (config or {}).get("observation", "vector") != "vector":
            raise ValueError("RayVectorEnv supports config observation='vector' only; use "
                             "TracksimVectorEnv for the dict observation")
        path = as_scenario(scenario).path
        self.num_envs = int(num_envs)
        base, extra = divmod(self.num_envs, int(num_actors))
        self.sizes = [base + (k < extra) for k in range(int(num_actors))]
        actor = ray.remote(num_cpus=num_cpus_per_actor)(_Shard)
        self.actors = [actor.remote(path, n, int(threads_per_actor), config) for n in self.sizes]
        self._ray = ray
        obs_space, act_space = ray.get(self.actors[0].spaces.remote())
        self.single_observation_space = obs_space
        self.single_action_space = act_space
        self.observation_space = batch_space(obs_space, self.num_envs)
        self.action_space = batch_space(act_space, self.num_envs)
        self._np_random = None

    def _split(self, rows):
        out, i = [], 0
        for n in self.sizes:
            out.append(rows[i:i + n])
            i += n
        return out

    def reset(self, *, seed=None, options: Optional[dict] = None):
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [int(s) for s in seed]
            if len(seeds) != self.num_envs:
                raise ValueError(f"reset(seed=list): {len(seeds)} seeds for {self.num_envs} "
                                 "environments; give one per environment or an int")
        else:
            if seed is not None:
                self._np_random, _ = gym.utils.seeding.np_random(int(seed))
            elif self._np_random is None:
                self._np_random, _ = gym.utils.seeding.np_random()
            base = int(seed) if seed is not None else int(self._np_random.integers(0, 2**62))
            seeds = [base + i for i in range(self.num_envs)]
        parts = self._ray.get([a.reset.remote(s) for a, s in zip(self.actors,
                                                                  self._split(seeds))])
        obs = np.concatenate([p[0] for p in parts])
        return obs, {"seed": np.concatenate([p[1] for p in parts])}

    def step(self, actions):
        a = np.asarray(actions, dtype=np.float32).reshape(self.num_envs, -1)
        parts = self._ray.get([act.step.remote(x) for act, x in zip(self.actors,
                                                                     self._split(a))])
        obs = np.concatenate([p[0] for p in parts])
        rew = np.concatenate([p[1] for p in parts])
        term = np.concatenate([p[2] for p in parts])
        trunc = np.concatenate([p[3] for p in parts])
        infos = {k: np.concatenate([p[4][k] for p in parts]) for k in _ARRAYS}
        for k in _LISTS:
            infos[k] = [s for p in parts for s in p[4][k]]
        return obs, rew, term, trunc, infos

    def close(self, **kwargs):
        for a in getattr(self, "actors", []):
            self._ray.kill(a)
        self.actors = []
