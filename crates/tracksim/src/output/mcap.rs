//! `run.mcap`: a run as a ROS 2 recording (MCAP, profile `ros2`, messages `cdr`, schemas
//! `ros2msg`, uncompressed chunks), which Foxglove and the ROS 2 bag tools open. Log, publish
//! and header times are the simulated time (ns from the start of the run). Messages are
//! written in time order.
//!
//! Frames (REP 103 axes, REP 105 names):
//! - `map`: the world frame (REP 105); ground truth and the elevation map are in it;
//! - `odom`: the encoders' odometry frame (it coincides with `map` at the start; `map ->
//!   odom` on `/tf` is the drift the slip has caused);
//! - `base_link`: the chassis (the vehicle file's body frame);
//! - `<flipper>_flipper_link`: each flipper, origin at its pivot, axes those of `base_link` at
//!   angle 0, turned by the flipper angle about its axis;
//! - `<sensor>_link`: each sensor's frame (`xyz_m`, `rpy_deg` of the vehicle file) on its
//!   mount (`base_link` or the flipper's link); a depth camera also has
//!   `<sensor>_optical_frame` (z forward, x right, y down), the frame of its images.
//!
//! Topics (one message per output sample unless said otherwise):
//! - `/clock` (`rosgraph_msgs/Clock`);
//! - `/tf` (`tf2_msgs/TFMessage`): `odom -> base_link` (the encoders' estimate, as `/odom`),
//!   `base_link -> <flipper>_flipper_link`, and `map -> odom` (the drift, so `map ->
//!   base_link` is the true pose and sensor data lands where it was taken);
//! - `/tf_static` (`tf2_msgs/TFMessage`, once at t = 0, QoS transient local): the sensor
//!   mounts and optical frames;
//! - `/odom` (`nav_msgs/Odometry`): what the encoders report (`Sample::odom`, slip included),
//!   frame `odom`, child `base_link`, planar (z 0, yaw only); the twist is the skid-steer
//!   model's forward speed and yaw rate from the measured belt speeds, in `base_link`;
//!   covariances 0 (unknown);
//! - `/ground_truth/odom` (`nav_msgs/Odometry`): the true pose, and the chassis's velocity
//!   (that of its centre of mass, `Sample::linvel`, and its angular velocity) turned into
//!   `base_link` axes;
//! - `/joint_states` (`sensor_msgs/JointState`): each flipper by its name (rad; velocity by
//!   backward difference of the samples, 0 at the first), then each track's belt as the
//!   continuous joint `<track>_belt` whose coordinate is the belt's travel (m, m/s);
//! - `/tracks` (`tracksim_msgs/TrackStates`, frame `base_link`): slip, traction, normal load,
//!   belt speed, command and position, motor figures ([`crate::rosmsg::TrackStates`]);
//! - every sensor on `/<sensor name>` at its own readings: an IMU as `sensor_msgs/Imu` (frame
//!   `<sensor>_link`, orientation in `map`, covariances of its white noise on the diagonal);
//!   a lidar as `sensor_msgs/LaserScan` with one scan line, else `sensor_msgs/PointCloud2`
//!   (organised: elevation rows of azimuth columns, x y z float32 in `<sensor>_link`, NaN for
//!   no return); a depth camera as `sensor_msgs/Image` `32FC1` (m along the optical axis, REP
//!   117 infinities) in `<sensor>_optical_frame`; an elevation map as `sensor_msgs/PointCloud2`
//!   of its cells' surface points in `map` (organised: `x` rows of `y` columns, NaN where a
//!   cell is unknown); encoders as `sensor_msgs/JointState` with the names of `/joint_states`
//!   (their quantised readings; the flippers' velocity NaN: not measured).

pub use super::ros_sensors::{MAP_FRAME, optical_frame, sensor_frame};
use super::ros_sensors::{Reading, SensorMessage, sensor_message};
use crate::error::{Error, Result};
use crate::model::{Parent, Scenario, SensorKind, SensorModel};
use crate::rosmsg::{
    self, Clock, Header, Image, Imu, JointState, LaserScan, Odometry, PointCloud2,
    PoseWithCovariance, Quaternion, RosMessage, TFMessage, TrackStates, Transform,
    TransformStamped, Twist, TwistWithCovariance, Vector3,
};
use crate::run::RunResult;
use crate::sensors::{LogData, SensorStream};
use crate::world::{Odometry as EncoderOdometry, PoseRpy, Sample};
use glam::{DMat3, DQuat, DVec3, EulerRot};
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// The file name of the recording in a run folder.
pub const MCAP_FILE: &str = "run.mcap";
/// The odometry frame (REP 105): `/odom` and `/tf`'s `odom -> base_link` are the encoders'
/// estimate in it; `map -> odom` is where that estimate drifted from the truth.
pub const ODOM_FRAME: &str = "odom";
/// The chassis frame.
pub const BASE_FRAME: &str = "base_link";

