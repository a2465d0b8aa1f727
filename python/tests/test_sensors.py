"""Sensors from Python: Simulation's readings, the dict observation of the environments, and
the streams `tracksim run` writes under sensors/."""

import csv

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tracksim
from conftest import SCENARIOS, SHORT_FLAT, VEHICLES, run_cli

SENSORS = SCENARIOS / "packbot_sensors.toml"
DICT = {"observation": "dict"}
#: Where the bundled stairs of packbot_sensors.toml begin, m (world x).
STAIRS_X = 0.9


@pytest.fixture(scope="module")
def at_rest():
    """The sensor scenario after 1 s without controls (the robot settled on flat ground)."""
    sim = tracksim.Simulation(SENSORS)
    sim.step(round(1.0 / sim.dt))
    return sim


def test_simulation_lists_its_sensors_and_refuses_an_unknown_name(at_rest):
    assert at_rest.sensor_names == ["imu", "encoders", "scan", "elevation", "front_camera",
                                    "flipper_imu"]
    assert set(at_rest.sensors()) == set(at_rest.sensor_names)
    with pytest.raises(KeyError, match="no sensor \"lidar\".*imu, encoders, scan"):
        at_rest.sensor("lidar")
    with pytest.raises(KeyError, match="front_camera"):
        at_rest.sensor_axes("camera")


