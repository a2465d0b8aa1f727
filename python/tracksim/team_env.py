"""Several robots in one world as a PettingZoo ``ParallelEnv`` (issue 40, docs/TEAMS.md).

A scenario with ``[[vehicles]]`` is one world; each robot is an agent named after it. Every
control period each agent's action, a twist ``[forward, yaw_rate]`` in ``[-1, 1]`` scaled by
``max_speed_mps`` and ``max_yaw_rate_rad_s``, is given to its robot; the world steps; each agent
observes itself and its nearest neighbour, and is rewarded its progress along its start heading.
An agent is terminated when its robot's own outcome is decided (``[vehicles.outcome]``: a
success, or a failure such as tipping over) and braked from then on; every agent is truncated at
the scenario's duration. Observations, rewards, terminations, truncations and infos are dicts
keyed by robot name, as PettingZoo's parallel API asks (``pettingzoo.test.parallel_api_test``
passes: ``python/tests/test_team.py``).
"""

from __future__ import annotations

import math

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from ._tracksim import Scenario, Simulation

#: Observation entries, in order (float32): the robot's position relative to its start in its
#: start frame (x forward, y left, z up: 3, m), roll, pitch, yaw relative to its start heading
#: (3, rad), its velocity in its heading frame (forward, left, up: 3, m/s), its angular velocity
#: (3, rad/s, world frame), the nearest other robot's position in its heading frame (2, m;
#: 0, 0 alone), and the fraction of the episode's time elapsed (1).
OBSERVATION_SIZE = 15
#: Reward added when a robot's own outcome is a success, and taken when it is a failure.
OUTCOME_REWARD = 10.0


def _wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


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
        self._sim = Simulation(self._scenario)
        self.possible_agents = list(self._sim.robot_names)
        self.render_mode = None
        if not control_hz > 0.0:
            raise ValueError(f"control_hz must be positive, got {control_hz}")
        self._substeps = max(1, round(1.0 / (control_hz * self._sim.dt)))
        self._max_time = float(max_time_s or self._scenario.duration_s)
        self._scale = np.array([max_speed_mps, max_yaw_rate_rad_s], dtype=np.float64)
        self._obs_space = spaces.Box(-np.inf, np.inf, (OBSERVATION_SIZE,), np.float32)
        self._act_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.agents: list[str] = []
        self._start: dict[str, tuple] = {}
        self._progress: dict[str, float] = {}

    def observation_space(self, agent):
        return self._obs_space

    def action_space(self, agent):
        return self._act_space

    def _state(self, agent):
        self._sim.select(agent)
        return self._sim.observe()

    def _forward(self, agent, state) -> float:
        x0, y0, yaw0 = self._start[agent]
        dx, dy = state["position_m"][0] - x0, state["position_m"][1] - y0
        return dx * math.cos(yaw0) + dy * math.sin(yaw0)

    def _observations(self, states):
        t = self._sim.time / self._max_time
        obs = {}
        for agent in self.agents:
            s = states[agent]
            x0, y0, yaw0 = self._start[agent]
            c0, s0 = math.cos(yaw0), math.sin(yaw0)
            p = s["position_m"]
            dx, dy = p[0] - x0, p[1] - y0
            roll, pitch, yaw = s["rpy_rad"]
            c, sn = math.cos(yaw), math.sin(yaw)
            v = s["linvel_mps"]
            near = (0.0, 0.0)
            others = [o for o in self.possible_agents if o != agent]
            if others:
                q = min(
                    (states[o]["position_m"] for o in others),
                    key=lambda q: (q[0] - p[0]) ** 2 + (q[1] - p[1]) ** 2,
                )
                ex, ey = q[0] - p[0], q[1] - p[1]
                near = (ex * c + ey * sn, -ex * sn + ey * c)
            obs[agent] = np.array(
                [
                    dx * c0 + dy * s0,
                    -dx * s0 + dy * c0,
                    p[2],
                    roll,
                    pitch,
                    _wrap(yaw - yaw0),
                    v[0] * c + v[1] * sn,
                    -v[0] * sn + v[1] * c,
                    v[2],
                    *s["angvel_rad_s"],
                    *near,
                    t,
                ],
                dtype=np.float32,
            )
        return obs

    def reset(self, seed=None, options=None):
        self._sim.reset(seed)
        self.agents = list(self.possible_agents)
        states = {a: self._state(a) for a in self.possible_agents}
        self._start = {
            a: (s["position_m"][0], s["position_m"][1], s["rpy_rad"][2]) for a, s in states.items()
        }
        self._progress = {a: 0.0 for a in self.agents}
        infos = {a: {} for a in self.agents}
        return self._observations(states), infos

    def step(self, actions):
        for agent in self.agents:
            a = np.clip(np.asarray(actions[agent], dtype=np.float64), -1.0, 1.0) * self._scale
            self._sim.select(agent)
            self._sim.set_twist(float(a[0]), float(a[1]))
        self._sim.step(self._substeps)
        states = {a: self._state(a) for a in self.possible_agents}
        obs = self._observations(states)
        rewards, terminations, truncations, infos = {}, {}, {}, {}
        time_up = self._sim.time >= self._max_time - 0.5 * self._sim.dt
        for agent in self.agents:
            forward = self._forward(agent, states[agent])
            reward = forward - self._progress[agent]
            self._progress[agent] = forward
            self._sim.select(agent)
            outcome = self._sim.outcome()
            done = outcome is not None
            if done:
                reward += OUTCOME_REWARD if outcome[0] == "success" else -OUTCOME_REWARD
                self._sim.set_twist(0.0, 0.0)
            rewards[agent] = float(reward)
            terminations[agent] = done
            truncations[agent] = time_up and not done
            infos[agent] = {"outcome": outcome[0] if outcome else None, "progress_m": forward}
        self.agents = [a for a in self.agents if not (terminations[a] or truncations[a])]
        return obs, rewards, terminations, truncations, infos

    def render(self):
        return None

    def close(self):
        pass
