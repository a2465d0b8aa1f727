"""run.mcap read by code no one here wrote (issue 27): a real `tracksim run --mcap` of the
sensor scenario, read with the `mcap` package, every message decoded from its own `ros2msg`
schema twice, by `mcap-ros2-support` and by `rosbags` (two independent CDR decoders and .msg
parsers), and the values checked against the run's trajectory.csv and the vehicle file."""

import collections
import csv
import math
import sys

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

try:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
except ImportError:  # rosbags needs Python 3.10+ (requirements-ci.txt)
    if sys.version_info >= (3, 10):
        raise
    get_typestore = None

from conftest import SCENARIOS, run_cli

SENSORS = SCENARIOS / "packbot_sensors.toml"
DURATION_S = 1.0
OUTPUT_INTERVAL_S = 0.01
#: The sensors of vehicles/packbot510_sensors.toml: topic -> (type, rate Hz).
SENSOR_TOPICS = {
    "/imu": ("sensor_msgs/msg/Imu", 200.0),
    "/encoders": ("sensor_msgs/msg/JointState", 100.0),
    "/scan": ("sensor_msgs/msg/LaserScan", 10.0),
    "/elevation": ("sensor_msgs/msg/PointCloud2", 20.0),
    "/front_camera": ("sensor_msgs/msg/Image", 5.0),
    "/flipper_imu": ("sensor_msgs/msg/Imu", 100.0),
}
#: One message per output sample.
SAMPLE_TOPICS = {
    "/clock": "rosgraph_msgs/msg/Clock",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/odom": "nav_msgs/msg/Odometry",
    "/ground_truth/odom": "nav_msgs/msg/Odometry",
    "/joint_states": "sensor_msgs/msg/JointState",
    "/tracks": "tracksim_msgs/msg/TrackStates",
}
JOINTS = ["front_left", "front_right", "left_belt", "right_belt", "flipper_left_belt",
          "flipper_right_belt"]
TRACKS = ["left", "right", "flipper_left", "flipper_right"]


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """The run folder, the MCAP header and summary, and every message decoded both ways:
    topic -> [(log time ns, mcap-ros2 message, rosbags message)]."""
    out = tmp_path_factory.mktemp("mcap")
    r = run_cli("run", SENSORS, "--out", out, "--mcap", "--duration", DURATION_S, "--no-plot",
                "--quiet", timeout=300)
    assert r.returncode == 0, r.stderr
    path = out / "run.mcap"
    store = get_typestore(Stores.EMPTY) if get_typestore else None
    msgs = collections.defaultdict(list)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        header = reader.get_header()
        summary = reader.get_summary()
        for schema in summary.schemas.values() if store else ():
            # rosbags parses the schema text (the type, then `===` / `MSG: pkg/Type` blocks).
            if schema.encoding == "ros2msg":
                store.register(get_types_from_msg(schema.data.decode(), schema.name))
        # The ROS 2 channels (Foxglove's JSON `/scene` is checked apart).
        cdr = [c.topic for c in summary.channels.values() if c.message_encoding == "cdr"]
        for schema, channel, message, decoded in reader.iter_decoded_messages(
                topics=cdr, log_time_order=True):
            # Without rosbags (Python 3.9) the comparisons below compare mcap-ros2's with itself.
            other = store.deserialize_cdr(message.data, schema.name) if store else decoded
            msgs[channel.topic].append((message.log_time, decoded, other))
    return out, header, summary, msgs


def test_every_channel_is_ros2_cdr_with_its_schema(recording):
    _, header, summary, msgs = recording
    assert header.profile == "ros2"
    types = {}
    for channel in summary.channels.values():
        if channel.topic == "/scene":  # Foxglove's scene (issue 42): JSON
            assert channel.message_encoding == "json"
            assert summary.schemas[channel.schema_id].name == "foxglove.SceneUpdate"
            continue
        assert channel.message_encoding == "cdr", channel.topic
        schema = summary.schemas[channel.schema_id]
        assert schema.encoding == "ros2msg", channel.topic
        assert "offered_qos_profiles" in channel.metadata
        types[channel.topic] = schema.name
    assert types == {**SAMPLE_TOPICS, "/tf_static": "tf2_msgs/msg/TFMessage",
                     "/robot_description": "std_msgs/msg/String",
                     **{t: ty for t, (ty, _) in SENSOR_TOPICS.items()}}
    # The per-track message carries its definition, dependencies in `MSG:` blocks.
    tracks = next(s for s in summary.schemas.values() if s.name.startswith("tracksim_msgs"))
    text = tracks.data.decode()
    assert "float64[] slip" in text and "float64[] normal_load" in text
    assert "\n" + "=" * 80 + "\nMSG: std_msgs/Header\n" in text
    # Every message was decoded (by both readers): the counts are those of the statistics.
    stats = summary.statistics.channel_message_counts
    for channel_id, channel in summary.channels.items():
        if channel.message_encoding == "cdr":
            assert len(msgs[channel.topic]) == stats[channel_id], channel.topic


