"""N simulations stepped on Rust threads behind Gymnasium's ``VectorEnv`` API."""

from __future__ import annotations

import os
from typing import Any, Callable, Optional, Union

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from ._tracksim import Scenario, VecEnvCore
from .env import (ProgressReward, as_scenario, check_render_mode, learner_obs,
                  observation_space, plain_config, render_config)


class TracksimVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` copies of :class:`tracksim.TracksimEnv` stepped together on ``threads`` Rust
    threads with the GIL released (a pool of ``threads`` threads started at the first step and
    kept for every later step; setting :attr:`threads` starts a new one). Results are
    bit-identical whatever ``threads`` is: each environment is advanced by one thread and owns
    its state.

    Autoreset is Gymnasium's "next step" mode: the step after an episode ended resets that
    environment (its action is ignored, reward 0, not terminated) with the next seed of its
    sequence. ``reset(seed=s)`` seeds environment ``i`` with ``s + i``; ``reset(seed=[s0, s1,
    ...])`` gives each its own. ``infos`` holds arrays
    ``progress_m``, ``progress_delta_m``, ``effort``, ``seed``, ``autoreset`` and lists
    ``outcome``, ``reason`` ("" while running); on a course (a scenario with ``[course]``) also
    the arrays ``course_gates_passed``, ``course_repetitions_done``, ``course_faults``,
    ``course_penalty_s``, ``course_score_s`` (s) and the list ``course_status``, each
    environment's score so far (at its terminating step the ended episode's, closed as its
    ``summary.json`` has it).

    With ``config={"observation": "dict"}`` the observations are a dict of stacked arrays:
    ``"state"`` (num_envs, obs_dim) and one entry per sensor (num_envs, *shape), laid out as
    in :class:`tracksim.TracksimEnv`; with ``"learner"`` a dict of the learner's entries
    stacked (num_envs, *shape). ``flipper_action``, ``record_dir`` (each environment's
    episodes written as run folders at autoreset and on ``close()``) work as there.
    ``render_mode="rgb_array"``: :meth:`render` returns every environment's frame as one
    ``numpy.uint8`` array (num_envs, height, width, 3), rendered on the Rust threads;
    ``render_camera`` and ``render_size`` as in :class:`tracksim.TracksimEnv`.
    ``metadata["render_fps"]`` is the control rate. ``"human"`` is refused: watch one
    :class:`tracksim.TracksimEnv` with ``render_mode="human"``, or record episodes with
    ``record_dir``.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": ["rgb_array"]}

    def __init__(self, scenario: Union[str, os.PathLike, Scenario], num_envs: int,
                 threads: int = 1, config: Optional[dict] = None,
                 reward: Optional[Callable[..., Any]] = None,
                 render_mode: Optional[str] = None, render_camera: Optional[str] = None,
                 render_size: Optional[tuple] = None):
        if render_mode not in (None, "rgb_array"):
            check_render_mode(render_mode)
            raise ValueError(
                f"render_mode={render_mode!r}: the vector environment renders frames only "
                "(render_mode='rgb_array'); watch one tracksim.TracksimEnv with "
                "render_mode='human', or write episodes with config={'record_dir': DIR} and "
                "open them with `tracksim view`")
        self.render_mode = render_mode
        self.scenario = as_scenario(scenario)
        self.config = render_config(plain_config(config), render_camera, render_size)
        self.reward_fn = reward if reward is not None else ProgressReward()
        self._core = VecEnvCore(self.scenario, int(num_envs), self.scenario.file_seed,
                                int(threads), self.config)
        self.num_envs = int(num_envs)
        self.control_period_s = self._core.control_period_s
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.control_period_s}
        self.obs_names = self._core.obs_names
        self.dict_obs = self._core.observation == "dict"
        self.learner_spec = self._core.learner_obs_spec
        self.single_observation_space = observation_space(self._core)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (self._core.action_dim,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._np_random = None

    @property
    def threads(self) -> int:
        """Rust threads used per step (the pool's; another count replaces the pool at the
        next step)."""
        return self._core.threads

    @threads.setter
    def threads(self, t: int) -> None:
        self._core.threads = int(t)

    def reset(self, *, seed: Optional[Union[int, list]] = None, options: Optional[dict] = None):
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [int(s) for s in seed]
            obs = self._obs(self._core.reset(None, seeds))
            infos = {"seed": np.asarray(seeds, dtype=np.uint64),
                     "randomized": [self._core.randomized(i) for i in range(self.num_envs)]}
            return obs, infos
        if seed is not None:
            self._np_random, _ = gym.utils.seeding.np_random(int(seed))
        elif self._np_random is None:
            self._np_random, _ = gym.utils.seeding.np_random()
        base = int(seed) if seed is not None else int(self._np_random.integers(0, 2**62))
        obs = self._obs(self._core.reset(base))
        infos = {"seed": np.arange(self.num_envs, dtype=np.uint64) + np.uint64(base),
                 "randomized": [self._core.randomized(i) for i in range(self.num_envs)]}
        return obs, infos

    def step(self, actions):
        a = np.ascontiguousarray(np.asarray(actions, dtype=np.float32).reshape(
            self.num_envs, -1))
        state, d = self._core.step(a)
        obs = self._obs(state)
        rewards = np.asarray(self.reward_fn(state, d["progress_delta_m"], d["effort"],
                                            self.control_period_s), dtype=np.float64)
        rewards = np.where(d["autoreset"], 0.0, rewards)
        infos = {k: d[k] for k in ("progress_m", "progress_delta_m", "effort", "seed",
                                   "autoreset", "outcome", "reason")}
        # A course (``[course]``): every environment's score so far.
        infos.update({k: v for k, v in d.items() if k.startswith("course_")})
        return obs, rewards, d["terminated"].copy(), d["truncated"].copy(), infos

    def render(self):
        """With ``render_mode="rgb_array"`` every environment's frame of its current state as
        a ``numpy.uint8`` array (num_envs, height, width, 3); else None."""
        if self.render_mode == "rgb_array":
            return self._core.render()
        return None

    def close_extras(self, **kwargs):
        """Writes every environment's episode in progress as a run folder (``record_dir``)."""
        if getattr(self, "_core", None) is not None:
            self._core.flush_records()

    def _obs(self, state):
        """The observations of the state vectors ``state`` (with the sensors' stacked entries
        as a dict), or the learner's entries stacked."""
        if self.learner_spec:
            return learner_obs(self.learner_spec, state)
        if not self.dict_obs:
            return state
        obs = {"state": state}
        obs.update(self._core.sensor_obs())
        return obs

    def randomized(self, i: int) -> dict:
        """The ``[randomize]`` values of environment ``i``'s current episode."""
        return self._core.randomized(i)
