"""Many team worlds stepped together: the vector form of :class:`tracksim.team_env.TeamParallelEnv`
(issue 40, docs/TEAMS.md).

``num_envs`` independent ``[[vehicles]]`` worlds are advanced one control period per ``step`` on
Rust threads with the GIL released (``tracksim::env::TeamVecEnv``, the threads of the
single-robot :class:`tracksim.TracksimVectorEnv`). The API is PettingZoo's parallel one with a
leading world axis: observations, rewards, terminations, truncations and infos are dicts keyed by
agent (robot name), each value an array over the worlds, e.g. ``obs["west"]`` of shape
``(num_envs, 15)``. Every agent has a row in every world at every step; ``infos[agent]["active"]``
says whether it acted (see :class:`TeamVectorEnv`).
"""

from __future__ import annotations

import os
from typing import Optional, Union

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from ._tracksim import Scenario, TeamVecEnvCore


class TeamVectorEnv:
    """``num_envs`` worlds of a ``[[vehicles]]`` scenario, each the world of a
    :class:`tracksim.team_env.TeamParallelEnv` with the same settings, stepped together on
    ``threads`` Rust threads (default: every core) with the GIL released. Results are
    bit-identical whatever ``threads`` is, and world ``i`` is bit-identical to a lone
    ``TeamParallelEnv`` reset with its seed and given its actions (the same library code).

    - ``reset(seed=s)`` seeds world ``i`` with ``s + i``; ``reset(seed=[s0, s1, ...])`` gives
      each its own; ``reset()`` draws a base seed from the generator seeded by the last integer
      seed. ``infos[agent]["seed"]`` holds the worlds' seeds, ``infos[agent]["randomized"]``
      each world's ``[randomize]`` values drawn from its seed (``randomized(i)`` after an
      autoreset).
    - ``step(actions)`` takes ``{agent: array (num_envs, 2)}`` (a twist ``[forward, yaw_rate]``
      in [-1, 1] per world; every agent's row is needed, an ended agent's is ignored) or one
      array ``(num_envs, len(possible_agents), 2)``; it returns ``obs`` ``{agent: float32
      (num_envs, 15)}``, ``rewards`` ``{agent: float64 (num_envs,)}``, ``terminations`` and
      ``truncations`` ``{agent: bool (num_envs,)}`` (True at the step the agent's episode ended)
      and ``infos`` ``{agent: {"active", "progress_m", "outcome", "reason", "autoreset",
      "seed", "t_s"}}`` (arrays or lists over the worlds).
    - An agent whose outcome is decided is braked, as in ``TeamParallelEnv``; until its world's
      episode ends it keeps being observed, with ``active`` False, reward 0 and neither flag.
    - Autoreset is Gymnasium's "next step" mode (``metadata["autoreset_mode"]``), per world: the
      step after every agent of a world ended resets that world with the next seed of its
      sequence; its actions are ignored, its rewards are 0, no flag is set, ``active`` is False
      and ``autoreset`` is True; its observations are the new episode's first.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        scenario: Union[str, os.PathLike, Scenario],
        num_envs: int,
        threads: Optional[int] = None,
        control_hz: float = 10.0,
        max_speed_mps: float = 0.5,
        max_yaw_rate_rad_s: float = 1.0,
        max_time_s: Optional[float] = None,
        render_mode: Optional[str] = None,
    ):
        if render_mode is not None:
            raise ValueError(
                f"render_mode {render_mode!r}: the team vector environment renders nothing; "
                "write an episode with `tracksim run` and `tracksim view`"
            )
        self.render_mode = None
        self.scenario = scenario if isinstance(scenario, Scenario) else Scenario(str(scenario))
        threads = int(threads) if threads else (os.cpu_count() or 1)
        self._core = TeamVecEnvCore(
            self.scenario,
            int(num_envs),
            self.scenario.file_seed,
            threads,
            float(control_hz),
            float(max_speed_mps),
            float(max_yaw_rate_rad_s),
            float(max_time_s) if max_time_s else None,
        )
        self.num_envs = int(num_envs)
        self.possible_agents = list(self._core.robot_names)
        #: Every agent has a row in every world at every step (see ``infos[agent]["active"]``).
        self.agents = list(self.possible_agents)
        self.control_period_s = self._core.control_period_s
        self._single_obs = spaces.Box(-np.inf, np.inf, (self._core.obs_dim,), np.float32)
        self._single_act = spaces.Box(-1.0, 1.0, (self._core.action_dim,), np.float32)
        self._obs = batch_space(self._single_obs, self.num_envs)
        self._act = batch_space(self._single_act, self.num_envs)
        self._np_random = None
        self.closed = False

    def randomized(self, i: int) -> dict:
        """The ``[randomize]`` values of world ``i``'s current episode (drawn from its seed)."""
        return self._core.randomized(i)

    @property
    def threads(self) -> int:
        """Rust threads used per step."""
        return self._core.threads

    @threads.setter
    def threads(self, t: int) -> None:
        self._core.threads = int(t)

    def single_observation_space(self, agent: str) -> spaces.Box:
        """One world's observation space of ``agent``: float32 (15,)."""
        return self._single_obs

    def single_action_space(self, agent: str) -> spaces.Box:
        """One world's action space of ``agent``: [-1, 1] (2,)."""
        return self._single_act

    def observation_space(self, agent: str) -> spaces.Box:
        """The batched observation space of ``agent``: (num_envs, 15)."""
        return self._obs

    def action_space(self, agent: str) -> spaces.Box:
        """The batched action space of ``agent``: (num_envs, 2)."""
        return self._act

    def _split(self, obs: np.ndarray) -> dict:
        return {a: np.ascontiguousarray(obs[:, k]) for k, a in enumerate(self.possible_agents)}

    def reset(self, seed: Optional[Union[int, list]] = None, options: Optional[dict] = None):
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = np.asarray([int(s) for s in seed], dtype=np.uint64)
            obs = self._core.reset(None, [int(s) for s in seeds])
        else:
            if seed is not None:
                self._np_random, _ = gym.utils.seeding.np_random(int(seed))
            elif self._np_random is None:
                self._np_random, _ = gym.utils.seeding.np_random()
            base = int(seed) if seed is not None else int(self._np_random.integers(0, 2**62))
            obs = self._core.reset(base)
            seeds = np.arange(self.num_envs, dtype=np.uint64) + np.uint64(base)
        drawn = [self._core.randomized(i) for i in range(self.num_envs)]
        infos = {a: {"seed": seeds.copy(), "randomized": drawn} for a in self.possible_agents}
        return self._split(obs), infos

    def _actions(self, actions) -> np.ndarray:
        if isinstance(actions, dict):
            missing = [a for a in self.possible_agents if a not in actions]
            if missing:
                raise KeyError(
                    f"no actions for {', '.join(missing)}: every agent needs a row per world "
                    "(an ended agent's is ignored)"
                )
            a = np.stack(
                [np.asarray(actions[a], dtype=np.float32).reshape(self.num_envs, -1)
                 for a in self.possible_agents],
                axis=1,
            )
        else:
            a = np.asarray(actions, dtype=np.float32)
        return np.ascontiguousarray(a)

    def step(self, actions):
        obs, d = self._core.step(self._actions(actions))
        rewards, terminations, truncations, infos = {}, {}, {}, {}
        world = {k: d[k] for k in ("autoreset", "seed", "t_s")}
        for k, a in enumerate(self.possible_agents):
            rewards[a] = np.ascontiguousarray(d["reward"][:, k])
            terminations[a] = np.ascontiguousarray(d["terminated"][:, k])
            truncations[a] = np.ascontiguousarray(d["truncated"][:, k])
            infos[a] = {
                "active": np.ascontiguousarray(d["active"][:, k]),
                "progress_m": np.ascontiguousarray(d["progress_m"][:, k]),
                "outcome": [row[k] for row in d["outcome"]],
                "reason": [row[k] for row in d["reason"]],
                **world,
            }
        return self._split(obs), rewards, terminations, truncations, infos

    def render(self):
        return None

    def close(self):
        self.closed = True
