"""Issue 29: the learner's Dict observation, velocity-controlled flippers, episodes recorded as
run folders (replayed by the CLI), the live page of render_mode="human" (rgb_array frames:
test_render.py)."""

import base64
import json
import os
import re
import socket
import struct
import threading
import time
import urllib.request

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tracksim
from conftest import SCENARIOS, run_cli

STAIRS = SCENARIOS / "packbot_stairs.toml"
STEP = SCENARIOS / "random" / "packbot_flippers_step_random.toml"
LEARNER = {"observation": "learner"}


def test_learner_observation_is_a_dict_of_bounded_float32_boxes():
    env = tracksim.TracksimEnv(STAIRS, config=LEARNER)
    check_env(env, skip_render_check=True)
    space = env.observation_space
    assert list(space.spaces) == [
        "roll_pitch_rad", "orientation_xyzw", "linear_velocity_mps", "angular_velocity_rad_s",
        "goal_m", "flipper_angle_rad", "flipper_velocity_rad_s", "track_slip",
        "track_traction_n", "track_contacts", "elevation_map_m"]
    assert space["elevation_map_m"].shape == (64, 64)
    assert space["track_slip"].shape == (4,) and space["track_slip"].high[0] == 2.0
    assert space["orientation_xyzw"].low[0] == -1.0
    obs, _ = env.reset(seed=0)
    for _ in range(20):
        obs, *_ = env.step(np.array([0.6, 0.0, 0.5, 0.5], np.float32))
    assert space.contains(obs)
    assert all(v.dtype == np.float32 for v in obs.values())
    # Driving forwards at 0.3 m/s, level, flippers at 30 deg.
    assert obs["linear_velocity_mps"][0] == pytest.approx(0.3, abs=0.05)
    assert abs(obs["roll_pitch_rad"]).max() < 0.05
    assert obs["flipper_angle_rad"] == pytest.approx(np.radians(30.0), abs=0.02)
    assert obs["track_contacts"][:2].min() > 0
    # The stairs (rise 0.15 m from x = 0.9 m) are in the map ahead, the ground behind.
    m = obs["elevation_map_m"]
    rise = m[-1, 32] - m[0, 32]
    assert rise > 0.1 and rise / 0.15 == pytest.approx(round(rise / 0.15), abs=0.05)


def test_learner_observation_in_the_vector_env_stacks_the_single_ones():
    vec = tracksim.TracksimVectorEnv(STEP, 2, threads=2, config=LEARNER)
    one = tracksim.TracksimEnv(STEP, config=LEARNER)
    obs, _ = vec.reset(seed=[3, 4])
    single, _ = one.reset(seed=4)
    a = np.array([[0.5, 0.0, 0.2, 0.2]] * 2, np.float32)
    for _ in range(3):
        obs, rewards, *_ = vec.step(a)
        single, r, *_ = one.step(a[1])
    assert vec.single_observation_space.contains({k: v[1] for k, v in obs.items()})
    for k, v in single.items():
        assert obs[k].shape == (2,) + v.shape
        np.testing.assert_array_equal(obs[k][1], v)
    assert rewards[1] == pytest.approx(r)


def test_velocity_flippers_move_at_the_commanded_rate_within_the_range():
    env = tracksim.TracksimEnv(STAIRS, config={
        "observation": "learner", "flipper_action": "velocity", "max_flipper_rate_rad_s": 1.0})
    env.reset(seed=0)
    angles = []
    for _ in range(16):
        obs, *_ = env.step(np.array([0.0, 0.0, 0.5, 0.25], np.float32))
        angles.append(obs["flipper_angle_rad"].astype(float))
    # From 0.25 s to 0.75 s (the servo settled), tips rising in the air: 0.5 and 0.25 rad/s
    # within 2 %. (Lowered, a tip meets the ground and the torque limit slows it: physics.)
    rate = (angles[14] - angles[4]) / 0.5
    assert rate == pytest.approx([0.5, 0.25], rel=0.02)
    for _ in range(30):
        obs, *_ = env.step(np.array([0.0, 0.0, 1.0, 1.0], np.float32))
    # Held at the range's top (60 deg) within the servo's deflection.
    assert obs["flipper_angle_rad"] == pytest.approx(np.radians([60.0, 60.0]), abs=0.01)