def test_counts_are_rates_times_duration_and_log_times_are_sim_time(recording):
    _, _, _, msgs = recording
    n = round(DURATION_S / OUTPUT_INTERVAL_S) + 1
    for topic in SAMPLE_TOPICS:
        assert len(msgs[topic]) == n, topic
    for topic, (_, rate) in SENSOR_TOPICS.items():
        assert len(msgs[topic]) == math.floor(rate * DURATION_S + 1e-6) + 1, topic
    assert len(msgs["/tf_static"]) == 1
    for topic, entries in msgs.items():
        if topic == "/robot_description":
            # A latched std_msgs/String (no header): the robot's URDF, once.
            assert len(entries) == 1 and "<robot" in entries[0][1].data
            continue
        for log_time, m, _ in entries:
            stamp = m.clock if topic == "/clock" else (
                m.transforms[0].header.stamp if topic.startswith("/tf") else m.header.stamp)
            assert stamp.sec * 1_000_000_000 + stamp.nanosec == log_time, topic
    assert [t for t, _, _ in msgs["/clock"]][-1] == round(DURATION_S * 1e9)


def yaw(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def test_odometry_is_trajectory_csv_and_advances(recording):
    out, _, _, msgs = recording
    with open(out / "trajectory.csv") as f:
        rows = list(csv.DictReader(f))
    odom, truth = msgs["/odom"], msgs["/ground_truth/odom"]
    assert len(rows) == len(odom) == len(truth)
    for row, (_, o, ob), (_, g, _) in zip(rows, odom, truth):
        assert o.header.frame_id == "odom" and o.child_frame_id == "base_link"
        p = o.pose.pose.position
        # The two decoders agree to the bit.
        assert (p.x, p.y, p.z) == (ob.pose.pose.position.x, ob.pose.pose.position.y,
                                   ob.pose.pose.position.z)
        assert p.x == pytest.approx(float(row["odom_x_m"]), abs=5.1e-7)
        assert p.y == pytest.approx(float(row["odom_y_m"]), abs=5.1e-7)
        assert yaw(o.pose.pose.orientation) == pytest.approx(float(row["odom_yaw_rad"]),
                                                             abs=5.1e-7)
        q = g.pose.pose.position
        assert q.x == pytest.approx(float(row["x_m"]), abs=5.1e-7)
        assert q.z == pytest.approx(float(row["z_m"]), abs=5.1e-7)
    xs = [o.pose.pose.position.x for _, o, _ in odom]
    assert xs[0] == 0.0 and xs[-1] > 0.1
    assert all(b >= a - 1e-4 for a, b in zip(xs, xs[1:]))  # it drives forwards
    # The encoders' forward speed at the end: the belts' mean speed (slip included).
    assert odom[-1][1].twist.twist.linear.x > 0.05


def test_joint_states_tf_and_tracks(recording):
    _, _, _, msgs = recording
    for _, j, jb in msgs["/joint_states"]:
        assert list(j.name) == JOINTS and list(jb.name) == JOINTS
        assert len(j.position) == len(j.velocity) == len(JOINTS)
    # The belts' travel (continuous joints, m) grows as the robot drives.
    last = msgs["/joint_states"][-1][1]
    assert last.position[2] > 0.1 and last.position[3] > 0.1
    for _, tf, _ in msgs["/tf"]:
        frames = [(t.header.frame_id, t.child_frame_id) for t in tf.transforms]
        assert frames == [("odom", "base_link"), ("base_link", "front_left_flipper_link"),
                          ("base_link", "front_right_flipper_link"), ("map", "odom")]
    static = {t.child_frame_id: t.header.frame_id
              for t in msgs["/tf_static"][0][1].transforms}
    assert static["imu_link"] == "base_link"
    assert static["front_camera_optical_frame"] == "front_camera_link"
    assert static["flipper_imu_link"].endswith("_flipper_link")
    for _, k, kb in msgs["/tracks"]:
        assert list(k.name) == TRACKS
        assert len(k.slip) == len(k.traction) == len(k.normal_load) == len(TRACKS)
        assert list(k.contacts) == list(kb.contacts)
    # Resting on the ground the tracks carry the robot's weight (PackBot 510: about 11 kg
    # without flippers' own share, tens of newtons each).
    load = sum(msgs["/tracks"][-1][1].normal_load)
    assert 50.0 < load < 500.0, load


def test_sensor_messages_decode_to_their_data(recording):
    _, _, _, msgs = recording
    imu = msgs["/imu"][0][1]
    assert imu.header.frame_id == "imu_link"
    assert imu.linear_acceleration.z == pytest.approx(9.81, abs=0.1)
    q = imu.orientation
    assert q.x ** 2 + q.y ** 2 + q.z ** 2 + q.w ** 2 == pytest.approx(1.0, abs=1e-9)
    for _, scan, scan_b in msgs["/scan"]:
        assert len(scan.ranges) == 720 and scan.header.frame_id == "scan_link"
        assert np.array_equal(np.asarray(scan.ranges, dtype=np.float32),
                              np.asarray(scan_b.ranges, dtype=np.float32), equal_nan=True)
        assert scan.angle_min == pytest.approx(-math.pi, abs=1e-6)
    for _, image, image_b in msgs["/front_camera"]:
        assert image.encoding == "32FC1" and image.step == 4 * image.width
        depth = np.frombuffer(bytes(image.data), dtype="<f4").reshape(image.height, image.width)
        assert np.array_equal(depth, np.frombuffer(bytes(image_b.data), dtype="<f4").reshape(
            image.height, image.width), equal_nan=True)
        # The bottom rows see the ground a few tens of centimetres ahead.
        bottom = depth[-1][np.isfinite(depth[-1])]
        assert bottom.size > 0 and (0.05 < bottom).all() and (bottom < 5.0).all()
    for _, cloud, _ in msgs["/elevation"]:
        assert cloud.header.frame_id == "map"
        assert [f.name for f in cloud.fields] == ["x", "y", "z"]
        assert len(cloud.data) == cloud.row_step * cloud.height
        pts = np.frombuffer(bytes(cloud.data), dtype="<f4").reshape(-1, 3)
        known = pts[np.isfinite(pts[:, 2])]
        assert len(known) > 0
        # Flat ground near the start: the stairs begin at x = 0.9 m.
        near = known[known[:, 0] < 0.5]
        assert np.abs(near[:, 2]).max() < 0.02
    encoders = msgs["/encoders"][-1][1]
    assert list(encoders.name) == JOINTS and encoders.position[2] > 0.1


def _decoded_both_ways(path):
    """Every CDR message of the MCAP file `path` decoded from the file's own schemas by both
    decoders: topic -> [(schema name, log time ns, mcap-ros2 message, rosbags message)]."""
    store = get_typestore(Stores.EMPTY) if get_typestore else None
    msgs = collections.defaultdict(list)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        for schema in summary.schemas.values() if store else ():
            if schema.encoding == "ros2msg":
                store.register(get_types_from_msg(schema.data.decode(), schema.name))
        cdr = [c.topic for c in summary.channels.values() if c.message_encoding == "cdr"]
        for schema, channel, message, decoded in reader.iter_decoded_messages(
                topics=cdr, log_time_order=True):
            other = store.deserialize_cdr(message.data, schema.name) if store else decoded
            msgs[channel.topic].append((schema.name, message.log_time, decoded, other))
    return msgs


def test_a_colour_camera_is_png_compressed_images_with_camera_info(tmp_path):
    """Issue 41: a 160 x 120 colour camera at 10 Hz (scenarios/packbot_camera.toml) in run.mcap:
    CompressedImage PNG on /front_rgb/compressed, CameraInfo on /front_rgb/camera_info, each
    decoded by both decoders from the file's own schemas; the PNG is the run folder's frame of
    the same time, K follows from the 70 deg field of view; no raw topic by default."""
    from PIL import Image
    import io

    out = tmp_path / "cam"
    r = run_cli("run", SCENARIOS / "packbot_camera.toml", "--out", out, "--mcap", "--duration",
                0.5, "--no-plot", "--quiet", timeout=300)
    assert r.returncode == 0, r.stderr
    msgs = _decoded_both_ways(out / "run.mcap")
    assert "/front_rgb" not in msgs
    images, infos = msgs["/front_rgb/compressed"], msgs["/front_rgb/camera_info"]
    with open(out / "sensors" / "front_rgb.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(images) == len(infos) == len(rows) == 6  # t = 0, 0.1, ..., 0.5 s
    f_px = 80.0 / math.tan(math.radians(35.0))
    k = [f_px, 0.0, 80.0, 0.0, f_px, 60.0, 0.0, 0.0, 1.0]
    for (ty, t, img, img2), (ty2, t2, info, info2), row in zip(images, infos, rows):
        assert ty == "sensor_msgs/msg/CompressedImage" and ty2 == "sensor_msgs/msg/CameraInfo"
        assert t == t2 == round(float(row["t_s"]) * 1e9)
        assert img.header.frame_id == info.header.frame_id == "front_rgb_optical_frame"
        assert img.format == img2.format == "rgb8; png compressed bgr8"
        data = bytes(img.data)
        assert data == bytes(img2.data) == (out / row["rgb_file"]).read_bytes()
        pixels = np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))
        assert pixels.shape == (120, 160, 3) and pixels.std() > 5
        assert (info.width, info.height) == (160, 120)
        assert info.distortion_model == info2.distortion_model == "plumb_bob"
        assert list(info.d) == list(info2.d) == [0.0] * 5
        assert np.allclose(info.k, k) and np.allclose(info2.k, k)
        assert np.allclose(info.p, [k[0], 0, 80, 0, 0, k[4], 60, 0, 0, 0, 1, 0])
        assert np.allclose(info2.p, info.p) and np.allclose(info.r, np.eye(3).ravel())


