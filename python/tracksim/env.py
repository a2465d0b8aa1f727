"""The Gymnasium environment over one simulation (:class:`TracksimEnv`) and its reward."""

from __future__ import annotations

import os
from collections import OrderedDict
from typing import Any, Callable, Optional, Union

import gymnasium as gym
import numpy as np

from ._tracksim import EnvCore, LiveView, Scenario

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


#: The render modes the environments support: ``"human"`` (the live 3-D page) and
#: ``"rgb_array"`` (frames as uint8 arrays, for ``gymnasium.wrappers.RecordVideo``).
RENDER_MODES = ["human", "rgb_array"]


def check_render_mode(render_mode: Optional[str]) -> None:
    """Refuses a render mode other than None, "human" and "rgb_array"."""
    if render_mode is None or render_mode in RENDER_MODES:
        return
    raise ValueError(f"render_mode={render_mode!r} is not supported: use None, 'human' (the "
                     f"live 3-D page on loopback) or 'rgb_array' (uint8 frames of the chase "
                     f"camera or an rgb_camera sensor, for gymnasium.wrappers.RecordVideo)")


def render_config(config: dict, render_camera: Optional[str],
                  render_size: Optional[tuple]) -> dict:
    """``config`` with the ``render_camera`` and ``render_size`` arguments as its settings
    ``render_camera`` and ``render_size_px`` (an argument given twice, differently, is
    refused)."""
    c = dict(config)
    for key, arg, value in (("render_camera", "render_camera", render_camera),
                            ("render_size_px", "render_size", render_size)):
        if value is None:
            continue
        if isinstance(value, (list, tuple)):
            value = tuple(value)
        if key in c and (tuple(c[key]) if isinstance(c[key], (list, tuple)) else c[key]) != value:
            raise ValueError(f"{arg}={value!r} and config[{key!r}]={c[key]!r}: give one")
        c[key] = value
    return c


def plain_config(config: Optional[dict]) -> dict:
    """``config`` with a path-like ``record_dir`` made a string."""
    c = dict(config or {})
    if c.get("record_dir") is not None and not isinstance(c["record_dir"], str):
        c["record_dir"] = os.fspath(c["record_dir"])
    return c


def learner_obs(spec, flat):
    """The learner's entries of the flat observation(s) ``flat`` (``(..., obs_dim)``): a dict of
    float32 arrays of shape ``(..., *shape)``, views into ``flat``."""
    out, at = {}, 0
    lead = flat.shape[:-1]
    for name, shape, _low, _high in spec:
        n = int(np.prod(shape))
        out[name] = flat[..., at:at + n].reshape(lead + tuple(shape))
        at += n
    return out