def test_recorded_episodes_open_in_view_and_replay_byte_for_byte(tmp_path):
    rec = tmp_path / "episodes"
    env = tracksim.TracksimEnv(STAIRS, config={"record_dir": rec, "flipper_action": "velocity"})
    env.reset(seed=11)
    for k in range(30):
        env.step(np.array([0.8, 0.2 if k < 15 else -0.2, 0.6, 0.3], np.float32))
    t = env._core.time
    env.reset(seed=12)  # writes the first episode
    env.step(np.array([0.5, 0.0, 0.0, 0.0], np.float32))
    env.close()  # writes the second
    folders = sorted(p.name for p in rec.iterdir())
    assert folders == ["seed11-ep0", "seed12-ep1"]
    ep = rec / "seed11-ep0"
    for f in ("summary.json", "trajectory.csv", "scene.json", "belts.csv", "commands.toml"):
        assert (ep / f).is_file(), f
    summary = json.loads((ep / "summary.json").read_text())
    assert summary["outcome"] == "interrupted"  # reset before the episode's end
    out = tmp_path / "replay"
    r = run_cli("run", STAIRS, "--commands", ep / "commands.toml", "--duration", repr(t),
                "--out", out, "--no-plot", "--quiet")
    assert r.returncode == 0, r.stderr
    assert (out / "trajectory.csv").read_bytes() == (ep / "trajectory.csv").read_bytes()


def ws_states(url, n, timeout=10.0):
    """The first `n` state messages of the page's WebSocket (a minimal RFC 6455 client)."""
    host, port = re.match(r"http://([^:/]+):(\d+)/", url).groups()
    s = socket.create_connection((host, int(port)), timeout=timeout)
    key = base64.b64encode(os.urandom(16)).decode()
    s.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
               f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
               "Sec-WebSocket-Version: 13\r\n\r\n").encode())
    buf = b""
    while b"\r\n\r\n" not in buf:
        buf += s.recv(4096)
    head, buf = buf.split(b"\r\n\r\n", 1)
    assert b" 101 " in head.split(b"\r\n")[0], head

    def take(k):
        nonlocal buf
        while len(buf) < k:
            chunk = s.recv(65536)
            assert chunk, "connection closed"
            buf += chunk
        out, buf = buf[:k], buf[k:]
        return out

    states = []
    while len(states) < n:
        b0, b1 = take(2)
        length = b1 & 0x7F
        if length == 126:
            length = struct.unpack(">H", take(2))[0]
        elif length == 127:
            length = struct.unpack(">Q", take(8))[0]
        payload = take(length)
        if b0 & 0x0F == 1:
            msg = json.loads(payload)
            if msg.get("type") == "hello":
                assert msg["role"] == "watcher"
            elif msg.get("type") == "state":
                states.append(msg)
    s.close()
    return states


def test_human_render_serves_the_live_page_with_moving_states(capsys):
    env = tracksim.TracksimEnv(STAIRS, render_mode="human", render_speed=None)
    assert env.metadata["render_modes"] == ["human", "rgb_array"]
    env.reset(seed=0)
    assert env.render_url is None and env.render() is None  # nothing served before a step
    env.step(np.array([0.0, 0.0, 0.0, 0.0], np.float32))
    url = env.render_url
    assert url.startswith("http://127.0.0.1:")
    assert url in capsys.readouterr().out
    page = urllib.request.urlopen(url, timeout=10).read()
    assert b"<html" in page.lower()
    scene = json.loads(urllib.request.urlopen(url + "scene.json", timeout=10).read())
    assert scene
    # Watch-only (issue 44): the page is told so and has no token to drive with.
    session = json.loads(urllib.request.urlopen(url + "session.json", timeout=10).read())
    assert session["watch_only"] is True and session["token"] is None
    got = {}
    reader = threading.Thread(target=lambda: got.setdefault("s", ws_states(url, 5)))
    reader.start()
    for _ in range(400):
        env.step(np.array([1.0, 0.0, 0.0, 0.0], np.float32))
        if not reader.is_alive():
            break
        time.sleep(0.01)
    reader.join(10)
    first, last = got["s"][0], got["s"][-1]
    assert last["t"] > first["t"]
    assert last["pose"][0] > first["pose"][0]  # driving forwards: the robot moves on the page
    # Nobody drives: no driver's status; the belts, speed and slip of the learner's robot (an
    # environment that records nothing: read from its simulation).
    assert last["driver"] is None
    assert last["belt_position"][0] > first["belt_position"][0]
    assert min(last["belt_speed"]) > 0.05 and last["forward_mps"] > 0.0  # 0.0 without samples
    assert len(last["slip"]) == len(last["belt_speed"])
    env.close()


