"""`tracksim ros` against an independent DDS implementation (Eclipse Cyclone DDS, the PyPI
`cyclonedds` package with its own C library), with every packet kept on this machine: the
peer (ros_peer.py) and the node run in a network namespace made here with only `lo`
(`unshare --net`, needs root: CI runs as root). The peer subscribes /odom and /joint_states
(ROS 2 type names, CDR), publishes /cmd_vel at 0.3 m/s for 4 s, then goes silent. In its
`team` mode it drives the two robots of scenarios/team/corridor_head_on.toml by their own
namespaced topics (/west/cmd_vel, /east/cmd_vel) and lets one fall silent.
"""

import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from conftest import cli

PEER = pathlib.Path(__file__).with_name("ros_peer.py")


def _can_run():
    """Why the test cannot run here (None: it can). On CI a missing piece fails the test."""
    try:
        import cyclonedds  # noqa: F401
    except ImportError:
        return "the cyclonedds package is not installed (python/requirements-ci.txt)"
    if os.geteuid() != 0:
        return "needs root for a network namespace (unshare --net)"
    if shutil.which("unshare") is None or shutil.which("ip") is None:
        return "needs unshare (util-linux) and ip (iproute2)"
    return None


def _peer(tmp_path_factory, mode):
    why = _can_run()
    if why:
        if os.environ.get("CI"):
            pytest.fail(why)
        pytest.skip(why)
    out = tmp_path_factory.mktemp("ros") / "run"
    p = subprocess.run(
        ["unshare", "--net", sys.executable, str(PEER), cli(), str(out), mode],
        capture_output=True,
        text=True,
        timeout=180,
    )
    lines = [line for line in p.stdout.splitlines() if line.startswith("{")]
    assert lines, f"peer printed no result (exit {p.returncode}): {p.stderr[-3000:]}"
    r = json.loads(lines[-1])
    assert "error" not in r, r
    r["out"] = out
    return r


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    return _peer(tmp_path_factory, "drive")


@pytest.fixture(scope="module")
def sensors(tmp_path_factory):
    """packbot_sensors: flippers, sensors, and bad commands (ros_peer.py `sensors`)."""
    return _peer(tmp_path_factory, "sensors")


def test_only_loopback_in_the_namespace(session):
    assert session["links"] == ["lo"]


def test_odometry_frames_and_joint_names(session):
    assert session["frame_id"] == "odom"
    assert session["child_frame_id"] == "base_link"
    assert session["joint_names"] == ["left_belt", "right_belt"]
    # 100 Hz for about 6 s.
    assert session["odom_messages"] > 300


def test_cmd_vel_drives_the_robot(session):
    v = session["forward_mps"]
    elapsed = session["t_driven"] - session["t_start"]
    dx = session["odom_x_driven"] - session["odom_x_start"]
    # Driven at v for most of the elapsed simulated time (minus the first command's latency
    # and the start-up), never faster.
    assert 0.7 * v * elapsed < dx < 1.05 * v * elapsed, (dx, elapsed)
    assert abs(session["odom_v_driven"] - v) < 0.05 * v
    assert abs(session["truth_v_driven"] - v) < 0.1 * v


def test_belt_joint_positions_advance(session):
    start, driven = session["joints_start"], session["joints_driven"]
    dx = session["odom_x_driven"] - session["odom_x_start"]
    for a, b in zip(start, driven):
        # Belt travel is at least the distance covered (slip only adds to it).
        assert b - a > 0.95 * dx


def test_silent_cmd_vel_stops_the_robot(session):
    # 1.5 s of silence: the 0.5 s watchdog has stopped it.
    assert session["t_stopped"] - session["t_driven"] > 1.0
    assert abs(session["odom_v_stopped"]) < 0.02
    assert abs(session["truth_v_stopped"]) < 0.03
    # It coasts at most a few centimetres after the watchdog stopped the belts.
    v = session["forward_mps"]
    travelled = session["odom_x_stopped"] - session["odom_x_driven"]
    assert travelled < v * (0.5 + 0.2), travelled
    assert "watchdog" in session["stderr"]


def test_sigterm_writes_the_run(session):
    assert session["exit_code"] == 130
    summary = json.loads((session["out"] / "summary.json").read_text())
    assert summary["outcome"] == "interrupted"
    assert (session["out"] / "commands.toml").exists()


def test_imu_at_its_rate_with_gravity(sensors):
    # vehicles/packbot510_sensors.toml: imu at 200 Hz, in imu_link; at rest the specific
    # force is +g along z.
    assert sensors["imu_frame"] == "imu_link"
    assert 180.0 < sensors["imu_rate_hz"] < 205.0, sensors["imu_rate_hz"]
    assert 9.3 < sensors["imu_accel_z"] < 10.3, sensors["imu_accel_z"]