def observation_space(core) -> gym.Space:
    """The observation space of one environment of ``core`` (an ``EnvCore`` or a
    ``VecEnvCore``): a float32 ``Box`` of the state vector, or with ``observation="dict"`` a
    ``Dict`` of it (``"state"``) and one float32 ``Box`` per sensor, or with
    ``observation="learner"`` a ``Dict`` of the learner's entries (float32 ``Box`` each, their
    bounds as documented in :class:`TracksimEnv`)."""
    if core.observation == "learner":
        # An OrderedDict keeps the documented order (a plain dict is sorted by gymnasium).
        return gym.spaces.Dict(OrderedDict(
            (name, gym.spaces.Box(np.float32(low), np.float32(high), tuple(shape), np.float32))
            for name, shape, low, high in core.learner_obs_spec
        ))
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
    (``action="belts"``, ``max_belt_speed_mps``), then one entry per flipper: with
    ``flipper_action="position"`` (the default) its target angle, mapped linearly onto
    ``flipper_range_rad``; with ``flipper_action="velocity"`` its rate, times
    ``max_flipper_rate_rad_s`` (rad/s, default 1), integrated into the target angle over each
    control period and clamped to ``flipper_range_rad`` and the joint's limits (0 holds the
    flipper where its target is). The joint's position servo (the vehicle file's stiffness,
    damping and torque limit) follows the moving target: a real velocity motor would let the
    arm sag under load at rate 0 and its commands could not be recorded as a scenario's
    ``flipper_angle_deg`` (see ``record_dir``).

    Reward: ``reward`` (default :class:`ProgressReward`). An episode terminates when the
    scenario's outcome is decided (success, failure, tip-over past ``max_tilt_deg``, off the
    terrain) and is truncated at the scenario's ``duration_s``. ``reset(seed=s)`` draws the
    scenario's ``[randomize]`` values from ``s`` (reported in ``info["randomized"]``).
    ``info`` after a step: ``progress_delta_m``, ``progress_m``, ``effort``, ``outcome``,
    ``reason``, ``t_s``, ``seed``, ``randomized``, and on a course (a scenario with
    ``[course]``) ``course``: the score so far (``gates_passed``, ``gates_total``,
    ``next_gate``, ``repetition``, ``repetitions_done``, ``repetitions_required``,
    ``elapsed_s``, ``time_limit_s``, ``penalty_s``, ``score_s``, ``faults`` by kind,
    ``status``, ``finished``), as the run's ``summary.json`` has it (at the step that ends the
    episode, closed as there: a course still running is then ``not_completed``).

    ``config`` keys: control_period_s, action, max_forward_mps, max_yaw_rate_rad_s,
    max_belt_speed_mps, flipper_range_rad, grid_shape, grid_spacing_m, grid_ahead_m,
    no_terrain_m, observation, flipper_action, max_flipper_rate_rad_s, map_shape,
    map_resolution_m, map_reach_m, goal_xy_m, record_dir, render_camera, render_size_px.

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
    - ``rgb_camera``: shape (height_px, width_px, 3): the colour image, 8-bit levels 0..255
      as float32 (bounds [0, 255]; ``astype(np.uint8)`` gives the frame's bytes);
    - ``elevation_map``: shape (nx, ny): terrain heights relative to the sensor (m), cell ``[i,
      j]`` ahead ``x[i]`` and left ``y[j]`` (``Simulation.sensor_axes``), ``no_terrain_m``
      where there is no terrain.

    A vehicle without sensors gives ``{"state": ...}``. The reward function is given the state
    vector.

    ``observation="learner"`` gives a ``gymnasium.spaces.Dict`` of float32 entries for a
    learner (computed once per step into preallocated buffers, about 1 ms per step with the
    default 64 x 64 map: ``python/examples/learner_obs_cost.py``):

    - ``roll_pitch_rad`` (2,): roll and pitch (rad, bounds +-pi);
    - ``orientation_xyzw`` (4,): the body's orientation quaternion in the world (bounds +-1);
    - ``linear_velocity_mps`` (3,), ``angular_velocity_rad_s`` (3,): the body origin's velocity
      and the body's angular velocity in the body frame (x forward, y left, z up);
    - ``goal_m`` (3,): the goal relative to the body, body frame (m): ``goal_xy_m`` if set,
      else the point of the ``[outcome]`` line ``success_x_m`` level with the start, else 10 m
      ahead of the start; at ``success_z_m`` height if the outcome has one, else the body's;
    - ``flipper_angle_rad`` (flippers,) (bounds +-2 pi), ``flipper_velocity_rad_s``
      (flippers,): relative to the body (left out for a vehicle without flippers);
    - ``track_slip`` (tracks,) (bounds +-2), ``track_traction_n`` (tracks,) (N, along the
      body's x), ``track_contacts`` (tracks,) (count, >= 0): the figures of the CLI's
      trajectory.csv, per track in ``track_names`` order;
    - ``elevation_map_m`` (rows, columns): terrain heights (m) relative to the map's origin
      around the body, level and turned with its yaw, cell ``[i, j]`` at ``(i + 0.5 - rows / 2)
      * resolution`` ahead and ``(j + 0.5 - columns / 2) * resolution`` left: the vehicle's
      ``elevation_map`` sensor if it has one (at its rate), else ``map_shape`` (default 64 x
      64) cells of ``map_resolution_m`` (default 2 m / 64) on the body origin, searched
      ``map_reach_m`` (default 1 m) above and below; ``no_terrain_m`` where there is none;
      bounds [-reach, reach] with ``no_terrain_m``.

    The reward function is given the flat vector of these entries (``roll_pitch_rad`` first,
    so :class:`ProgressReward` reads roll and pitch as from the state vector).

    Watching: ``render_mode="human"`` serves the live 3-D page (the one of ``tracksim drive``,
    watch-only: no drive controls and no driver's status; the HUD shows each belt's commanded
    speed and position and each flipper's target, and the belts run in the 3-D view) on
    127.0.0.1 (``render_port``, default a free port) from the first :meth:`step` (the URL is
    then printed and in ``render_url``; an environment never stepped, such as the ones
    gymnasium's ``check_env`` makes to try each render mode, serves nothing) and shows every
    step, paced to ``render_speed`` simulated seconds per wall
    second (default 1: real time, the training runs no faster; None: never waits).
    ``config={"record_dir": DIR}`` writes every episode as a run folder
    ``DIR/seed<SEED>-ep<K>`` (summary.json, trajectory.csv, scene.json, belts.csv,
    commands.toml) when the next one starts or the env closes: ``tracksim view`` opens it and
    ``tracksim run FILE --commands DIR/.../commands.toml --duration T`` replays it byte for
    byte (a file without ``[randomize]``, or the episode's seed the file's).

    Frames: ``render_mode="rgb_array"`` makes :meth:`render` return the current state as a
    ``numpy.uint8`` array of shape (height, width, 3), RGB, rows from the top, traced by
    tracksim's CPU ray tracer (no GPU or GL needed; ``docs/SENSORS.md`` has the light model).
    ``render_camera="chase"`` (the default) is a camera 1.6 m behind and 0.9 m above the robot
    following its heading, 70 deg across, of ``render_size=(width, height)`` pixels (default
    (160, 120); a few ms per frame at that size); the name of an ``rgb_camera`` sensor of the
    vehicle gives that sensor's latest frame instead (its own size and rate; the vehicle's
    sensors then run). Both are also the settings ``render_camera`` and ``render_size_px`` of
    ``config``. ``metadata["render_fps"]`` is the control rate (``1 / control_period_s``: one
    frame per step), so ``gymnasium.wrappers.RecordVideo`` writes videos in simulated real
    time. Rendering never changes the simulation. An ``rgb_camera`` sensor with
    ``observation="dict"`` is also an entry of the observation: float32 (height, width, 3)
    levels 0..255.
    """

    metadata = {"render_modes": RENDER_MODES}

    def __init__(self, scenario: Union[str, os.PathLike, Scenario],
                 config: Optional[dict] = None,
                 reward: Optional[Callable[..., Any]] = None,
                 render_mode: Optional[str] = None, render_port: int = 0,
                 render_speed: Optional[float] = 1.0, render_camera: Optional[str] = None,
                 render_size: Optional[tuple] = None):
        check_render_mode(render_mode)
        self.scenario = as_scenario(scenario)
        self.config = render_config(plain_config(config), render_camera, render_size)
        self.reward_fn = reward if reward is not None else ProgressReward()
        self.render_mode = render_mode
        self._core = EnvCore(self.scenario, self.scenario.file_seed, self.config)
        self.control_period_s = self._core.control_period_s
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.control_period_s}
        self.obs_names = self._core.obs_names
        self.dict_obs = self._core.observation == "dict"
        self.learner_spec = self._core.learner_obs_spec
        self.observation_space = observation_space(self._core)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (self._core.action_dim,), np.float32)
        self._view = None
        self.render_url = None
        if render_mode == "human":
            port = render_port
            if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
                raise ValueError(f"render_port: a TCP port from 0 to 65535 (0: a free one), "
                                 f"got {render_port!r}")
            # Served from the first step (an episode to watch), not here: an environment made
            # only to be inspected (gymnasium's check_env makes one per render mode, resets it
            # and calls render()) starts no server.
            self._render_port, self._render_speed = port, render_speed

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        episode_seed = int(seed) if seed is not None else int(self.np_random.integers(0, 2**63))
        obs = self._obs(self._core.reset(episode_seed))
        if self._view is not None:
            self._view.new_episode(self._core)
            self._view.show(self._core)
        return obs, {"seed": episode_seed, "randomized": self._core.randomized}

    def step(self, action):
        if self.render_mode == "human" and self._view is None:
            self._serve()
        a = np.asarray(action, dtype=np.float32).reshape(-1).tolist()
        state, terminated, truncated, info = self._core.step(a)
        reward = float(self.reward_fn(state, info["progress_delta_m"], info["effort"],
                                      self.control_period_s))
        if self._view is not None:
            self._view.show(self._core)
        return self._obs(state), reward, bool(terminated), bool(truncated), info

    def _serve(self):
        """Starts the live page (``render_mode="human"``) on the episode in progress."""
        self._view = LiveView(self._core, self._render_port, self._render_speed)
        self.render_url = self._view.url
        print(f"tracksim: watch the environment at {self.render_url}", flush=True)
        self._view.new_episode(self._core)
        self._view.show(self._core)

    def render(self):
        """With ``render_mode="rgb_array"`` the current state as a ``numpy.uint8`` array
        (height, width, 3) (see the class's text); with ``"human"`` the page is fed at every
        step already (this publishes the current state again) and None is returned; without a
        render mode None."""
        if self.render_mode == "rgb_array":
            return self._core.render()
        if self._view is not None:
            self._view.show(self._core)
        return None

    def close(self):
        """Writes the episode in progress as a run folder (with ``record_dir``) and stops the
        live page (with ``render_mode="human"``)."""
        if getattr(self, "_core", None) is not None:
            self._core.flush_record()
        if getattr(self, "_view", None) is not None:
            self._view.close()
            self._view = None
        super().close()

    def _obs(self, state):
        """The observation of the state vector ``state`` (with the sensors' entries as a dict),
        or the learner's entries."""
        if self.learner_spec:
            return learner_obs(self.learner_spec, state)
        if not self.dict_obs:
            return state
        obs = {"state": state}
        obs.update(self._core.sensor_obs())
        return obs
