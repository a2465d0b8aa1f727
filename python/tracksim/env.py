"""The Gymnasium environment over one simulation (:class:`TracksimEnv`) and its reward."""

from __future__ import annotations

import os
from typing import Any, Callable, Optional, Union

import gymnasium as gym
import numpy as np

from ._tracksim import EnvCore, Scenario

#: Index of roll and pitch in the observation vector (rad).
ROLL, PITCH = 0, 1


class ProgressReward:
    """The default reward: ``progress_weight * progress_delta_m`` minus
    ``tilt_penalty * (|roll| + |pitch|) * control_period_s`` (rad s) minus
    ``energy_penalty * effort * control_period_s``, where ``effort`` is the mean of the squared
    normalised actions (a proxy of the actuators' effort, not joules).

    Works on scalars (one env) and arrays (vector env). Replace it with any callable of the same
    signature ``(obs, progress_delta_m, effort, control_period_s) -> reward``.
    """

    def __init__(self, progress_weight: float = 1.0, tilt_penalty: float = 0.0,
                 energy_penalty: float = 0.0):
        self.progress_weight = float(progress_weight)
        self.tilt_penalty = float(tilt_penalty)
        self.energy_penalty = float(energy_penalty)

    def __call__(self, obs, progress_delta_m, effort, control_period_s):
        obs = np.asarray(obs)
        tilt = np.abs(obs[..., ROLL]) + np.abs(obs[..., PITCH])
        return (self.progress_weight * np.asarray(progress_delta_m)
                - self.tilt_penalty * tilt * control_period_s
                - self.energy_penalty * np.asarray(effort) * control_period_s)


def observation_space(core) -> gym.Space:
    """The observation space of one environment of ``core`` (an ``EnvCore`` or a
    ``VecEnvCore``): a float32 ``Box`` of the state vector, or with ``observation="dict"`` a
    ``Dict`` of it (``"state"``) and one float32 ``Box`` per sensor."""
    state = gym.spaces.Box(-np.inf, np.inf, (core.obs_dim,), np.float32)
    if core.observation != "dict":
        return state
    spaces = {"state": state}
    for name, _kind, shape, low, high in core.sensor_obs_spec:
        spaces[name] = gym.spaces.Box(np.float32(low), np.float32(high), tuple(shape),
                                      np.float32)
    return gym.spaces.Dict(spaces)


def as_scenario(scenario: Union[str, os.PathLike, Scenario]) -> Scenario:
    """A :class:`Scenario` from a path or a loaded one."""
    return scenario if isinstance(scenario, Scenario) else Scenario(os.fspath(scenario))


class TracksimEnv(gym.Env):
    """A tracked robot in a scenario file, one action per control period (default 50 ms).

    Observation (float32): roll, pitch, yaw relative to the start heading (rad), height above the
    start (m), body-frame linear (m/s) and angular (rad/s) velocity, flipper angles (rad),
    measured belt speeds (m/s), and terrain heights relative to the body (m) on a grid ahead
    (``grid_shape`` rows x columns, ``grid_spacing_m``, from ``grid_ahead_m``) by ray casts;
    ``obs_names`` names every entry.

    Action (float32, each in [-1, 1]): forward speed and yaw rate (``action="twist"``, scaled by
    ``max_forward_mps`` and ``max_yaw_rate_rad_s``) or one belt speed per track
    (``action="belts"``, ``max_belt_speed_mps``), then one target per flipper mapped linearly
    onto ``flipper_range_rad``.

    Reward: ``reward`` (default :class:`ProgressReward`). An episode terminates when the
    scenario's outcome is decided (success, failure, tip-over past ``max_tilt_deg``, off the
    terrain) and is truncated at the scenario's ``duration_s``. ``reset(seed=s)`` draws the
    scenario's ``[randomize]`` values from ``s`` (reported in ``info["randomized"]``).

    ``config`` keys: control_period_s, action, max_forward_mps, max_yaw_rate_rad_s,
    max_belt_speed_mps, flipper_range_rad, grid_shape, grid_spacing_m, grid_ahead_m,
    no_terrain_m, observation.

    ``observation="vector"`` (the default) gives the state vector above. ``observation="dict"``
    gives a ``gymnasium.spaces.Dict``: ``"state"``, that vector, and one float32 entry per
    sensor of the vehicle (``[[sensors]]`` of its file), keyed by the sensor's name, its latest
    reading (sensors update at their own rates, so an entry may be older than the control
    period):

    - ``imu``: shape (10,): accel (m/s^2, specific force in the sensor frame: +9.81 along z at
      rest), gyro (rad/s), orientation quaternion (x, y, z, w);
    - ``encoders``: shape (2 * tracks + flippers,): belt positions (m), belt speeds (m/s),
      flipper angles (rad), in ``track_names`` / ``flipper_names`` order;
    - ``lidar``: shape (elevation_rays, azimuth_rays): ranges (m), no return as the lidar's
      ``max_range_m``, nearer than ``min_range_m`` as 0 (bounds [0, max_range_m]);
    - ``depth_camera``: shape (height_px, width_px): depth along the optical axis (m), likewise;
    - ``elevation_map``: shape (nx, ny): terrain heights relative to the sensor (m), cell ``[i,
      j]`` ahead ``x[i]`` and left ``y[j]`` (``Simulation.sensor_axes``), ``no_terrain_m``
      where there is no terrain.

    A vehicle without sensors gives ``{"state": ...}``. The reward function is given the state
    vector.
    """

    metadata = {"render_modes": []}

    def __init__(self, scenario: Union[str, os.PathLike, Scenario],
                 config: Optional[dict] = None,
                 reward: Optional[Callable[..., Any]] = None,
                 render_mode: Optional[str] = None):
        self.scenario = as_scenario(scenario)
        self.config = dict(config or {})
        self.reward_fn = reward if reward is not None else ProgressReward()
        self.render_mode = render_mode
        self._core = EnvCore(self.scenario, self.scenario.file_seed, self.config)
        self.control_period_s = self._core.control_period_s
        self.obs_names = self._core.obs_names
        self.dict_obs = self._core.observation == "dict"
        self.observation_space = observation_space(self._core)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (self._core.action_dim,), np.float32)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        episode_seed = int(seed) if seed is not None else int(self.np_random.integers(0, 2**63))
        obs = self._obs(self._core.reset(episode_seed))
        return obs, {"seed": episode_seed, "randomized": self._core.randomized}

    def step(self, action):
        a = np.asarray(action, dtype=np.float32).reshape(-1).tolist()
        state, terminated, truncated, info = self._core.step(a)
        reward = float(self.reward_fn(state, info["progress_delta_m"], info["effort"],
                                      self.control_period_s))
        return self._obs(state), reward, bool(terminated), bool(truncated), info

    def _obs(self, state):
        """The observation of the state vector ``state`` (with the sensors' entries as a dict)."""
        if not self.dict_obs:
            return state
        obs = {"state": state}
        obs.update(self._core.sensor_obs())
        return obs
