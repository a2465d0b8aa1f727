"""The independent DDS peer of test_ros_dds.py, run INSIDE a network namespace with only `lo`
(the test starts it under `unshare --net`): brings `lo` up with a multicast route, starts
`tracksim ros` on a bundled scenario, and with Eclipse Cyclone DDS (the `cyclonedds` PyPI
package, its own C library; message types declared as IDL with the ROS 2 type names)
subscribes /odom and /joint_states and publishes /cmd_vel. Prints one JSON line of what it
measured; every wait is bounded and the child is always killed.

Usage: python ros_peer.py TRACKSIM_BIN OUT_DIR [drive|sensors|urdf|team|namespace]

- drive (default): packbot_flat; /cmd_vel at 0.3 m/s for 4 s at 20 Hz, then silence;
- sensors: packbot_sensors (flippers and sensors); /imu read for its rate and gravity, flipper
  targets sent by Float64 and by a JointState naming an unknown flipper, a NaN /cmd_vel, and
  /rosout read for the warnings.
- team: scenarios/team/corridor_head_on (robots `west` and `east`): /west/cmd_vel forward at
  0.3 m/s and /east/cmd_vel backward at 0.2 m/s for 3 s, then only /west/cmd_vel for 2 s
  (east's watchdog stops east alone); /west/odom, /east/odom and /tf read.
- namespace: packbot_flat with `--namespace solo`, driven by /solo/cmd_vel for 2 s.
"""

import json
import pathlib
import struct
import subprocess
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.annotations import final
from cyclonedds.idl.types import array, float64, int32, sequence, uint8, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

FORWARD_MPS = 0.3  # commanded on /cmd_vel
DRIVE_S = 4.0  # wall seconds of cmd_vel at 20 Hz
SILENT_S = 1.5  # then silence (the watchdog stops it after 0.5 s)


@final
@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@final
@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@final
@dataclass
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: float64
    y: float64
    z: float64


@final
@dataclass
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    linear: Vector3
    angular: Vector3


@final
@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: float64
    y: float64
    z: float64


@final
@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@final
@dataclass
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    position: Point
    orientation: Quaternion


@final
@dataclass
class PoseWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    pose: Pose
    covariance: array[float64, 36]


@final
@dataclass
class TwistWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    twist: Twist
    covariance: array[float64, 36]


