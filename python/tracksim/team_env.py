"""Several robots in one world as a PettingZoo ``ParallelEnv`` (issue 40, docs/TEAMS.md).

A scenario with ``[[vehicles]]`` is one world; each robot is an agent named after it. Every
control period each agent's action, a twist ``[forward, yaw_rate]`` in ``[-1, 1]`` scaled by
``max_speed_mps`` and ``max_yaw_rate_rad_s``, is given to its robot; the world steps; each agent
observes itself and its nearest neighbour, and is rewarded its progress along its start heading.
A file with ``[randomize]`` draws
its values from each episode's seed (``reset(seed=s)``; ``tracksim run FILE --seed s`` runs the
same world), reported in the reset's ``infos[agent]["randomized"]``. An agent is terminated when its robot's own outcome is decided (``[vehicles.outcome]``: a
success, or a failure such as tipping over) and braked from then on; every agent is truncated at
the scenario's duration. Observations, rewards, terminations, truncations and infos are dicts
keyed by robot name, as PettingZoo's parallel API asks (``pettingzoo.test.parallel_api_test``
passes: ``python/tests/test_team.py``). The world, the observations and the rewards are the
library's (``tracksim::env::TeamEnv``), the same as in each world of
:class:`tracksim.team_vector.TeamVectorEnv`.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from ._tracksim import Scenario, TeamEnvCore

#: Observation entries, in order (float32): the robot's position relative to its start in its
#: start frame (x forward, y left, z up: 3, m), roll, pitch, yaw relative to its start heading
#: (3, rad), its velocity in its heading frame (forward, left, up: 3, m/s), its angular velocity
#: (3, rad/s, world frame), the nearest other robot's position in its heading frame (2, m;
#: 0, 0 alone), and the fraction of the episode's time elapsed (1).
OBSERVATION_SIZE = 15
#: Reward added when a robot's own outcome is a success, and taken when it is a failure.
OUTCOME_REWARD = 10.0


class TeamParallelEnv(ParallelEnv):
    """The robots of a ``[[vehicles]]`` scenario as agents of one PettingZoo parallel world."""

    metadata = {"name": "tracksim_team_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(
        self,
        scenario,
        control_hz: float = 10.0,
        max_speed_mps: float = 0.5,
        max_yaw_rate_rad_s: float = 1.0,
        max_time_s: float | None = None,
        render_mode: str | None = None,
    ):
        if render_mode is not None:
            raise ValueError(
                f"render_mode {render_mode!r}: the team environment renders nothing yet; "
                "write the episode with `tracksim run` and `tracksim view`"
            )
        self._scenario = scenario if isinstance(scenario, Scenario) else Scenario(str(scenario))
        self._core = TeamEnvCore(
            self._scenario,
            None,
            float(control_hz),
            float(max_speed_mps),
            float(max_yaw_rate_rad_s),
            float(max_time_s) if max_time_s else None,
        )
        self.possible_agents = list(self._core.robot_names)
        self.render_mode = None
        self.control_period_s = self._core.control_period_s
        self._obs_space = spaces.Box(-np.inf, np.inf, (OBSERVATION_SIZE,), np.float32)
        self._act_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.agents: list[str] = []

    def observation_space(self, agent):
        return self._obs_space

    def action_space(self, agent):
        return self._act_space

    def reset(self, seed=None, options=None):
        obs = self._core.reset(None if seed is None else int(seed))[0]
        self.agents = list(self.possible_agents)
        observations = {a: obs[k] for k, a in enumerate(self.possible_agents)}
        # The episode's seed and the scenario's [randomize] values drawn from it (every agent
        # shares the world's).
        info = {"seed": self._core.seed, "randomized": self._core.randomized}
        return observations, {a: dict(info) for a in self.agents}

    def step(self, actions):
        a = np.zeros((1, len(self.possible_agents), 2), dtype=np.float32)
        for k, agent in enumerate(self.possible_agents):
            if agent in self.agents:
                a[0, k] = np.asarray(actions[agent], dtype=np.float32).reshape(2)
        obs, d = self._core.step(a)
        obs = obs[0]
        observations, rewards, terminations, truncations, infos = {}, {}, {}, {}, {}
        for k, agent in enumerate(self.possible_agents):
            if agent not in self.agents:
                continue
            observations[agent] = obs[k]
            rewards[agent] = float(d["reward"][0, k])
            terminations[agent] = bool(d["terminated"][0, k])
            truncations[agent] = bool(d["truncated"][0, k])
            infos[agent] = {"outcome": d["outcome"][0][k], "progress_m": float(d["progress_m"][0, k])}
        self.agents = [a for a in self.agents if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def render(self):
        return None

    def close(self):
        pass