/// The frame of flipper `name`.
pub fn flipper_frame(name: &str) -> String {
    format!("{name}_flipper_link")
}

/// The joint name of track `name`'s belt in `/joint_states`.
pub fn belt_joint(name: &str) -> String {
    format!("{name}_belt")
}

/// Writes `dir/run.mcap` (atomically) from a run of `sc`; returns its path.
pub fn write_mcap(sc: &Scenario, result: &RunResult, dir: &Path) -> Result<PathBuf> {
    let path = dir.join(MCAP_FILE);
    let bytes = mcap_bytes(sc, result).map_err(|e| Error::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    crate::files::write_atomic(&path, &bytes)?;
    Ok(path)
}

/// The bytes of `run.mcap` for a run of `sc` (an error says what could not be encoded).
pub fn mcap_bytes(sc: &Scenario, result: &RunResult) -> std::result::Result<Vec<u8>, String> {
    let mut rec = Recorder::new()?;
    record_samples(&mut rec, sc, result)?;
    record_static(&mut rec, sc)?;
    for stream in &result.sensors {
        let Some(m) = sc.vehicle.sensors.iter().find(|m| m.name == stream.name) else {
            continue;
        };
        record_sensor(&mut rec, result, m, stream)?;
    }
    rec.finish()
}

/// QoS of a channel as rosbag2 records it (`offered_qos_profiles`): reliable, keep last,
/// volatile or (latched topics) transient local.
fn qos(latched: bool) -> String {
    let inf = "\n    sec: 2147483647\n    nsec: 4294967295";
    format!(
        "- history: 1\n  depth: {}\n  reliability: 1\n  durability: {}\n  deadline:{inf}\n  lifespan:{inf}\n  liveliness: 1\n  liveliness_lease_duration:{inf}\n  avoid_ros_namespace_conventions: false\n",
        if latched { 1 } else { 10 },
        if latched { 1 } else { 2 }
    )
}

/// Channels and messages, written in time order at the end.
struct Recorder {
    writer: ::mcap::Writer<Cursor<Vec<u8>>>,
    schemas: BTreeMap<String, u16>,
    /// (log time ns, channel, CDR bytes).
    messages: Vec<(u64, u16, Vec<u8>)>,
}

impl Recorder {
    fn new() -> std::result::Result<Self, String> {
        let writer = ::mcap::WriteOptions::new()
            .profile("ros2")
            .library(format!("tracksim {}", env!("CARGO_PKG_VERSION")))
            .compression(None)
            .create(Cursor::new(Vec::new()))
            .map_err(|e| format!("MCAP: {e}"))?;
        Ok(Recorder {
            writer,
            schemas: BTreeMap::new(),
            messages: Vec::new(),
        })
    }

    /// A channel on `topic` of message type `T`.
    fn channel<T: RosMessage>(
        &mut self,
        topic: &str,
        latched: bool,
    ) -> std::result::Result<u16, String> {
        let name = T::schema_name();
        let schema = match self.schemas.get(&name) {
            Some(id) => *id,
            None => {
                let id = self
                    .writer
                    .add_schema(&name, "ros2msg", T::schema_text().as_bytes())
                    .map_err(|e| format!("MCAP schema {name}: {e}"))?;
                self.schemas.insert(name, id);
                id
            }
        };
        let meta = BTreeMap::from([("offered_qos_profiles".to_string(), qos(latched))]);
        self.writer
            .add_channel(schema, topic, "cdr", &meta)
            .map_err(|e| format!("MCAP channel {topic}: {e}"))
    }

    /// `msg` on `channel` at `t` s.
    fn push<T: RosMessage>(
        &mut self,
        channel: u16,
        t: f64,
        msg: &T,
    ) -> std::result::Result<(), String> {
        let bytes = rosmsg::encode(msg).map_err(|e| format!("{}: {e}", T::schema_name()))?;
        self.messages
            .push((rosmsg::Time::from_secs(t).nanos(), channel, bytes));
        Ok(())
    }

    fn finish(mut self) -> std::result::Result<Vec<u8>, String> {
        self.messages.sort_by_key(|m| m.0);
        let mut sequence: BTreeMap<u16, u32> = BTreeMap::new();
        for (t, channel, data) in std::mem::take(&mut self.messages) {
            let seq = sequence.entry(channel).or_insert(0);
            *seq += 1;
            let header = ::mcap::records::MessageHeader {
                channel_id: channel,
                sequence: *seq,
                log_time: t,
                publish_time: t,
            };
            self.writer
                .write_to_known_channel(&header, &data)
                .map_err(|e| format!("MCAP message: {e}"))?;
        }
        self.writer
            .finish()
            .map_err(|e| format!("MCAP summary: {e}"))?;
        Ok(self.writer.into_inner().into_inner())
    }
}

fn vec3(v: DVec3) -> Vector3 {
    Vector3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

fn quat(q: DQuat) -> Quaternion {
    Quaternion {
        x: q.x,
        y: q.y,
        z: q.z,
        w: q.w,
    }
}

/// The rotation of a REP 103 roll/pitch/yaw pose.
pub fn pose_rotation(p: &PoseRpy) -> DQuat {
    DQuat::from_euler(EulerRot::ZYX, p.yaw, p.pitch, p.roll)
}

/// The transform `parent -> child` at `t` s: `child`'s origin `at` (m) and rotation `rot` in
/// `parent`.
pub fn transform(t: f64, parent: &str, child: &str, at: DVec3, rot: DQuat) -> TransformStamped {
    TransformStamped {
        header: Header::new(t, parent),
        child_frame_id: child.to_string(),
        transform: Transform {
            translation: vec3(at),
            rotation: quat(rot),
        },
    }
}

/// The skid-steer odometry of `sc`'s chassis tracks (for the encoders' twist).
pub fn encoder_model(sc: &Scenario) -> EncoderOdometry {
    let offsets: Vec<Option<f64>> = sc
        .vehicle
        .tracks
        .iter()
        .map(|t| (t.parent == Parent::Body).then(|| t.lateral_offset()))
        .collect();
    let b = sc
        .vehicle
        .odometry_separation
        .unwrap_or_else(|| EncoderOdometry::geometric_separation(&offsets));
    EncoderOdometry::new(&offsets, b, 0.0, 0.0, 0.0)
}

/// The encoder odometry of sample `s` (frame `odom`, child `base_link`).
pub fn encoder_odometry(s: &Sample, model: &EncoderOdometry) -> Odometry {
    let (v, w) = model.twist(&s.belt_speed);
    let [x, y, yaw] = s.odom;
    let mut pose = PoseWithCovariance::default();
    pose.pose.position = rosmsg::Point { x, y, z: 0.0 };
    pose.pose.orientation = quat(DQuat::from_rotation_z(yaw));
    let twist = TwistWithCovariance {
        twist: Twist {
            linear: Vector3 {
                x: v,
                y: 0.0,
                z: 0.0,
            },
            angular: Vector3 {
                x: 0.0,
                y: 0.0,
                z: w,
            },
        },
        ..TwistWithCovariance::default()
    };
    Odometry {
        header: Header::new(s.t, ODOM_FRAME),
        child_frame_id: BASE_FRAME.into(),
        pose,
        twist,
    }
}

/// The true odometry of sample `s`: pose in `map`, velocities in `base_link` axes.
pub fn true_odometry(s: &Sample) -> Odometry {
    let r = pose_rotation(&s.pose);
    let inv = r.inverse();
    let mut pose = PoseWithCovariance::default();
    pose.pose.position = rosmsg::Point {
        x: s.pose.x,
        y: s.pose.y,
        z: s.pose.z,
    };
    pose.pose.orientation = quat(r);
    let twist = TwistWithCovariance {
        twist: Twist {
            linear: vec3(inv * DVec3::from_array(s.linvel)),
            angular: vec3(inv * DVec3::from_array(s.angvel)),
        },
        ..TwistWithCovariance::default()
    };
    Odometry {
        header: Header::new(s.t, MAP_FRAME),
        child_frame_id: BASE_FRAME.into(),
        pose,
        twist,
    }
}

/// The pose of an odometry message: its position (m) and rotation.
fn pose_of(o: &Odometry) -> (DVec3, DQuat) {
    let p = &o.pose.pose;
    let q = &p.orientation;
    (
        DVec3::new(p.position.x, p.position.y, p.position.z),
        DQuat::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// `/tf` of sample `s` (REP 105): `odom -> base_link` from the encoder odometry `odom` (what
/// `/odom` says: planar, slip included), `base_link -> <flipper>_flipper_link` (origin at
/// the pivot, turned by the flipper angle about its axis), and with `with_map` also
/// `map -> odom`, the encoders' drift from the true pose (a perfect localisation: `map ->
/// base_link` is the truth, so sensor data lands where it was taken).
pub fn tf_of_sample(sc: &Scenario, s: &Sample, odom: &Odometry, with_map: bool) -> TFMessage {
    let (at, rot) = pose_of(odom);
    let mut transforms = vec![transform(s.t, ODOM_FRAME, BASE_FRAME, at, rot)];
    for (f, angle) in sc.vehicle.flippers.iter().zip(&s.flipper_angle) {
        transforms.push(transform(
            s.t,
            BASE_FRAME,
            &flipper_frame(&f.name),
            f.pivot,
            DQuat::from_axis_angle(f.axis.normalize(), *angle),
        ));
    }
    if with_map {
        // map->odom = (map->base_link) * (odom->base_link)^-1.
        let r = (pose_rotation(&s.pose) * rot.inverse()).normalize();
        let t = DVec3::new(s.pose.x, s.pose.y, s.pose.z) - r * at;
        transforms.push(transform(s.t, MAP_FRAME, ODOM_FRAME, t, r));
    }
    TFMessage { transforms }
}

/// The per-track message of sample `s`.
pub fn track_states(s: &Sample, names: &[String]) -> TrackStates {
    let motors = s.drive.iter().any(|d| d.is_some());
    let motor = |f: fn(&crate::world::DriveSample) -> f64| -> Vec<f64> {
        if motors {
            s.drive
                .iter()
                .map(|d| d.as_ref().map_or(f64::NAN, f))
                .collect()
        } else {
            Vec::new()
        }
    };
    TrackStates {
        header: Header::new(s.t, BASE_FRAME),
        name: names.to_vec(),
        slip: s.slip.clone(),
        belt_speed: s.belt_speed.clone(),
        belt_command: s.belt_cmd.clone(),
        belt_position: s.belt_position.clone(),
        traction: s.loads.iter().map(|l| l.traction_n).collect(),
        friction_traction: s.loads.iter().map(|l| l.friction_traction_n).collect(),
        normal_load: s.loads.iter().map(|l| l.normal_n).collect(),
        contacts: s.loads.iter().map(|l| l.contacts as u32).collect(),
        belt_force: motor(|d| d.belt_force_n),
        motor_torque: motor(|d| d.motor_torque_nm),
    }
}

/// The joint names of `/joint_states`: the flippers, then the belts.
fn joint_names(result: &RunResult) -> Vec<String> {
    let mut names = result.flipper_names.clone();
    names.extend(result.track_names.iter().map(|n| belt_joint(n)));
    names
}

/// `/clock`, `/tf`, `/odom`, `/ground_truth/odom`, `/joint_states` and `/tracks` at every
/// sample.
fn record_samples(
    rec: &mut Recorder,
    sc: &Scenario,
    result: &RunResult,
) -> std::result::Result<(), String> {
    let clock = rec.channel::<Clock>("/clock", false)?;
    let tf = rec.channel::<TFMessage>("/tf", false)?;
    let odom = rec.channel::<Odometry>("/odom", false)?;
    let truth = rec.channel::<Odometry>("/ground_truth/odom", false)?;
    let joints = rec.channel::<JointState>("/joint_states", false)?;
    let tracks = rec.channel::<TrackStates>("/tracks", false)?;
    let model = encoder_model(sc);
    let names = joint_names(result);
    let mut last: Option<&Sample> = None;
    for s in &result.samples {
        rec.push(
            clock,
            s.t,
            &Clock {
                clock: rosmsg::Time::from_secs(s.t),
            },
        )?;
        let enc = encoder_odometry(s, &model);
        rec.push(tf, s.t, &tf_of_sample(sc, s, &enc, true))?;
        rec.push(odom, s.t, &enc)?;
        rec.push(truth, s.t, &true_odometry(s))?;
        rec.push(joints, s.t, &joint_state(&names, s, last))?;
        rec.push(tracks, s.t, &track_states(s, &result.track_names))?;
        last = Some(s);
    }
    Ok(())
}

/// The rotation from a depth camera's frame (x forward, y left, z up) to its optical frame
/// (z forward, x right, y down).
pub fn optical_rotation() -> DQuat {
    let q = DQuat::from_mat3(&DMat3::from_cols(
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(1.0, 0.0, 0.0),
    ));
    if q.w < 0.0 { -q } else { q }
}

/// `/joint_states` of sample `s`: flipper angles (rad; velocity by backward difference from
/// `prev`, 0 without it), belt travel (m) and measured belt speed (m/s).
pub fn joint_state(names: &[String], s: &Sample, prev: Option<&Sample>) -> JointState {
    let mut position = s.flipper_angle.clone();
    position.extend(&s.belt_position);
    let mut velocity: Vec<f64> = match prev {
        Some(p) if s.t > p.t => s
            .flipper_angle
            .iter()
            .zip(&p.flipper_angle)
            .map(|(a, b)| (a - b) / (s.t - p.t))
            .collect(),
        _ => vec![0.0; s.flipper_angle.len()],
    };
    velocity.extend(&s.belt_speed);
    JointState {
        header: Header::new(s.t, ""),
        name: names.to_vec(),
        position,
        velocity,
        effort: Vec::new(),
    }
}

/// `/tf_static`: each sensor's frame on its mount (`base_link` or the flipper's link) and the
/// depth cameras' optical frames (encoders have no frame).
pub fn tf_static(sc: &Scenario) -> TFMessage {
    let mut transforms = Vec::new();
    for m in &sc.vehicle.sensors {
        if matches!(m.kind, SensorKind::Encoders(_)) {
            continue;
        }
        let (parent, at) = match m.mount {
            crate::model::Mount::Body => (BASE_FRAME.to_string(), m.position),
            crate::model::Mount::Flipper(i) => {
                let f = &sc.vehicle.flippers[i];
                (flipper_frame(&f.name), m.position - f.pivot)
            }
        };
        let frame = sensor_frame(&m.name);
        transforms.push(transform(0.0, &parent, &frame, at, m.rotation));
        if matches!(m.kind, SensorKind::DepthCamera(_)) {
            transforms.push(transform(
                0.0,
                &frame,
                &optical_frame(&m.name),
                DVec3::ZERO,
                optical_rotation(),
            ));
        }
    }
    TFMessage { transforms }
}

/// `/tf_static` ([`tf_static`]) once at t = 0, when the vehicle has sensor frames.
fn record_static(rec: &mut Recorder, sc: &Scenario) -> std::result::Result<(), String> {
    let msg = tf_static(sc);
    if msg.transforms.is_empty() {
        return Ok(());
    }
    let ch = rec.channel::<TFMessage>("/tf_static", true)?;
    rec.push(ch, 0.0, &msg)
}

/// Reading `k` of a stream's channel called `name` (f64; empty if there is no such channel).
fn reading(stream: &SensorStream, name: &str, k: usize) -> Vec<f64> {
    let Some(c) = stream.channels.iter().find(|c| c.channel.name == name) else {
        return Vec::new();
    };
    let n = c.channel.data.len();
    match &c.values {
        LogData::F64(v) => v.get(k * n..(k + 1) * n).unwrap_or(&[]).to_vec(),
        LogData::F32(v) => v
            .get(k * n..(k + 1) * n)
            .unwrap_or(&[])
            .iter()
            .map(|x| *x as f64)
            .collect(),
    }
}

/// A fixed axis of a stream (`azimuth`, `x`, ...).
fn axis(stream: &SensorStream, name: &str) -> Vec<f64> {
    stream
        .axes
        .iter()
        .find(|a| a.name == name)
        .map(|a| a.data.clone())
        .unwrap_or_default()
}

/// One sensor's readings on `/<name>` ([`sensor_message`]).
fn record_sensor(
    rec: &mut Recorder,
    result: &RunResult,
    m: &SensorModel,
    stream: &SensorStream,
) -> std::result::Result<(), String> {
    let topic = format!("/{}", m.name);
    let names = joint_names(result);
    let axis = |name: &str| axis(stream, name);
    let mut channel = None;
    for (k, t) in stream.times.iter().enumerate() {
        let get = |name: &str| reading(stream, name, k);
        let r = Reading {
            channel: &get,
            axis: &axis,
        };
        let msg = sensor_message(m, *t, &r, &names)?;
        let ch = match channel {
            Some(c) => c,
            None => {
                let c = match &msg {
                    SensorMessage::Imu(_) => rec.channel::<Imu>(&topic, false)?,
                    SensorMessage::Scan(_) => rec.channel::<LaserScan>(&topic, false)?,
                    SensorMessage::Cloud(_) => rec.channel::<PointCloud2>(&topic, false)?,
                    SensorMessage::Image(_) => rec.channel::<Image>(&topic, false)?,
                    SensorMessage::Joints(_) => rec.channel::<JointState>(&topic, false)?,
                };
                channel = Some(c);
                c
            }
        };
        match &msg {
            SensorMessage::Imu(x) => rec.push(ch, *t, x)?,
            SensorMessage::Scan(x) => rec.push(ch, *t, x)?,
            SensorMessage::Cloud(x) => rec.push(ch, *t, x)?,
            SensorMessage::Image(x) => rec.push(ch, *t, x)?,
            SensorMessage::Joints(x) => rec.push(ch, *t, x)?,
        }
    }
    Ok(())
}