def test_a_course_run_records_its_events_and_final_score(tmp_path):
    """A scored course (scenarios/course_stairs.toml, run to its end: it ends at the finish) in
    run.mcap: /course/events has each of summary.json's course events at its time and
    /course the final score, both decoded by both decoders from the file's own schemas."""
    import json

    out = tmp_path / "course"
    r = run_cli("run", SCENARIOS / "course_stairs.toml", "--out", out, "--mcap", "--no-plot",
                "--quiet", timeout=300)
    assert r.returncode == 0, r.stderr
    course = json.loads((out / "summary.json").read_text())["course"]
    assert course["status"] == "completed"
    msgs = _decoded_both_ways(out / "run.mcap")
    events = msgs["/course/events"]
    assert len(events) == len(course["events"]) >= 3
    for (ty, t, e, e2), want in zip(events, course["events"]):
        assert ty == "tracksim_msgs/msg/CourseEvent"
        assert t == round(want["t_s"] * 1e9)
        assert e.header.frame_id == e2.header.frame_id == "map"
        assert (e.kind, e.detail) == (e2.kind, e2.detail) == (want["kind"], want["detail"])
        assert e.fault == e2.fault == want.get("fault", "")
        assert e.penalty == e2.penalty == want.get("penalty_s", 0.0)
    [(ty, t, s, s2)] = msgs["/course"]
    assert ty == "tracksim_msgs/msg/CourseStatus"
    assert t == round(course["score"]["time_s"] * 1e9), "the run ends at the finish"
    for m in (s, s2):
        assert (m.name, m.status, m.finished) == (course["name"], "completed", True)
        assert (m.gates_passed, m.gates_total) == (course["gates_passed"], course["gates_total"])
        assert m.repetitions_done == course["repetitions_done"]
        assert list(m.repetition_times) == course["rep_times_s"]
        assert m.time_limit == course.get("time_limit_s", 0.0)
        assert (m.trial_time, m.penalty, m.score) == (
            course["score"]["time_s"], course["penalty_s"], course["score"]["score_s"])