def test_unknown_render_modes_are_refused_naming_the_modes():
    with pytest.raises(ValueError) as e:
        tracksim.TracksimEnv(STAIRS, render_mode="ansi")
    msg = str(e.value)
    for alt in ("'human'", "'rgb_array'", "RecordVideo"):
        assert alt in msg
    with pytest.raises(ValueError, match="renders frames only"):
        tracksim.TracksimVectorEnv(STAIRS, 2, render_mode="human")


def test_a_bad_render_port_is_named():
    for port in (-1, 70000, "8080", 1.5):
        with pytest.raises(ValueError, match="render_port: a TCP port from 0 to 65535"):
            tracksim.TracksimEnv(str(SCENARIOS / "packbot_flat.toml"), render_mode="human", render_port=port)


def test_check_env_with_the_render_check_starts_no_server(monkeypatch):
    """gymnasium's check_env makes an environment of every declared render mode ("human"
    included), resets it and calls render(): no page is served for it (the page starts at the
    first step)."""
    import gymnasium as gym

    import tracksim.env as tenv

    started, live_view = [], tenv.LiveView

    def counting(*a, **k):
        started.append(1)
        return live_view(*a, **k)

    monkeypatch.setattr(tenv, "LiveView", counting)
    env = gym.make("tracksim/PackBotFlat-v0")
    check_env(env.unwrapped, skip_render_check=False)
    env.close()
    assert started == []
    # The counting is live: a human env that is reset does serve its page.
    h = tracksim.TracksimEnv(str(SCENARIOS / "packbot_flat.toml"), render_mode="human",
                             render_speed=None)
    h.reset(seed=0)
    h.render()
    assert started == []
    h.step(h.action_space.sample())
    h.close()
    assert started == [1]


def test_an_episode_of_a_randomised_scenario_replays_with_its_seed(tmp_path):
    """`tracksim run FILE --seed S --commands .../commands.toml` re-runs the recorded episode of
    seed S of a randomised file (its folder `seed<S>-ep<K>` names the seed) byte for byte; with
    the file's own seed the drawn step differs and so does the trajectory."""
    rec = tmp_path / "episodes"
    env = tracksim.TracksimEnv(STEP, config={"record_dir": rec})
    env.reset(seed=7)
    for _ in range(40):
        env.step(np.array([0.6, 0.0, 0.3, 0.3], np.float32))
    t = env._core.time
    env.close()
    ep = rec / "seed7-ep0"
    assert ep.is_dir()
    runs = {}
    for name, seed in (("seed", ["--seed", "7"]), ("file", [])):
        out = tmp_path / name
        r = run_cli("run", STEP, *seed, "--commands", ep / "commands.toml", "--duration",
                    repr(t), "--out", out, "--no-plot", "--quiet")
        assert r.returncode == 0, r.stderr
        runs[name] = (out / "trajectory.csv").read_bytes()
    assert runs["seed"] == (ep / "trajectory.csv").read_bytes()
    assert runs["file"] != runs["seed"]
    r = run_cli("run", STEP, "--seed", "7", "--ensemble", "2", "--out", tmp_path / "e")
    assert r.returncode == 2 and "--seed" in r.stderr