def rotation(q):
    """The rotation matrix of the quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def test_imu_at_rest_reads_gravity_and_no_rotation(at_rest):
    r = at_rest.sensor("imu")
    # 200 Hz: the last reading at or just before 1 s.
    assert r["t_s"] == pytest.approx(1.0, abs=0.5 / 200 + at_rest.dt)
    assert r["accel_m_s2"].shape == (3,) and r["accel_m_s2"].dtype == np.float64
    q = r["orientation"]
    assert q.shape == (4,) and np.linalg.norm(q) == pytest.approx(1.0, abs=1e-9)
    assert abs(q[3]) > 0.999  # level, heading +x

    # Every reading over the next second against the body's motion. The IMU sits at the body
    # origin (its centre of mass), so it reads R^T ((v_k - v_k-1) / T + g z) and R^T w: a body
    # "at rest" on the contact solver still vibrates by a few mm/s, which over T = 5 ms is
    # tenths of m/s^2, far above the IMU's own noise. The noise: white sigma = 0.0017 *
    # sqrt(200) = 0.024 m/s^2 (gyro 0.00024 * sqrt(200) = 0.0034 rad/s), the bias walk below
    # 1e-3 over 2 s; 0.15 m/s^2 and 0.03 rad/s are 6 sigma and more.
    sim = tracksim.Simulation(SENSORS)
    sim.step(round(1.0 / sim.dt))
    readings = []
    t = sim.sensor("imu")["t_s"]
    while sim.time < 2.0:
        sim.step()
        r = sim.sensor("imu")
        if r["t_s"] != t:
            t = r["t_s"]
            s = sim.observe()
            assert s["t_s"] == t
            readings.append((t, r, s["linvel_mps"], s["angvel_rad_s"]))
    assert len(readings) == 200
    g = np.array([0.0, 0.0, 9.81])
    accels = []
    for (t0, _, v0, _), (t1, r, v1, w1) in zip(readings, readings[1:]):
        rt = rotation(r["orientation"]).T
        np.testing.assert_allclose(r["accel_m_s2"], rt @ ((v1 - v0) / (t1 - t0) + g), atol=0.15)
        np.testing.assert_allclose(r["gyro_rad_s"], rt @ w1, atol=0.03)
        accels.append(r["accel_m_s2"])
    # Over 1 s the vibration averages out: the mean is (v_end - v_start) / 1 s (mm/s) off
    # gravity, plus noise / sqrt(199).
    np.testing.assert_allclose(np.mean(accels, axis=0), g, atol=0.05)
    np.testing.assert_allclose(np.mean([x[1]["gyro_rad_s"] for x in readings], axis=0), 0,
                               atol=0.01)


def test_encoders_match_the_state(at_rest):
    r = at_rest.sensor("encoders")
    s = at_rest.observe()
    n_tracks, n_flippers = len(at_rest.track_names), len(at_rest.flipper_names)
    assert r["belt_position_m"].shape == (n_tracks,)
    assert r["belt_speed_m_s"].shape == (n_tracks,)
    # 100 Hz: the reading may be up to one period old, and the flippers hold still at rest.
    np.testing.assert_allclose(r["flipper_angle_rad"], s["flipper_angle_rad"], atol=1e-3)
    assert r["flipper_angle_rad"].shape == (n_flippers,)


def test_elevation_map_over_flat_ground_is_minus_the_sensor_height(at_rest):
    r = at_rest.sensor("elevation")
    axes = at_rest.sensor_axes("elevation")
    h = r["height_m"]
    assert h.shape == (64, 64) and axes["x_m"].shape == (64,) and axes["y_m"].shape == (64,)
    # 64 cells of 1/32 m over 2 m, centred on the sensor.
    np.testing.assert_allclose(axes["x_m"][[0, -1]], [-1 + 1 / 64, 1 - 1 / 64])
    pos = r["position_m"]
    ground = at_rest.terrain_heights([pos[0]], [pos[1]])[0]
    assert ground == pytest.approx(0.0, abs=1e-6)
    flat = pos[0] + axes["x_m"] < STAIRS_X - 0.05  # cells short of the first riser
    assert flat.sum() >= 40
    assert np.isfinite(h[flat]).all()
    # f32 ray casts: 1e-4 m. The robot itself is not seen: the cells under it are ground too.
    np.testing.assert_allclose(h[flat], ground - pos[2], atol=1e-4)
    # On the first steps the map sees them higher than the ground.
    assert (h[~flat] > ground - pos[2] + 0.1).any()


def test_lidar_scan_sees_the_stairs_ahead(at_rest):
    r = at_rest.sensor("scan")
    axes = at_rest.sensor_axes("scan")
    rng = r["range_m"]
    assert rng.shape == (1, 720) and r["points_m"].shape == (1, 720, 3)
    assert axes["azimuth_rad"].shape == (720,) and axes["elevation_rad"].shape == (1,)
    ok = np.isfinite(rng)
    assert ((rng[ok] >= 0.1) & (rng[ok] <= 10.0)).all()
    assert np.isnan(r["points_m"][~ok]).all() and np.isfinite(r["points_m"][ok]).all()
    # Straight ahead (azimuth 0) the ray meets the first riser taller than the scan plane.
    a0 = int(np.argmin(np.abs(axes["azimuth_rad"])))
    pos = r["position_m"]
    k = int(np.floor(pos[2] / 0.15))  # risers of 0.15 m, treads of 0.30 m from x = 0.9
    assert rng[0, a0] == pytest.approx(STAIRS_X + 0.30 * k - pos[0], abs=0.05)


def test_sensors_start_again_on_reset(at_rest):
    sim = tracksim.Simulation(SENSORS)
    first = sim.sensor("front_camera")
    assert first["t_s"] == 0.0 and first["depth_m"].shape == (48, 64)
    sim.step(round(0.3 / sim.dt))  # 5 Hz: a reading at 0.2 s
    assert sim.sensor("front_camera")["t_s"] == pytest.approx(0.2)
    sim.reset()
    again = sim.sensor("front_camera")
    assert again["t_s"] == 0.0
    np.testing.assert_array_equal(again["depth_m"], first["depth_m"])
    assert sim.sensor_axes("front_camera")["focal_length_px"].shape == (1,)


def test_a_vehicle_without_sensors_has_none(write_scenario):
    sim = tracksim.Simulation(write_scenario(SHORT_FLAT % "1.0"))
    assert sim.sensor_names == [] and sim.sensors() == {}
    with pytest.raises(KeyError, match="its sensors: none"):
        sim.sensor("imu")


def test_dict_observation_passes_check_env():
    env = tracksim.TracksimEnv(SENSORS, config=DICT)
    check_env(env, skip_render_check=True)


def test_dict_observation_layout_and_space():
    env = tracksim.TracksimEnv(SENSORS, config=DICT)
    space = env.observation_space
    assert set(space.spaces) == {"state", "imu", "encoders", "scan", "elevation",
                                 "front_camera", "flipper_imu"}
    assert space["state"].shape == (len(env.obs_names),)
    assert space["imu"].shape == (10,) and space["flipper_imu"].shape == (10,)
    assert space["encoders"].shape == (2 * 4 + 2,)  # 4 tracks, 2 flippers
    assert space["scan"].shape == (1, 720) and space["scan"].high.max() == 10.0
    assert space["elevation"].shape == (64, 64)
    assert space["front_camera"].shape == (48, 64) and space["front_camera"].high.max() == 5.0
    obs, _ = env.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(20):
        assert space.contains(obs), {k: v.shape for k, v in obs.items()}
        for v in obs.values():
            assert v.dtype == np.float32 and not np.isnan(v).any()
        obs, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
    # The state entry is the vector observation, unchanged.
    vec = tracksim.TracksimEnv(SENSORS)
    v0, _ = vec.reset(seed=3)
    d0, _ = env.reset(seed=3)
    np.testing.assert_array_equal(d0["state"], v0)
    # The IMU entry is accel, gyro, orientation: gravity on z at rest.
    assert d0["imu"][2] == pytest.approx(9.81, abs=0.15)


def test_dict_observation_is_deterministic():
    def episode(seed):
        env = tracksim.TracksimEnv(SENSORS, config=DICT)
        out = [env.reset(seed=seed)[0]]
        rng = np.random.default_rng(1)
        for _ in range(10):
            out.append(env.step(rng.uniform(-1, 1, env.action_space.shape)
                                .astype(np.float32))[0])
        return out

    a, b, c = episode(7), episode(7), episode(8)
    for x, y in zip(a, b):
        for k in x:
            np.testing.assert_array_equal(x[k], y[k], err_msg=k)
    # Another seed gives other sensor noise (the lidar's range noise is 0.01 m).
    assert not np.array_equal(a[-1]["scan"], c[-1]["scan"])


def test_dict_replaces_no_terrain_and_no_return(write_scenario, tmp_path):
    # A map that looks only 2 cm below the sensor finds no ground: every cell is no_terrain_m.
    text = (VEHICLES / "packbot510_sensors.toml").read_text()
    text = text.replace("resolution_m = 0.03125", "resolution_m = 0.03125\ndepth_below_m = 0.02")
    (tmp_path / "v.toml").write_text(text)
    s = write_scenario((SHORT_FLAT % "1.0").replace("{vehicles}/packbot510.toml", "v.toml"))
    sim = tracksim.Simulation(s)
    assert np.isnan(sim.sensor("elevation")["height_m"]).all()
    env = tracksim.TracksimEnv(s, config={"observation": "dict", "no_terrain_m": -2.5})
    obs, _ = env.reset(seed=0)
    assert (obs["elevation"] == -2.5).all()
    # On open flat ground most lidar rays (horizontal plane) have no return: max range.
    raw = sim.sensor("scan")["range_m"]
    assert np.isposinf(raw).any()
    np.testing.assert_array_equal(obs["scan"][np.isposinf(raw)], 10.0)


def test_no_sensors_gives_just_the_state(write_scenario):
    env = tracksim.TracksimEnv(write_scenario(SHORT_FLAT % "1.0"), config=DICT)
    assert list(env.observation_space.spaces) == ["state"]
    obs, _ = env.reset(seed=0)
    assert list(obs) == ["state"] and env.observation_space.contains(obs)


def test_a_bad_observation_mode_is_refused_with_its_key():
    with pytest.raises(ValueError, match="observation.*\"image\" is not an observation mode"):
        tracksim.TracksimEnv(SENSORS, config={"observation": "image"})
    with pytest.raises(ValueError, match="observation"):
        tracksim.TracksimVectorEnv(SENSORS, 2, config={"observation": 1.0})
    # The default is the vector.
    assert isinstance(tracksim.TracksimEnv(SENSORS).observation_space, gym.spaces.Box)


def test_vector_env_stacks_the_dict_observation():
    n = 3
    venv = tracksim.TracksimVectorEnv(SENSORS, n, threads=2, config=DICT)
    obs, _ = venv.reset(seed=5)
    single = tracksim.TracksimEnv(SENSORS, config=DICT)
    shapes = {k: s.shape for k, s in single.observation_space.spaces.items()}
    assert {k: v.shape for k, v in obs.items()} == {k: (n, *s) for k, s in shapes.items()}
    assert venv.observation_space.contains(obs)
    # Environment i is the single environment seeded 5 + i.
    for i in range(n):
        o, _ = single.reset(seed=5 + i)
        for k in o:
            np.testing.assert_array_equal(obs[k][i], o[k], err_msg=k)
    actions = np.zeros((n, venv.single_action_space.shape[0]), np.float32)
    actions[:, 0] = 1.0
    for _ in range(3):
        obs, rewards, *_ = venv.step(actions)
        assert {k: v.shape for k, v in obs.items()} == {k: (n, *s) for k, s in shapes.items()}
        assert venv.observation_space.contains(obs) and rewards.shape == (n,)


def test_run_writes_sensor_streams(tmp_path):
    out = tmp_path / "run"
    r = run_cli("run", SENSORS, "--duration", "1", "--out", out)
    assert r.returncode == 0, r.stderr
    d = out / "sensors"
    # (file, rate Hz, {key: shape of one reading})
    arrays = {
        "scan": (10, {"range_m": (1, 720), "points_m": (1, 720, 3), "position_m": (3,),
                      "orientation": (4,)}),
        "elevation": (20, {"height_m": (64, 64), "position_m": (3,)}),
        "front_camera": (5, {"depth_m": (48, 64)}),
    }
    for name, (rate, keys) in arrays.items():
        with np.load(d / f"{name}.npz") as z:
            n = 1 * rate + 1  # readings at 0, 1/rate, ..., 1 s
            assert z["t_s"].shape == (n,), name
            np.testing.assert_allclose(z["t_s"], np.arange(n) / rate, atol=1e-9)
            for k, shape in keys.items():
                assert z[k].shape == (n, *shape), (name, k)
    with np.load(d / "elevation.npz") as z:
        assert z["x_m"].shape == (64,)
    with np.load(d / "scan.npz") as z:
        assert z["azimuth_rad"].shape == (720,)
    for name, rate in (("imu", 200), ("flipper_imu", 100), ("encoders", 100)):
        with open(d / f"{name}.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == 1 * rate + 1, name
        assert float(rows[-1]["t_s"]) == pytest.approx(1.0)
    with open(d / "imu.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert {"accel_z_m_s2", "gyro_x_rad_s", "qw"} <= set(rows[0])
    # At t = 0 the IMU reads gravity alone (no velocity history yet).
    assert float(rows[0]["accel_z_m_s2"]) == pytest.approx(9.81, abs=0.15)
