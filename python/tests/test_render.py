"""Issue 41 (learners): render_mode="rgb_array" frames of the chase camera or an rgb_camera
sensor (uint8, (H, W, 3)), reproducible by seed, moving with the robot; metadata["render_fps"]
the control rate; gymnasium's RecordVideo writing an mp4 of an episode (moviepy and the ffmpeg
of imageio-ffmpeg's wheel); check_env with rgb_array; the vector env's batched frames; a camera
image in a dict observation with its Box space."""

import numpy as np
import gymnasium as gym
import pytest
from gymnasium.utils.env_checker import check_env

import tracksim
from conftest import SCENARIOS

CAMERA = str(SCENARIOS / "packbot_camera.toml")
FLAT = str(SCENARIOS / "packbot_flat.toml")
FORWARD = np.array([1.0, 0.0, 0.0, 0.0], np.float32)


def test_rgb_array_frames_are_uint8_of_the_chosen_size():
    env = tracksim.TracksimEnv(FLAT, render_mode="rgb_array")
    env.reset(seed=0)
    f = env.render()
    assert isinstance(f, np.ndarray) and f.dtype == np.uint8 and f.shape == (120, 160, 3)
    # Sky above, ground below: not a blank frame.
    assert f[:10].mean() != f[-10:].mean() and f.std() > 5
    assert env.metadata["render_fps"] == pytest.approx(1.0 / env.control_period_s)
    assert env.metadata["render_fps"] == pytest.approx(20.0)  # the default 50 ms period
    small = tracksim.TracksimEnv(FLAT, render_mode="rgb_array", render_size=(64, 48),
                                 config={"control_period_s": 0.1})
    small.reset(seed=0)
    assert small.render().shape == (48, 64, 3)
    assert small.metadata["render_fps"] == pytest.approx(10.0)
    # No render mode: nothing rendered.
    assert tracksim.TracksimEnv(FLAT).render() is None


def test_same_seed_same_frames_and_the_frame_moves_with_the_robot():
    env = tracksim.TracksimEnv(CAMERA, render_mode="rgb_array")

    def episode(seed):
        env.reset(seed=seed)
        frames = [env.render()]
        for _ in range(20):
            env.step(FORWARD)
        frames.append(env.render())
        return frames

    a, b = episode(3), episode(3)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    # Driving 1 s at 0.5 m/s changes the view (the boxes come nearer).
    diff = np.abs(a[0].astype(int) - a[1].astype(int))
    assert (diff.sum(axis=2) > 30).mean() > 0.01, (diff.sum(axis=2) > 30).mean()
    # Rendering does not change the simulation: the same steps give the same observations.
    env.reset(seed=3)
    seen = [env.step(FORWARD)[0] for _ in range(5) if env.render() is not None]
    env.reset(seed=3)
    unseen = [env.step(FORWARD)[0] for _ in range(5)]
    assert all(np.array_equal(x, y) for x, y in zip(seen, unseen))


def test_a_named_rgb_camera_sensor_is_rendered_and_unknown_names_refused():
    env = tracksim.TracksimEnv(CAMERA, render_mode="rgb_array", render_camera="front_rgb")
    env.reset(seed=0)
    for _ in range(4):
        env.step(FORWARD)
    f = env.render()
    assert f.shape == (120, 160, 3) and f.dtype == np.uint8 and f.std() > 5
    with pytest.raises(ValueError, match="render_camera.*front_rgb"):
        tracksim.TracksimEnv(CAMERA, render_mode="rgb_array", render_camera="rear")
    with pytest.raises(ValueError, match="no rgb_camera"):
        tracksim.TracksimEnv(FLAT, render_mode="rgb_array", render_camera="front_rgb")
    with pytest.raises(ValueError, match="render_size_px"):
        tracksim.TracksimEnv(FLAT, render_mode="rgb_array", render_size=(0, 10))