def test_flipper_commands_by_float64_and_joint_state(sensors):
    assert sensors["joint_names"][:2] == ["front_left", "front_right"]
    # front_left by /flippers/front_left/cmd_position, front_right by
    # /flippers/cmd_positions (beside an unknown name): both reach 0.9 rad.
    for a in sensors["flipper_end"]:
        assert abs(a - 0.9) < 0.05, sensors["flipper_end"]


def test_bad_commands_never_reach_the_physics(sensors):
    # NaN cmd_vel for 3 s: dropped, the robot stays put.
    assert abs(sensors["odom_dx"]) < 0.01
    for text in ("not a finite number", 'no flipper named "no_such_flipper"'):
        assert any(text in m for m in sensors["rosout"]), sensors["rosout"]
        assert text in sensors["stderr"]
    # Rate-limited: about one warning of each kind per second over 3 s, not 60.
    assert len(sensors["rosout"]) <= 10
    assert "more like it" in sensors["stderr"]


@pytest.fixture(scope="module")
def urdf_robot(tmp_path_factory):
    """packbot_urdf_stairs: the bundled URDF robot (ros_peer.py `urdf`)."""
    return _peer(tmp_path_factory, "urdf")


def test_the_bundled_urdf_robot_runs_under_ros(urdf_robot):
    # Joints by their URDF names, then the belts of vehicles/packbot510_urdf.toml's tracks.
    names = urdf_robot["joint_names"]
    assert names[:2] == ["front_left", "front_right"], names
    assert "left_belt" in names and "flipper_left_belt" in names, names
    # /cmd_vel at 0.3 m/s for 2 s drove it (after discovery latency), and front_left rose
    # towards its 0.6 rad command while front_right stayed at 0.
    assert 0.2 < urdf_robot["odom_dx"] < 0.65, urdf_robot["odom_dx"]
    fl, fr = urdf_robot["positions"][:2]
    assert 0.45 < fl < 0.65 and abs(fr) < 0.05, (fl, fr)


def test_elevation_map_live_in_map_frame(sensors):
    # vehicles/packbot510_sensors.toml: 2 x 2 m at 0.03125 m (64 x 64 cells), 20 Hz, an
    # organised PointCloud2 of the cells' surface points in the world frame. The robot stands
    # on flat ground (z = 0) with the stairs 0.9 m ahead: most known cells are at z = 0.
    assert sensors.get("elevation_messages", 0) > 20, sensors.get("elevation_messages")
    assert sensors["elevation_frame"] == "map"
    assert sensors["elevation_shape"] == [64, 64, 12]
    assert sensors["elevation_fields"] == ["x", "y", "z"]
    assert sensors["elevation_known"] > 1000
    assert abs(sensors["elevation_median_z"]) < 0.02, sensors["elevation_median_z"]


@pytest.fixture(scope="module")
def team(tmp_path_factory):
    """corridor_head_on: two robots on one node (ros_peer.py `team`)."""
    return _peer(tmp_path_factory, "team")


def test_team_robots_are_namespaced_on_one_node(team):
    assert team["links"] == ["lo"]
    for n in ("west", "east"):
        assert team["frame_ids"][n] == f"{n}/odom"
        assert team["child_frame_ids"][n] == f"{n}/base_link"
        # One /tf carries every robot's transforms.
        assert [f"{n}/odom", f"{n}/base_link"] in team["tf_pairs"], team["tf_pairs"]
        assert ["map", f"{n}/odom"] not in team["tf_pairs"], "map -> odom only with --map-tf"
    # No robot on the one-robot names.
    assert team["plain_odom_messages"] == 0


TEAM_BOTH_S = 3.0  # ros_peer.py: both robots driven this long


def test_team_robots_move_as_each_is_commanded(team):
    for n, v in team["commanded"].items():
        assert abs(team["both"][n]["v"] - v) < 0.05 * abs(v) + 0.01, (n, team["both"][n])
        dx = team["both"][n]["x"] - team["start"][n]["x"]
        # Odometry starts at the robot's start pose in the world: west drives forward (+x);
        # east, facing west (-x), backs away from it (+x too). At least half of 3 s of driving.
        assert dx > 0.5 * abs(v) * TEAM_BOTH_S, (n, dx)


def test_team_silent_peer_stops_its_robot_only(team):
    west, east = team["one"]["west"], team["one"]["east"]
    assert abs(west["v"] - team["commanded"]["west"]) < 0.02, west
    assert abs(east["v"]) < 0.02, east
    # East coasts a few centimetres after its watchdog; west drove on for 2 s.
    assert abs(east["x"] - team["both"]["east"]["x"]) < 0.2 * 0.7
    assert west["x"] - team["both"]["west"]["x"] > 0.3 * 1.5
    assert "`east`: watchdog" in team["stderr"]
    assert "`west`: watchdog" not in team["stderr"]