@final
@dataclass
class Odometry(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    header: Header
    child_frame_id: str
    pose: PoseWithCovariance
    twist: TwistWithCovariance


@final
@dataclass
class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    translation: Vector3
    rotation: Quaternion


@final
@dataclass
class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    header: Header
    child_frame_id: str
    transform: Transform


@final
@dataclass
class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    transforms: sequence[TransformStamped]


@final
@dataclass
class JointState(IdlStruct, typename="sensor_msgs::msg::dds_::JointState_"):
    header: Header
    name: sequence[str]
    position: sequence[float64]
    velocity: sequence[float64]
    effort: sequence[float64]


@final
@dataclass
class Float64(IdlStruct, typename="std_msgs::msg::dds_::Float64_"):
    data: float64


@final
@dataclass
class Imu(IdlStruct, typename="sensor_msgs::msg::dds_::Imu_"):
    header: Header
    orientation: Quaternion
    orientation_covariance: array[float64, 9]
    angular_velocity: Vector3
    angular_velocity_covariance: array[float64, 9]
    linear_acceleration: Vector3
    linear_acceleration_covariance: array[float64, 9]


@final
@dataclass
class PointField(IdlStruct, typename="sensor_msgs::msg::dds_::PointField_"):
    name: str
    offset: uint32
    datatype: uint8
    count: uint32


@final
@dataclass
class PointCloud2(IdlStruct, typename="sensor_msgs::msg::dds_::PointCloud2_"):
    header: Header
    height: uint32
    width: uint32
    fields: sequence[PointField]
    is_bigendian: bool
    point_step: uint32
    row_step: uint32
    data: sequence[uint8]
    is_dense: bool


@final
@dataclass
class CompressedImage(IdlStruct, typename="sensor_msgs::msg::dds_::CompressedImage_"):
    header: Header
    format: str
    data: sequence[uint8]


@final
@dataclass
class RegionOfInterest(IdlStruct, typename="sensor_msgs::msg::dds_::RegionOfInterest_"):
    x_offset: uint32
    y_offset: uint32
    height: uint32
    width: uint32
    do_rectify: bool


@final
@dataclass
class CameraInfo(IdlStruct, typename="sensor_msgs::msg::dds_::CameraInfo_"):
    header: Header
    height: uint32
    width: uint32
    distortion_model: str
    d: sequence[float64]
    k: array[float64, 9]
    r: array[float64, 9]
    p: array[float64, 12]
    binning_x: uint32
    binning_y: uint32
    roi: RegionOfInterest


@final
@dataclass
class Image(IdlStruct, typename="sensor_msgs::msg::dds_::Image_"):
    header: Header
    height: uint32
    width: uint32
    encoding: str
    is_bigendian: uint8
    step: uint32
    data: sequence[uint8]


@final
@dataclass
class CourseStatus(IdlStruct, typename="tracksim_msgs::msg::dds_::CourseStatus_"):
    header: Header
    name: str
    status: str
    finished: bool
    next_gate: uint32
    gates_passed: uint32
    gates_total: uint32
    repetition: uint32
    repetitions_done: uint32
    repetitions_required: uint32
    repetition_times: sequence[float64]
    elapsed: float64
    time_limit: float64
    resets: uint32
    tip_overs: uint32
    touches: uint32
    penalty: float64
    trial_time: float64
    score: float64


@final
@dataclass
class CourseEvent(IdlStruct, typename="tracksim_msgs::msg::dds_::CourseEvent_"):
    header: Header
    kind: str
    detail: str
    fault: str
    penalty: float64


@final
@dataclass
class Log(IdlStruct, typename="rcl_interfaces::msg::dds_::Log_"):
    stamp: Time
    level: uint8
    name: str
    msg: str
    file: str
    function: str
    line: uint32


def netns_setup():
    """`lo` up with multicast and a multicast route (this namespace has nothing else)."""
    for cmd in (
        ["ip", "link", "set", "lo", "up"],
        ["ip", "link", "set", "lo", "multicast", "on"],
        ["ip", "route", "add", "224.0.0.0/4", "dev", "lo"],
    ):
        subprocess.run(cmd, check=True, timeout=10)
    links = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True, timeout=10).stdout
    return [line.split(":")[1].strip() for line in links.splitlines()]


def twist(v):
    return Twist(linear=Vector3(v, 0.0, 0.0), angular=Vector3(0.0, 0.0, 0.0))


QOS = Qos(
    Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
    Policy.History.KeepLast(10),
    Policy.DataRepresentation(use_cdrv0_representation=True),
)


def finish(child, result):
    """SIGTERM (tracksim writes its run folder), bounded; the child's exit and output."""
    child.terminate()
    try:
        stdout, stderr = child.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        child.kill()
        stdout, stderr = child.communicate(timeout=10)
    result.update(exit_code=child.returncode, stdout=stdout[-3000:], stderr=stderr[-3000:])


def take(reader, kind, into, n=200):
    for s in reader.take(N=n):
        if isinstance(s, kind):
            into.append(s)