def test_check_env_passes_with_rgb_array():
    env = tracksim.TracksimEnv(FLAT, render_mode="rgb_array", render_size=(32, 24))
    check_env(env, skip_render_check=False)


def test_record_video_writes_an_mp4_of_an_episode(tmp_path):
    pytest.importorskip("moviepy")
    env = tracksim.TracksimEnv(CAMERA, render_mode="rgb_array",
                               config={"control_period_s": 0.1})
    env = gym.wrappers.TimeLimit(env, max_episode_steps=15)
    env = gym.wrappers.RecordVideo(env, str(tmp_path), episode_trigger=lambda e: True,
                                   name_prefix="camera", disable_logger=True)
    env.reset(seed=0)
    done = False
    while not done:
        _, _, term, trunc, _ = env.step(FORWARD)
        done = term or trunc
    env.close()
    videos = sorted(tmp_path.glob("camera-episode-0.mp4"))
    assert videos, list(tmp_path.iterdir())
    data = videos[0].read_bytes()
    assert len(data) > 1000 and data[4:8] == b"ftyp"  # an MP4 container
    # Read back: 16 frames (the reset's and 15 steps') of the rendered size at the control rate.
    from moviepy import VideoFileClip
    clip = VideoFileClip(str(videos[0]))
    assert tuple(clip.size) == (160, 120)
    assert clip.fps == pytest.approx(10.0)
    assert clip.duration == pytest.approx(1.6, abs=0.15)
    clip.close()


def test_vector_env_renders_batched_frames_equal_to_single_envs():
    v = tracksim.TracksimVectorEnv(CAMERA, 3, threads=2, render_mode="rgb_array",
                                   render_size=(48, 32))
    v.reset(seed=5)
    for _ in range(3):
        v.step(np.tile(FORWARD, (3, 1)))
    frames = v.render()
    assert frames.dtype == np.uint8 and frames.shape == (3, 32, 48, 3)
    assert v.metadata["render_fps"] == pytest.approx(20.0)
    single = tracksim.TracksimEnv(CAMERA, render_mode="rgb_array", render_size=(48, 32))
    for i in range(3):
        single.reset(seed=5 + i)
        for _ in range(3):
            single.step(FORWARD)
        assert np.array_equal(frames[i], single.render()), i
    v.close()


def test_an_rgb_camera_is_in_the_dict_observation_with_its_box():
    env = tracksim.TracksimEnv(CAMERA, config={"observation": "dict"})
    space = env.observation_space["front_rgb"]
    assert space.shape == (120, 160, 3) and space.dtype == np.float32
    assert space.low.min() == 0.0 and space.high.max() == 255.0
    obs, _ = env.reset(seed=0)
    for _ in range(4):
        obs, *_ = env.step(FORWARD)
    img = obs["front_rgb"]
    assert env.observation_space.contains(obs)
    assert img.shape == (120, 160, 3) and img.std() > 5
    assert np.array_equal(img, np.round(img))  # whole 8-bit levels
    # The same image as the sensor's rendered frame.
    cam = tracksim.TracksimEnv(CAMERA, config={"observation": "dict"}, render_mode="rgb_array",
                               render_camera="front_rgb")
    cam.reset(seed=0)
    for _ in range(4):
        o, *_ = cam.step(FORWARD)
    assert np.array_equal(o["front_rgb"].astype(np.uint8), cam.render())
    v = tracksim.TracksimVectorEnv(CAMERA, 2, config={"observation": "dict"})
    obs, _ = v.reset(seed=0)
    assert obs["front_rgb"].shape == (2, 120, 160, 3)
    v.close()


def test_a_registered_task_renders_through_gymnasium_make():
    env = gym.make("tracksim/PackBotSteps-v0", render_mode="rgb_array", render_size=(32, 24))
    assert env.render_mode == "rgb_array"
    env.reset(seed=0)
    f = env.render()
    assert f.dtype == np.uint8 and f.shape == (24, 32, 3)
    check_env(env.unwrapped, skip_render_check=False)
    env.close()