def test_team_session_writes_the_world_and_replays(team, tmp_path):
    out = team["out"]
    assert team["exit_code"] == 130
    summary = json.loads((out / "team.json").read_text())
    assert [r["name"] for r in summary["robots"]] == ["west", "east"]
    for n in ("west", "east"):
        assert (out / n / "trajectory.csv").exists()
    text = (out / "commands.toml").read_text()
    assert 'name = "west"' in text and 'name = "east"' in text
    line = next(x for x in text.splitlines() if "tracksim run" in x)
    # The header's command: `--duration T`, then `--keep-running` (a session goes on past
    # its outcome, so its replay does too).
    duration, *rest = line.split("--duration")[1].split()
    again = tmp_path / "again"
    p = subprocess.run(
        [cli(), "run", team["scenario"], "--commands", str(out / "commands.toml"),
         "--duration", duration, *rest, "--out", str(again), "--no-plot", "--quiet"],
        capture_output=True, text=True, timeout=300,
    )
    assert p.returncode in (0, 1), p.stderr
    for n in ("west", "east"):
        assert (again / n / "trajectory.csv").read_text() == (out / n / "trajectory.csv").read_text(), n


@pytest.fixture(scope="module")
def solo(tmp_path_factory):
    """packbot_flat with --namespace solo (ros_peer.py `namespace`)."""
    return _peer(tmp_path_factory, "namespace")


def test_one_robot_namespaced_on_request(solo):
    assert solo["frame_id"] == "solo/odom"
    assert solo["child_frame_id"] == "solo/base_link"
    assert ["solo/odom", "solo/base_link"] in solo["tf_pairs"], solo["tf_pairs"]
    assert solo["plain_odom_messages"] == 0
    # 2 s of /solo/cmd_vel at 0.3 m/s drove it (less the discovery latency).
    assert 0.2 < solo["odom_dx"] < 0.65, solo["odom_dx"]


@pytest.fixture(scope="module")
def camera(tmp_path_factory):
    """packbot_camera: a colour camera's compressed images and calibration (issue 41)."""
    return _peer(tmp_path_factory, "camera")


def test_colour_camera_publishes_png_and_camera_info(camera):
    import math

    assert camera["links"] == ["lo"]
    assert camera["images"] >= 5 and camera["infos"] >= 5, camera
    assert camera["raw_images"] == 0  # the raw topic only with --raw-images
    assert camera["stamps_paired"]
    assert camera["format"] == "rgb8; png compressed bgr8"
    assert camera["frame_id"] == camera["info_frame_id"] == "front_rgb_optical_frame"
    assert camera["png_signature"] == "89504e470d0a1a0a"
    assert camera["png_size"] == [160, 120] and camera["png_mode"] == "RGB"
    assert camera["info_size"] == [160, 120]
    f = 80.0 / math.tan(math.radians(35.0))
    assert camera["k"] == pytest.approx([f, 0, 80, 0, f, 60, 0, 0, 1])
    assert camera["p"] == pytest.approx([f, 0, 80, 0, 0, f, 60, 0, 0, 0, 1, 0])
    assert camera["distortion_model"] == "plumb_bob" and camera["d"] == [0.0] * 5


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """course_stairs driven by its own commands (ros_peer.py `course`)."""
    return _peer(tmp_path_factory, "course")


def test_course_score_on_ros_topics(course):
    """/course and /course/events from the node equal the score the session writes: every
    event once (a late reader gets them: transient local), and the first completed status
    received is the summary's score."""
    assert course["links"] == ["lo"]
    summary = json.loads((course["out"] / "summary.json").read_text())
    c = summary["course"]
    assert c["status"] == "completed", c
    got = course["events"]
    assert [(e["kind"], e["detail"]) for e in got] == [
        (e["kind"], e["detail"]) for e in c["events"]
    ]
    for e, want in zip(got, c["events"]):
        assert abs(e["t"] - want["t_s"]) < 1e-9
        assert e["fault"] == want.get("fault", "")
        assert e["penalty"] == want.get("penalty_s", 0.0)
    assert course["stamps_increase"] and course["gates_never_fall"]
    assert course["before_finish"] == ["running"], "every status before the finish says running"
    done = course["completed"]
    assert done["frame_id"] == "map"
    assert done["name"] == c["name"] and done["finished"]
    # The node runs --fast: a reader keeping 10 may miss a few statuses, never the score.
    assert done["t"] >= c["score"]["time_s"] - 1e-9, "completed from the finishing sample on"
    assert done["elapsed"] == c["elapsed_s"] == c["score"]["time_s"], "the clock stops at the finish"
    assert (done["gates_passed"], done["gates_total"]) == (c["gates_passed"], c["gates_total"])
    assert done["repetitions_done"] == c["repetitions_done"]
    assert done["repetition_times"] == c["rep_times_s"]
    assert done["time_limit"] == c.get("time_limit_s", 0.0)
    assert (done["trial_time"], done["penalty"], done["score"]) == (
        c["score"]["time_s"],
        c["penalty_s"],
        c["score"]["score_s"],
    )
    assert done["score"] == done["trial_time"] + done["penalty"]
    # The score holds after the finish (the session goes on until stopped).
    assert course["last"] == {"status": "completed", "score": c["score"]["score_s"]}
