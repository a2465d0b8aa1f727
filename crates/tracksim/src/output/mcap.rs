//! `run.mcap`: a run as a ROS 2 recording (MCAP, profile `ros2`, messages `cdr`, schemas
//! `ros2msg`, uncompressed chunks), which Foxglove and the ROS 2 bag tools open. Log, publish
//! and header times are the simulated time (ns from the start of the run). Messages are
//! written in time order.
//!
//! A world of several robots has one `run.mcap` too ([`team_mcap_bytes`]): each robot's topics
//! below under `/<name>/` and its frames prefixed `<name>/` ([`super::ros_names`]), one
//! `/clock`, one `/tf` carrying every robot's transforms and one `/tf_static`; `map` is shared.
//!
//! Frames (REP 103 axes, REP 105 names):
//! - `map`: the world frame (REP 105); ground truth and the elevation map are in it;
//! - `odom`: the encoders' odometry frame (it coincides with `map` at the start; `map ->
//!   odom` on `/tf` is the drift the slip has caused);
//! - `base_link`: the chassis (the vehicle file's body frame);
//! - `<flipper>_flipper_link`: each flipper, origin at its pivot, axes those of `base_link` at
//!   angle 0, turned by the flipper angle about its axis;
//! - `<sensor>_link`: each sensor's frame (`xyz_m`, `rpy_deg` of the vehicle file) on its
//!   mount (`base_link` or the flipper's link); a depth or colour camera also has
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
//!   117 infinities) in `<sensor>_optical_frame`; a colour camera as
//!   `sensor_msgs/CompressedImage` (its PNG frames, format `"rgb8; png compressed bgr8"`) on
//!   `/<sensor>/compressed` and `sensor_msgs/CameraInfo` (K from its field of view, plumb bob
//!   with zero distortion) on `/<sensor>/camera_info`, both in `<sensor>_optical_frame` with
//!   the reading's stamp, and with [`McapOptions::raw_images`] the raw `sensor_msgs/Image`
//!   (`rgb8`) on `/<sensor>`; an elevation map as `sensor_msgs/PointCloud2`
//!   of its cells' surface points in `map` (organised: `x` rows of `y` columns, NaN where a
//!   cell is unknown); encoders as `sensor_msgs/JointState` with the names of `/joint_states`
//!   (their quantised readings; the flippers' velocity NaN: not measured);
//! - with a `[course]`: `/course/events` (`tracksim_msgs/CourseEvent`, each event of the score
//!   at its time: gates, repetitions, faults, the finish) and `/course`
//!   (`tracksim_msgs/CourseStatus`) once, the final score at the run's end (the live node sends
//!   it at every sample; a recording has the events that changed it).

use super::ros_course::{course_event, course_status};
pub use super::ros_messages::{
    BASE_FRAME, ODOM_FRAME, belt_joint, encoder_model, encoder_odometry, flipper_frame,
    joint_state, optical_rotation, pose_rotation, tf_of_sample, tf_static, track_states, transform,
    true_odometry,
};
use super::ros_names::Namespace;
pub use super::ros_sensors::{MAP_FRAME, optical_frame, sensor_frame};
use super::ros_sensors::{
    Reading, SensorMessage, camera_info_topic, compressed_topic, sensor_message,
};
use crate::error::{Error, Result};
use crate::model::{Scenario, SensorModel};
use crate::rosmsg::{
    self, CameraInfo, Clock, CompressedImage, CourseEvent, CourseStatus, Image, Imu, JointState,
    LaserScan, Odometry, PointCloud2, RosMessage, TFMessage, TrackStates,
};
use crate::run::{RunResult, TeamResult};
use crate::sensors::{SensorStream, Values};
use crate::world::Sample;
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// The file name of the recording in a run folder.
pub const MCAP_FILE: &str = "run.mcap";

/// What `run.mcap` holds besides what every recording has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct McapOptions {
    /// Colour cameras' raw `sensor_msgs/Image` (`rgb8`) on `/<sensor>` besides their
    /// `CompressedImage` (PNG) on `/<sensor>/compressed`: 57.6 kB per 160 x 120 frame against
    /// 3 to 37 kB of PNG (docs/MCAP.md); Foxglove shows the compressed topic, so it is off by
    /// default.
    pub raw_images: bool,
}