def sensors(binary, out, links):
    dp = DomainParticipant(0)
    # 200 Hz read every 50 ms: a history deep enough to keep every message.
    deep = Qos(
        Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
        Policy.History.KeepLast(200),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )
    imu_r = DataReader(dp, Topic(dp, "rt/imu", Imu), qos=deep)
    joints_r = DataReader(dp, Topic(dp, "rt/joint_states", JointState), qos=QOS)
    odom_r = DataReader(dp, Topic(dp, "rt/odom", Odometry), qos=QOS)
    log_r = DataReader(dp, Topic(dp, "rt/rosout", Log), qos=QOS)
    elev_r = DataReader(dp, Topic(dp, "rt/elevation", PointCloud2), qos=QOS)
    cmd_w = DataWriter(dp, Topic(dp, "rt/cmd_vel", Twist), qos=QOS)
    fl_w = DataWriter(dp, Topic(dp, "rt/flippers/front_left/cmd_position", Float64), qos=QOS)
    all_w = DataWriter(dp, Topic(dp, "rt/flippers/cmd_positions", JointState), qos=QOS)
    child = subprocess.Popen(
        [binary, "ros", "packbot_sensors", "--out", out, "--no-plot", "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links}
    imu, joints, odom, logs, elev = [], [], [], [], []

    def drain():
        take(elev_r, PointCloud2, elev)
        take(imu_r, Imu, imu, 1000)
        take(joints_r, JointState, joints)
        take(odom_r, Odometry, odom)
        take(log_r, Log, logs)

    try:
        deadline = time.monotonic() + 20.0
        while not (imu and joints and odom) and time.monotonic() < deadline:
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.05)
        if not (imu and joints and odom):
            raise RuntimeError("no /imu, /joint_states or /odom within 20 s")
        time.sleep(1.0)
        drain()
        start_odom, start_joints = odom[-1], joints[-1]
        result["flipper_start"] = list(start_joints.position[:2])
        t_end = time.monotonic() + 3.0
        header = Header(stamp=Time(0, 0), frame_id="")
        while time.monotonic() < t_end:
            nan = float("nan")
            cmd_w.write(Twist(linear=Vector3(nan, 0.0, 0.0), angular=Vector3(0.0, 0.0, 0.0)))
            fl_w.write(Float64(0.9))
            all_w.write(JointState(header, ["front_right", "no_such_flipper"], [0.9, 0.1], [], []))
            drain()
            time.sleep(0.05)
        drain()
        stamp = lambda m: m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec
        span = stamp(imu[-1]) - stamp(imu[0])
        result.update(
            joint_names=list(joints[-1].name),
            flipper_end=list(joints[-1].position[:2]),
            odom_dx=odom[-1].pose.pose.position.x - start_odom.pose.pose.position.x,
            imu_messages=len(imu),
            imu_rate_hz=(len(imu) - 1) / span if span > 0 else 0.0,
            imu_frame=imu[-1].header.frame_id,
            imu_accel_z=sum(m.linear_acceleration.z for m in imu) / len(imu),
            rosout=[m.msg for m in logs],
        )
        if elev:
            c = elev[-1]
            z = [v for v in struct.unpack(f"<{len(c.data) // 4}f", bytes(c.data))[2::3]
                 if v == v]
            z.sort()
            result.update(
                elevation_messages=len(elev),
                elevation_frame=c.header.frame_id,
                elevation_shape=[c.height, c.width, c.point_step],
                elevation_fields=[f.name for f in c.fields],
                elevation_known=len(z),
                elevation_median_z=z[len(z) // 2] if z else None,
            )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


def drive(binary, out, links):
    qos = QOS
    dp = DomainParticipant(0)
    odom_r = DataReader(dp, Topic(dp, "rt/odom", Odometry), qos=qos)
    joints_r = DataReader(dp, Topic(dp, "rt/joint_states", JointState), qos=qos)
    truth_r = DataReader(dp, Topic(dp, "rt/ground_truth/odom", Odometry), qos=qos)
    cmd_w = DataWriter(dp, Topic(dp, "rt/cmd_vel", Twist), qos=qos)
    child = subprocess.Popen(
        [binary, "ros", "packbot_flat", "--out", out, "--no-plot", "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links, "forward_mps": FORWARD_MPS}
    odom, joints, truth = [], [], []

    def drain():
        for s in odom_r.take(N=100):
            if isinstance(s, Odometry):
                odom.append(s)
        for s in joints_r.take(N=100):
            if isinstance(s, JointState):
                joints.append(s)
        for s in truth_r.take(N=100):
            if isinstance(s, Odometry):
                truth.append(s)

    try:
        # Discovery: wait (bounded) for the first odometry message.
        deadline = time.monotonic() + 20.0
        while not odom and time.monotonic() < deadline and child.poll() is None:
            drain()
            time.sleep(0.05)
        result["discovered_s"] = 20.0 - (deadline - time.monotonic())
        if not odom:
            raise RuntimeError("no /odom from tracksim within 20 s")
        start = (odom[-1], joints[-1] if joints else None, truth[-1] if truth else None)
        # Drive: cmd_vel at 20 Hz.
        t_end = time.monotonic() + DRIVE_S
        while time.monotonic() < t_end:
            cmd_w.write(twist(FORWARD_MPS))
            drain()
            time.sleep(0.05)
        drain()
        driven = (odom[-1], joints[-1], truth[-1])
        # Silence: the watchdog stops the robot.
        t_end = time.monotonic() + SILENT_S
        while time.monotonic() < t_end:
            drain()
            time.sleep(0.05)
        drain()
        stopped = (odom[-1], joints[-1], truth[-1])
        stamp = lambda m: m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec
        result.update(
            odom_messages=len(odom),
            joint_messages=len(joints),
            frame_id=start[0].header.frame_id,
            child_frame_id=start[0].child_frame_id,
            joint_names=list(driven[1].name),
            t_start=stamp(start[0]),
            t_driven=stamp(driven[0]),
            t_stopped=stamp(stopped[0]),
            odom_x_start=start[0].pose.pose.position.x,
            odom_x_driven=driven[0].pose.pose.position.x,
            odom_x_stopped=stopped[0].pose.pose.position.x,
            odom_v_driven=driven[0].twist.twist.linear.x,
            odom_v_stopped=stopped[0].twist.twist.linear.x,
            truth_v_driven=driven[2].twist.twist.linear.x,
            truth_v_stopped=stopped[2].twist.twist.linear.x,
            joints_start=list(start[1].position) if start[1] else None,
            joints_driven=list(driven[1].position),
            joints_stopped=list(stopped[1].position),
        )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)  # SIGTERM: tracksim writes its run folder
    print(json.dumps(result))


def urdf(binary, out, links):
    """The bundled URDF robot (packbot_urdf_stairs): its joints by their URDF names, driven by
    /cmd_vel, its front_left flipper raised by a Float64 command."""
    dp = DomainParticipant(0)
    joints_r = DataReader(dp, Topic(dp, "rt/joint_states", JointState), qos=QOS)
    odom_r = DataReader(dp, Topic(dp, "rt/odom", Odometry), qos=QOS)
    cmd_w = DataWriter(dp, Topic(dp, "rt/cmd_vel", Twist), qos=QOS)
    fl_w = DataWriter(dp, Topic(dp, "rt/flippers/front_left/cmd_position", Float64), qos=QOS)
    child = subprocess.Popen(
        [binary, "ros", "packbot_urdf_stairs", "--out", out, "--no-plot", "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links}
    joints, odom = [], []

    def drain():
        take(joints_r, JointState, joints)
        take(odom_r, Odometry, odom)

    try:
        deadline = time.monotonic() + 20.0
        while not (joints and odom) and time.monotonic() < deadline:
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.05)
        if not (joints and odom):
            raise RuntimeError("no /joint_states or /odom within 20 s")
        start = odom[-1]
        t_end = time.monotonic() + 2.0
        while time.monotonic() < t_end:
            cmd_w.write(twist(FORWARD_MPS))
            fl_w.write(Float64(0.6))
            drain()
            time.sleep(0.05)
        drain()
        result.update(
            joint_names=list(joints[-1].name),
            positions=list(joints[-1].position),
            odom_dx=odom[-1].pose.pose.position.x - start.pose.pose.position.x,
        )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


TEAM = ("west", "east")
TEAM_V = {"west": 0.3, "east": -0.2}  # commanded forward speeds, m/s
TEAM_BOTH_S = 3.0  # wall seconds both robots are driven
TEAM_ONE_S = 2.0  # then only west (east's watchdog stops it after 0.5 s)


def team(binary, out, links):
    """Two robots of one world on one node, each by its own namespaced topics."""
    dp = DomainParticipant(0)
    odom_r = {n: DataReader(dp, Topic(dp, f"rt/{n}/odom", Odometry), qos=QOS) for n in TEAM}
    cmd_w = {n: DataWriter(dp, Topic(dp, f"rt/{n}/cmd_vel", Twist), qos=QOS) for n in TEAM}
    tf_r = DataReader(dp, Topic(dp, "rt/tf", TFMessage), qos=QOS)
    plain_r = DataReader(dp, Topic(dp, "rt/odom", Odometry), qos=QOS)
    scenario = str(pathlib.Path(__file__).resolve().parents[2] / "scenarios/team/corridor_head_on.toml")
    child = subprocess.Popen(
        [binary, "ros", scenario, "--out", out, "--no-plot", "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links, "scenario": scenario, "commanded": TEAM_V}
    odom = {n: [] for n in TEAM}
    tf, plain = [], []

    def drain():
        for n in TEAM:
            take(odom_r[n], Odometry, odom[n])
        take(tf_r, TFMessage, tf)
        take(plain_r, Odometry, plain)

    def state(n):
        m = odom[n][-1]
        return {
            "x": m.pose.pose.position.x,
            "v": m.twist.twist.linear.x,
            "t": m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec,
        }

    try:
        deadline = time.monotonic() + 20.0
        while not all(odom.values()) and time.monotonic() < deadline:
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.05)
        if not all(odom.values()):
            raise RuntimeError("no /west/odom or /east/odom within 20 s")
        start = {n: state(n) for n in TEAM}
        for names, span in ((TEAM, TEAM_BOTH_S), (TEAM[:1], TEAM_ONE_S)):
            t_end = time.monotonic() + span
            while time.monotonic() < t_end:
                for n in names:
                    cmd_w[n].write(twist(TEAM_V[n]))
                drain()
                time.sleep(0.05)
            drain()
            if len(names) == 2:
                both = {n: state(n) for n in TEAM}
        one = {n: state(n) for n in TEAM}
        frames = sorted({(t.header.frame_id, t.child_frame_id) for m in tf[-5:] for t in m.transforms})
        result.update(
            start=start,
            both=both,
            one=one,
            frame_ids={n: odom[n][-1].header.frame_id for n in TEAM},
            child_frame_ids={n: odom[n][-1].child_frame_id for n in TEAM},
            tf_pairs=frames,
            plain_odom_messages=len(plain),
        )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


def namespaced(binary, out, links):
    """One robot namespaced by `--namespace solo`: /solo/cmd_vel drives it, /solo/odom in
    solo/odom, nothing on /odom."""
    dp = DomainParticipant(0)
    odom_r = DataReader(dp, Topic(dp, "rt/solo/odom", Odometry), qos=QOS)
    plain_r = DataReader(dp, Topic(dp, "rt/odom", Odometry), qos=QOS)
    tf_r = DataReader(dp, Topic(dp, "rt/tf", TFMessage), qos=QOS)
    cmd_w = DataWriter(dp, Topic(dp, "rt/solo/cmd_vel", Twist), qos=QOS)
    child = subprocess.Popen(
        [binary, "ros", "packbot_flat", "--namespace", "solo", "--out", out, "--no-plot",
         "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links}
    odom, plain, tf = [], [], []

    def drain():
        take(odom_r, Odometry, odom)
        take(plain_r, Odometry, plain)
        take(tf_r, TFMessage, tf)

    try:
        deadline = time.monotonic() + 20.0
        while not odom and time.monotonic() < deadline:
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.05)
        if not odom:
            raise RuntimeError("no /solo/odom within 20 s")
        start = odom[-1]
        t_end = time.monotonic() + 2.0
        while time.monotonic() < t_end:
            cmd_w.write(twist(FORWARD_MPS))
            drain()
            time.sleep(0.05)
        drain()
        result.update(
            frame_id=odom[-1].header.frame_id,
            child_frame_id=odom[-1].child_frame_id,
            odom_dx=odom[-1].pose.pose.position.x - start.pose.pose.position.x,
            tf_pairs=sorted({(t.header.frame_id, t.child_frame_id) for m in tf[-3:]
                             for t in m.transforms}),
            plain_odom_messages=len(plain),
        )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


def camera(binary, out, links):
    """packbot_camera (a 160 x 120 colour camera at 10 Hz): PNG CompressedImage on
    /front_rgb/compressed with its CameraInfo on /front_rgb/camera_info, nothing on the raw
    /front_rgb (no --raw-images)."""
    dp = DomainParticipant(0)
    img_r = DataReader(dp, Topic(dp, "rt/front_rgb/compressed", CompressedImage), qos=QOS)
    info_r = DataReader(dp, Topic(dp, "rt/front_rgb/camera_info", CameraInfo), qos=QOS)
    raw_r = DataReader(dp, Topic(dp, "rt/front_rgb", Image), qos=QOS)
    child = subprocess.Popen(
        [binary, "ros", "packbot_camera", "--out", out, "--no-plot", "--duration", "30"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links}
    imgs, infos, raws = [], [], []

    def drain():
        take(img_r, CompressedImage, imgs)
        take(info_r, CameraInfo, infos)
        take(raw_r, Image, raws)

    try:
        deadline = time.monotonic() + 25.0
        while not (len(imgs) >= 5 and len(infos) >= 5) and time.monotonic() < deadline:
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.05)
        drain()
        stamp = lambda m: (m.header.stamp.sec, m.header.stamp.nanosec)
        last = imgs[-1] if imgs else None
        result.update(
            images=len(imgs),
            infos=len(infos),
            raw_images=len(raws),
            stamps_paired=sorted({stamp(m) for m in imgs} & {stamp(m) for m in infos}) != [],
            format=last.format if last else None,
            frame_id=last.header.frame_id if last else None,
            png_signature=bytes(last.data[:8]).hex() if last else None,
            png_bytes=len(last.data) if last else 0,
            info_frame_id=infos[-1].header.frame_id if infos else None,
            info_size=[infos[-1].width, infos[-1].height] if infos else None,
            k=list(infos[-1].k) if infos else None,
            p=list(infos[-1].p) if infos else None,
            d=list(infos[-1].d) if infos else None,
            distortion_model=infos[-1].distortion_model if infos else None,
        )
        if last:
            import io
            from PIL import Image as PilImage
            px = PilImage.open(io.BytesIO(bytes(last.data)))
            result.update(png_size=list(px.size), png_mode=px.mode)
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


def course(binary, out, links):
    """scenarios/course_stairs.toml driven by its own [[commands]] (`--play-commands`) as fast
    as it runs: /course at every sample and /course/events (transient local: a reader that
    joins late still gets every event); stopped by SIGTERM once a status says completed."""
    dp = DomainParticipant(0)
    events_qos = Qos(
        Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
        Policy.Durability.TransientLocal,
        Policy.History.KeepLast(100),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )
    status_r = DataReader(dp, Topic(dp, "rt/course", CourseStatus), qos=QOS)
    events_r = DataReader(dp, Topic(dp, "rt/course/events", CourseEvent), qos=events_qos)
    child = subprocess.Popen(
        [binary, "ros", "course_stairs", "--play-commands", "--fast", "--out", out,
         "--no-plot", "--duration", "120"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    result = {"links": links}
    statuses, events = [], []

    def drain():
        take(status_r, CourseStatus, statuses)
        take(events_r, CourseEvent, events, n=100)

    stamp = lambda m: m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec
    try:
        deadline = time.monotonic() + 60.0
        while not any(m.status == "completed" for m in statuses):
            if time.monotonic() > deadline:
                raise RuntimeError(f"no completed /course within 60 s ({len(statuses)} statuses)")
            if child.poll() is not None:
                raise RuntimeError("tracksim ended early")
            drain()
            time.sleep(0.02)
        time.sleep(0.2)
        drain()
        done = next(m for m in statuses if m.status == "completed")
        result.update(
            statuses=len(statuses),
            stamps_increase=all(stamp(a) < stamp(b) for a, b in zip(statuses, statuses[1:])),
            gates_never_fall=all(
                a.gates_passed <= b.gates_passed for a, b in zip(statuses, statuses[1:])
            ),
            before_finish=sorted({m.status for m in statuses if stamp(m) < stamp(done)}),
            completed=dict(
                t=stamp(done), name=done.name, finished=done.finished,
                gates_passed=done.gates_passed, gates_total=done.gates_total,
                repetitions_done=done.repetitions_done,
                repetition_times=list(done.repetition_times), elapsed=done.elapsed,
                time_limit=done.time_limit, penalty=done.penalty,
                trial_time=done.trial_time, score=done.score, frame_id=done.header.frame_id,
            ),
            last=dict(status=statuses[-1].status, score=statuses[-1].score),
            events=[
                dict(t=stamp(e), kind=e.kind, detail=e.detail, fault=e.fault, penalty=e.penalty)
                for e in events
            ],
        )
    except Exception as e:  # reported to the test, which fails on it
        result["error"] = repr(e)
    finally:
        finish(child, result)
    print(json.dumps(result))


def main():
    binary, out = sys.argv[1], sys.argv[2]
    mode = sys.argv[3] if len(sys.argv) > 3 else "drive"
    links = netns_setup()
    {
        "drive": drive,
        "sensors": sensors,
        "urdf": urdf,
        "team": team,
        "namespace": namespaced,
        "camera": camera,
        "course": course,
    }[mode](binary, out, links)


if __name__ == "__main__":
    main()