/// Writes `dir/run.mcap` (atomically) from a run of `sc`; returns its path.
pub fn write_mcap(
    sc: &Scenario,
    result: &RunResult,
    dir: &Path,
    opts: McapOptions,
) -> Result<PathBuf> {
    let path = dir.join(MCAP_FILE);
    let bytes = mcap_bytes_with(sc, result, opts).map_err(|e| Error::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    crate::files::write_atomic(&path, &bytes)?;
    Ok(path)
}

/// The bytes of `run.mcap` for a run of `sc` (an error says what could not be encoded), with
/// the default [`McapOptions`].
pub fn mcap_bytes(sc: &Scenario, result: &RunResult) -> std::result::Result<Vec<u8>, String> {
    mcap_bytes_with(sc, result, McapOptions::default())
}

/// [`mcap_bytes`] with `opts`.
pub fn mcap_bytes_with(
    sc: &Scenario,
    result: &RunResult,
    opts: McapOptions,
) -> std::result::Result<Vec<u8>, String> {
    world_bytes(&[(sc, result, Namespace::none())], opts)
}

/// Writes the world's `dir/run.mcap` (atomically) from a run of `sc`, a scenario with several
/// robots ([`team_mcap_bytes`]); returns its path.
pub fn write_team_mcap(
    sc: &Scenario,
    r: &TeamResult,
    dir: &Path,
    opts: McapOptions,
) -> Result<PathBuf> {
    let path = dir.join(MCAP_FILE);
    let bytes = team_bytes(sc, r, opts).map_err(|e| Error::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    crate::files::write_atomic(&path, &bytes)?;
    Ok(path)
}

/// The bytes of the world's `run.mcap` for a run of `sc` with several robots: every robot's
/// topics and frames in its namespace ([`Namespace`]: `/<name>/odom`, `/<name>/joint_states`,
/// `/<name>/<sensor>`, frames `<name>/odom`, `<name>/base_link`), as `tracksim ros` publishes
/// them; one `/clock`, one `/tf` (every robot's transforms in one message per sample) and one
/// `/tf_static`.
pub fn team_mcap_bytes(sc: &Scenario, r: &TeamResult) -> std::result::Result<Vec<u8>, String> {
    team_bytes(sc, r, McapOptions::default())
}

/// [`team_mcap_bytes`] with `opts`.
fn team_bytes(
    sc: &Scenario,
    r: &TeamResult,
    opts: McapOptions,
) -> std::result::Result<Vec<u8>, String> {
    let views: Vec<Scenario> = (0..r.robots.len()).map(|k| sc.robot_view(k)).collect();
    let robots: Vec<(&Scenario, &RunResult, Namespace)> = views
        .iter()
        .zip(&r.robots)
        .map(|(v, (name, run))| (v, run, Namespace::robot(name)))
        .collect();
    world_bytes(&robots, opts)
}

/// The recording of `robots` (each robot's own scenario, run and namespace) in one world.
fn world_bytes(
    robots: &[(&Scenario, &RunResult, Namespace)],
    opts: McapOptions,
) -> std::result::Result<Vec<u8>, String> {
    let mut rec = Recorder::new()?;
    record_samples(&mut rec, robots)?;
    record_static(&mut rec, robots)?;
    record_descriptions(&mut rec, robots)?;
    record_scene(&mut rec, robots)?;
    record_course(&mut rec, robots)?;
    for (sc, result, ns) in robots {
        for stream in &result.sensors {
            let Some(m) = sc.vehicle.sensors.iter().find(|m| m.name == stream.name) else {
                continue;
            };
            record_sensor(&mut rec, (result, ns), m, stream, opts)?;
        }
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

    /// A JSON channel on `topic` with schema `name` (JSON schema `schema`), as Foxglove's own
    /// schemas (`foxglove.SceneUpdate`) are recorded.
    fn json_channel(
        &mut self,
        topic: &str,
        name: &str,
        schema: &str,
    ) -> std::result::Result<u16, String> {
        let id = self
            .writer
            .add_schema(name, "jsonschema", schema.as_bytes())
            .map_err(|e| format!("MCAP schema {name}: {e}"))?;
        let meta = BTreeMap::from([("offered_qos_profiles".to_string(), qos(true))]);
        self.writer
            .add_channel(id, topic, "json", &meta)
            .map_err(|e| format!("MCAP channel {topic}: {e}"))
    }

    /// JSON `value` on `channel` at `t` s.
    fn push_json(&mut self, channel: u16, t: f64, value: &serde_json::Value) {
        self.messages.push((
            rosmsg::Time::from_secs(t).nanos(),
            channel,
            value.to_string().into_bytes(),
        ));
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

/// The joint names of `/joint_states`: the flippers, then the belts.
fn joint_names(result: &RunResult) -> Vec<String> {
    let mut names = result.flipper_names.clone();
    names.extend(result.track_names.iter().map(|n| belt_joint(n)));
    names
}

/// A robot's channels of its samples.
struct SampleChannels {
    odom: u16,
    truth: u16,
    joints: u16,
    tracks: u16,
}

/// `/clock` and `/tf` (every robot's transforms) at every sample, and each robot's `/odom`,
/// `/ground_truth/odom`, `/joint_states` and `/tracks` (in its namespace).
fn record_samples(
    rec: &mut Recorder,
    robots: &[(&Scenario, &RunResult, Namespace)],
) -> std::result::Result<(), String> {
    let clock = rec.channel::<Clock>("/clock", false)?;
    let tf = rec.channel::<TFMessage>("/tf", false)?;
    let mut channels = Vec::new();
    for (_, _, ns) in robots {
        channels.push(SampleChannels {
            odom: rec.channel::<Odometry>(&ns.topic("/odom"), false)?,
            truth: rec.channel::<Odometry>(&ns.topic("/ground_truth/odom"), false)?,
            joints: rec.channel::<JointState>(&ns.topic("/joint_states"), false)?,
            tracks: rec.channel::<TrackStates>(&ns.topic("/tracks"), false)?,
        });
    }
    let mut models: Vec<_> = robots.iter().map(|r| encoder_model(r.0)).collect();
    let names: Vec<_> = robots.iter().map(|r| joint_names(r.1)).collect();
    let count = robots.iter().map(|r| r.1.samples.len()).max().unwrap_or(0);
    // Each robot's samples read once in order (they may be on disk), with the one before.
    let mut iters: Vec<_> = robots.iter().map(|r| r.1.samples.iter()).collect();
    let mut previous: Vec<Option<Sample>> = vec![None; robots.len()];
    for _ in 0..count {
        // The robots' samples are taken at the same steps.
        let here: Vec<(usize, std::borrow::Cow<'_, Sample>, Odometry)> = iters
            .iter_mut()
            .enumerate()
            .filter_map(|(k, it)| it.next().map(|s| (k, s)))
            .map(|(k, s)| {
                let enc = encoder_odometry(&s, &mut models[k]);
                (k, s, enc)
            })
            .collect();
        let Some(t) = here.first().map(|h| h.1.t) else {
            continue;
        };
        rec.push(
            clock,
            t,
            &Clock {
                clock: rosmsg::Time::from_secs(t),
            },
        )?;
        let transforms = here
            .iter()
            .flat_map(|(k, s, enc)| {
                let (sc, _, ns) = &robots[*k];
                ns.tf(tf_of_sample(sc, s, enc, true)).transforms
            })
            .collect();
        rec.push(tf, t, &TFMessage { transforms })?;
        for (k, s, enc) in here {
            let (_, run, ns) = &robots[k];
            let ch = &channels[k];
            let last = previous[k].as_ref();
            rec.push(ch.odom, s.t, &ns.odometry(enc))?;
            rec.push(ch.truth, s.t, &ns.odometry(true_odometry(&s)))?;
            rec.push(ch.joints, s.t, &joint_state(&names[k], &s, last))?;
            rec.push(
                ch.tracks,
                s.t,
                &ns.track_states(track_states(&s, &run.track_names)),
            )?;
            previous[k] = Some(s.into_owned());
        }
    }
    Ok(())
}

/// `/tf_static` ([`tf_static`], every robot's in its namespace) once at t = 0, when a vehicle
/// has sensor frames.
fn record_static(
    rec: &mut Recorder,
    robots: &[(&Scenario, &RunResult, Namespace)],
) -> std::result::Result<(), String> {
    let transforms: Vec<_> = robots
        .iter()
        .flat_map(|(sc, _, ns)| ns.tf(tf_static(sc)).transforms)
        .collect();
    if transforms.is_empty() {
        return Ok(());
    }
    let ch = rec.channel::<TFMessage>("/tf_static", true)?;
    rec.push(ch, 0.0, &TFMessage { transforms })
}

/// Each robot's `/course/events` (`tracksim_msgs/CourseEvent`, [`course_event`]) at their
/// times, and its `/course` (`tracksim_msgs/CourseStatus`, [`course_status`]) once, the final
/// score at the run's end, when the scenario has a `[course]`.
fn record_course(
    rec: &mut Recorder,
    robots: &[(&Scenario, &RunResult, Namespace)],
) -> std::result::Result<(), String> {
    for (_, run, ns) in robots {
        let Some(c) = &run.summary.course else {
            continue;
        };
        let status = rec.channel::<CourseStatus>(&ns.topic("/course"), false)?;
        let events = rec.channel::<CourseEvent>(&ns.topic("/course/events"), false)?;
        for e in &c.events {
            rec.push(events, e.t_s, &course_event(e))?;
        }
        let end = run.samples.last().map_or(0.0, |s| s.t);
        rec.push(status, end, &course_status(end, c))?;
    }
    Ok(())
}

/// `/scene` (`foxglove.SceneUpdate`, JSON) once at t = 0: the terrain in `map` and each
/// robot's links in its frames ([`super::foxglove_scene`]); on a soil run each robot's `/soil`
/// (its tracks' sinkage and thrust) at every sample.
fn record_scene(
    rec: &mut Recorder,
    robots: &[(&Scenario, &RunResult, Namespace)],
) -> std::result::Result<(), String> {
    use super::foxglove_scene as fx;
    let list: Vec<(&Scenario, Namespace)> =
        robots.iter().map(|(sc, _, ns)| (*sc, ns.clone())).collect();
    let ch = rec.json_channel(fx::SCENE_TOPIC, fx::SCENE_SCHEMA, &fx::scene_schema())?;
    let scene = fx::scene_update(&list, MAP_FRAME);
    rec.push_json(ch, 0.0, &scene);
    for (_, run, ns) in robots {
        let mut ch = None;
        for s in run.samples.iter() {
            let Some(m) = fx::soil_message(&s, &run.track_names) else {
                continue;
            };
            let c = match ch {
                Some(c) => c,
                None => *ch.insert(rec.json_channel(
                    &ns.topic(fx::SOIL_TOPIC),
                    fx::SOIL_SCHEMA,
                    &fx::soil_schema(),
                )?),
            };
            rec.push_json(c, s.t, &m);
        }
    }
    Ok(())
}

/// Each robot's `/robot_description` (its URDF, [`super::urdf_export::robot_description`]) once
/// at t = 0, latched, in its namespace.
fn record_descriptions(
    rec: &mut Recorder,
    robots: &[(&Scenario, &RunResult, Namespace)],
) -> std::result::Result<(), String> {
    for (sc, _, ns) in robots {
        let ch = rec.channel::<rosmsg::RosString>(&ns.topic("/robot_description"), true)?;
        let data = super::urdf_export::robot_description(sc);
        rec.push(ch, 0.0, &rosmsg::RosString { data })?;
    }
    Ok(())
}

/// Reading `r`'s channel called `name` (f64; empty if there is no such channel).
fn reading(stream: &SensorStream, r: &crate::sensors::Reading, name: &str) -> Vec<f64> {
    let Some(c) = stream.channels.iter().position(|c| c.name == name) else {
        return Vec::new();
    };
    match &r.values[c] {
        Values::F64(v) => v.clone(),
        Values::F32(v) => v.iter().map(|x| *x as f64).collect(),
        Values::Png(b) => crate::render::encode::decode_values(b).unwrap_or_default(),
    }
}

/// Reading `r`'s image channel called `name` as its stored PNG bytes.
fn reading_png(stream: &SensorStream, r: &crate::sensors::Reading, name: &str) -> Option<Vec<u8>> {
    let c = stream.channels.iter().position(|c| c.name == name)?;
    match &r.values[c] {
        Values::Png(v) => Some(v.clone()),
        _ => None,
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

/// The channels of one sensor's messages, made at its first reading.
enum SensorChannels {
    /// One topic.
    One(u16),
    /// A colour camera: raw images (with `raw_images`), compressed images, calibration.
    Camera(Option<u16>, u16, u16),
}

/// One sensor's readings on `/<name>` ([`sensor_message`]), in the robot's namespace; a colour
/// camera's on `/<name>/compressed` and `/<name>/camera_info` (and `/<name>` with
/// `raw_images`).
fn record_sensor(
    rec: &mut Recorder,
    (result, ns): (&RunResult, &Namespace),
    m: &SensorModel,
    stream: &SensorStream,
    opts: McapOptions,
) -> std::result::Result<(), String> {
    let topic = ns.topic(&format!("/{}", m.name));
    let names = joint_names(result);
    let axis = |name: &str| axis(stream, name);
    let mut channels = None;
    for one in stream.readings.iter() {
        let t = &one.t;
        let get = |name: &str| reading(stream, &one, name);
        let png = |name: &str| reading_png(stream, &one, name);
        let r = Reading {
            channel: &get,
            axis: &axis,
            png: &png,
        };
        let msg = ns.sensor(sensor_message(m, *t, &r, &names)?);
        let ch = match &channels {
            Some(c) => c,
            None => {
                let one = |c| Ok::<_, String>(SensorChannels::One(c));
                let c = match &msg {
                    SensorMessage::Imu(_) => one(rec.channel::<Imu>(&topic, false)?)?,
                    SensorMessage::Scan(_) => one(rec.channel::<LaserScan>(&topic, false)?)?,
                    SensorMessage::Cloud(_) => one(rec.channel::<PointCloud2>(&topic, false)?)?,
                    SensorMessage::Image(_) => one(rec.channel::<Image>(&topic, false)?)?,
                    SensorMessage::Joints(_) => one(rec.channel::<JointState>(&topic, false)?)?,
                    SensorMessage::Camera(_) => SensorChannels::Camera(
                        match opts.raw_images {
                            true => Some(rec.channel::<Image>(&topic, false)?),
                            false => None,
                        },
                        rec.channel::<CompressedImage>(&compressed_topic(&topic), false)?,
                        rec.channel::<CameraInfo>(&camera_info_topic(&topic), false)?,
                    ),
                };
                channels.insert(c)
            }
        };
        match (ch, &msg) {
            (SensorChannels::One(c), SensorMessage::Imu(x)) => rec.push(*c, *t, x)?,
            (SensorChannels::One(c), SensorMessage::Scan(x)) => rec.push(*c, *t, x)?,
            (SensorChannels::One(c), SensorMessage::Cloud(x)) => rec.push(*c, *t, x)?,
            (SensorChannels::One(c), SensorMessage::Image(x)) => rec.push(*c, *t, x)?,
            (SensorChannels::One(c), SensorMessage::Joints(x)) => rec.push(*c, *t, x)?,
            (SensorChannels::Camera(raw, compressed, info), SensorMessage::Camera(x)) => {
                if let Some(c) = raw {
                    rec.push(*c, *t, &x.image)?;
                }
                rec.push(*compressed, *t, &x.compressed)?;
                rec.push(*info, *t, &x.info)?;
            }
            _ => return Err(format!("sensor {}: its messages changed type", m.name)),
        }
    }
    Ok(())
}
