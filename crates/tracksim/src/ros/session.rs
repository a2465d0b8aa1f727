//! A `tracksim ros` session: the scenario's [`Runner`] (the one run loop; paced to the wall
//! clock unless `fast`) with its controls from ROS topics, recorded as a run.
//!
//! At every sample boundary (`output_interval_s`, 10 ms by default) and only there, as in a
//! `drive` session: the received commands are sanitised and taken in, the watchdog is
//! applied, changed controls go to the physics (recorded as a `[[commands]]` entry at that
//! time, so `commands.toml` replays the session with `tracksim run`); then the world steps
//! to the next sample, which is published.
//!
//! A file with several robots ([`run_ros_team`]) is one node on the same loop over the world's
//! [`TeamRunner`]: each robot's topics and frames in its namespace
//! ([`crate::output::ros_names::Namespace`]), its own [`RobotControl`] (command state,
//! watchdog, counts), one `/clock`, `/tf`, `/tf_static` and `/rosout` for the world.

use super::commands::{Command, CommandState, WATCHDOG_TIMEOUT_S};
use super::dds::{DdsNode, Publishers, Subscriptions, WorldPublishers};
use super::network::NetworkRange;
use super::sanitize::{self, Problem, Warnings};
use super::sensors::SensorPublishers;
use super::services::{ServiceCall, Services};
use super::topics;
use crate::error::{Error, Result};
use crate::model::{Scenario, VehicleModel};
use crate::output::ros_course::{EventCursor, course_event, course_status};
use crate::output::ros_messages::{
    self as messages, encoder_model, encoder_odometry, track_states, true_odometry,
};
use crate::output::ros_names::Namespace;
use crate::rosmsg::{TFMessage, TransformStamped};
use crate::run::{
    CommandLog, ControlSource, CourseScore, LogHeader, RunResult, Runner, SessionLimits,
    TeamResult, TeamRunner, WorldSource, run_world_session,
};
use crate::sensors::SensorSet;
use crate::spec::{CommandSpec, PerTrack};
use crate::world::Sample;
use ros2_client::log::LogLevel;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Options of a session.
#[derive(Clone, Debug, Default)]
pub struct RosOptions {
    /// Step as fast as the computer can (`/clock` tells the others the time) instead of at
    /// real time.
    pub fast: bool,
    /// Also publish `map -> odom` on `/tf` from the true pose (a perfect localisation; leave
    /// it off when a localisation node such as AMCL or a SLAM node publishes it).
    pub map_tf: bool,
    /// End the session at this simulated time, s (None: on Ctrl-C or SIGTERM).
    pub max_time: Option<f64>,
    /// The DDS domain (`ROS_DOMAIN_ID`).
    pub domain_id: u16,
    /// Also publish colour cameras' raw `sensor_msgs/Image` (`rgb8`) on `/<sensor>`, besides
    /// their `CompressedImage` (PNG) on `/<sensor>/compressed` and `CameraInfo` (off by
    /// default: Foxglove shows the compressed topic, a few times to 20 times smaller; RViz's Image
    /// display and `cv_bridge` nodes want the raw one, or `image_transport republish`).
    pub raw_images: bool,
    /// The network the node is reachable on.
    pub network: NetworkRange,
    /// A one-robot session's namespace: its topics under `/<namespace>/` and its frames
    /// prefixed `<namespace>/`, as a robot of a world of several robots (None: the one-robot
    /// names).
    pub namespace: Option<String>,
    /// When set (by a Ctrl-C or SIGTERM handler), the session ends at the next sample as
    /// interrupted.
    pub interrupt: Option<&'static AtomicBool>,
    /// Play the file's `[[commands]]` (each robot's) until the robot's first ROS command
    /// ([`FileCommands`]); off: they are not played, and a line says so.
    pub play_commands: bool,
}

/// A finished session.
pub struct RosSession {
    /// The run, as `tracksim run` returns it.
    pub result: RunResult,
    /// Each change of the controls, as a scenario's `[[commands]]` entry at the simulated
    /// time it was applied (belt speeds by track name, flipper targets in degrees).
    pub log: CommandLog,
    /// Commands taken in.
    pub received: u64,
    /// Problems found in received messages (each dropped or clamped, see
    /// [`super::sanitize`]).
    pub problems: u64,
    /// Samples dropped because they did not decode as their topic's type
    /// ([`super::decode`]).
    pub undecodable: u64,
    /// Times the watchdog stopped the robot.
    pub watchdog_stops: u64,
    /// Times `/tracksim/reset` restarted the session (the run written is the one since the
    /// last).
    pub resets: u64,
}

/// Reports a warning on `/rosout` and through `warn` (standard error for the CLI).
struct Reporter<'a> {
    node: &'a DdsNode,
    warnings: Warnings,
    warn: &'a mut dyn FnMut(&str),
}

impl Reporter<'_> {
    fn say(&mut self, level: LogLevel, t: f64, msg: &str) {
        self.node.rosout(level, t, msg);
        (self.warn)(msg);
    }

    fn problems(&mut self, t: f64, problems: &[Problem]) {
        for p in problems {
            if let Some(text) = self.warnings.admit(p) {
                self.say(LogLevel::Warn, t, &text);
            }
        }
        for text in self.warnings.held_back() {
            self.say(LogLevel::Warn, t, &text);
        }
    }
}

/// Every command received since the last call on robot namespace `ns`'s topics at simulated
/// time `t` s, sanitised (problems into `problems`).
fn receive(
    subs: &Subscriptions,
    ns: &Namespace,
    v: &VehicleModel,
    t: f64,
    problems: &mut Vec<Problem>,
) -> Vec<Command> {
    let mut out = Vec::new();
    let cmd_vel = ns.topic(topics::CMD_VEL);
    let plain = subs.cmd_vel.drain();
    let stamped = subs.cmd_vel_stamped.drain();
    let twists = plain.iter().chain(
        stamped
            .iter()
            .filter_map(|m| sanitize::fresh_twist(&cmd_vel, m, t, problems)),
    );
    for tw in twists.collect::<Vec<_>>() {
        if let Some((f, w)) = sanitize::twist(&cmd_vel, tw, problems) {
            out.push(Command::Twist {
                forward_mps: f,
                yaw_rate_rad_s: w,
            });
        }
    }
    cmd_vel_undecodable(subs, stamped.len(), problems);
    for (track, sub) in subs.track_speed.iter().enumerate() {
        for m in sub.iter().flat_map(|s| s.drain()) {
            let topic = &sub.as_ref().expect("drained").topic;
            if let Some(mps) = sanitize::belt_speed(topic, m.data, problems) {
                out.push(Command::BeltSpeed { track, mps });
            }
        }
        sub.iter().for_each(|s| undecodable(s, problems));
    }
    for (flipper, sub) in subs.flipper_position.iter().enumerate() {
        for m in sub.iter().flat_map(|s| s.drain()) {
            let topic = &sub.as_ref().expect("drained").topic;
            if let Some(rad) = sanitize::flipper_angle(topic, m.data, problems) {
                out.push(Command::Flipper { flipper, rad });
            }
        }
        sub.iter().for_each(|s| undecodable(s, problems));
    }
    let positions = ns.topic(topics::FLIPPER_POSITIONS);
    for js in subs.flipper_positions.drain() {
        let targets = sanitize::joint_command(&positions, v, &js, problems);
        out.extend(
            targets
                .into_iter()
                .map(|(flipper, rad)| Command::Flipper { flipper, rad }),
        );
    }
    undecodable(&subs.flipper_positions, problems);
    out
}

/// The `/cmd_vel` samples that decoded as neither form since the last call, as a problem.
/// RustDDS keeps one sample cache per topic name, so both readers see every sample: a stamped
/// one is an undecodable sample to the plain reader, and a plain one to the stamped reader.
/// What neither decoded is what the plain reader dropped less what the stamped one took; a
/// sample that arrives between the two readers' turns is counted by one of them in the next
/// call, so the difference is kept as a running balance (`Subscriptions::cmd_vel_balance`)
/// and only what is left over is reported.
fn cmd_vel_undecodable(subs: &Subscriptions, stamped: usize, problems: &mut Vec<Problem>) {
    let _ = subs.cmd_vel_stamped.take_dropped();
    let dropped = subs.cmd_vel.take_dropped() as i64;
    let balance = subs.cmd_vel_balance.get() + dropped - stamped as i64;
    let count = balance.max(0) as u64;
    subs.cmd_vel_balance.set(balance.min(0));
    if count > 0 {
        problems.push(Problem::Undecodable {
            topic: subs.cmd_vel.topic.clone(),
            count,
        });
    }
}

/// The samples of `sub` that did not decode since the last call, as a problem.
fn undecodable<T: super::decode::Bounded>(sub: &super::dds::Sub<T>, problems: &mut Vec<Problem>) {
    let count = sub.take_dropped();
    if count > 0 {
        problems.push(Problem::Undecodable {
            topic: sub.topic.clone(),
            count,
        });
    }
}

fn dds_error(e: String) -> Error {
    Error::Io {
        path: PathBuf::from("(ROS 2 / DDS)"),
        source: std::io::Error::other(e),
    }
}

/// What a robot's commands came to besides its run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Commands taken in.
    pub received: u64,
    /// Problems found in received messages (each dropped or clamped).
    pub problems: u64,
    /// Samples dropped because they did not decode as their topic's type (within bounds).
    pub undecodable: u64,
    /// Times the watchdog stopped the robot.
    pub watchdog_stops: u64,
}

/// A file's `[[commands]]` played in a ROS session until the robot's first ROS command: each
/// entry at the first sample boundary at or after its time (the entries due at one boundary
/// merged, later ones winning), as belt speeds and flipper targets by name, so that
/// `commands.toml` records them as it records ROS commands and the replay reproduces the
/// session.
#[derive(Clone, Debug, Default)]
pub struct FileCommands {
    entries: Vec<CommandSpec>,
    next: usize,
    playing: bool,
}

impl FileCommands {
    /// The commands `commands` (a compiled scenario's, sorted by time) of vehicle `v`, played
    /// if `play`.
    pub fn new(v: &VehicleModel, commands: &[crate::model::Command], play: bool) -> Self {
        let entries = commands
            .iter()
            .map(|c| {
                let belts: std::collections::BTreeMap<String, f64> = v
                    .tracks
                    .iter()
                    .zip(&c.controls.belt_speed)
                    .filter_map(|(t, s)| s.map(|s| (t.name.clone(), s)))
                    .collect();
                CommandSpec {
                    t_s: c.t,
                    belt_speed_mps: (!belts.is_empty()).then_some(PerTrack::ByName(belts)),
                    flipper_angle_deg: v
                        .flippers
                        .iter()
                        .zip(&c.controls.flipper_angle)
                        .filter_map(|(f, a)| a.map(|a| (f.name.clone(), a.to_degrees())))
                        .collect(),
                    ..CommandSpec::default()
                }
            })
            .collect();
        FileCommands {
            entries,
            next: 0,
            playing: play,
        }
    }

    /// How many entries the file has.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the file has none.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Whether they are still being played.
    pub fn playing(&self) -> bool {
        self.playing && !self.entries.is_empty()
    }

    /// The entries due at `t` s (merged into one at `t`), if any.
    fn due(&mut self, t: f64) -> Option<CommandSpec> {
        let mut out: Option<CommandSpec> = None;
        while let Some(e) = self.entries.get(self.next) {
            if e.t_s > t + 1e-9 {
                break;
            }
            self.next += 1;
            let o = out.get_or_insert_with(|| CommandSpec {
                t_s: t,
                ..CommandSpec::default()
            });
            if let Some(PerTrack::ByName(b)) = &e.belt_speed_mps {
                match &mut o.belt_speed_mps {
                    Some(PerTrack::ByName(m)) => m.extend(b.clone()),
                    _ => o.belt_speed_mps = Some(PerTrack::ByName(b.clone())),
                }
            }
            o.flipper_angle_deg.extend(e.flipper_angle_deg.clone());
        }
        out
    }
}

/// One robot's commands in a session, apart from DDS: its set-points ([`CommandState`]), its
/// own watchdog, and what they came to. Each robot of a world has its own, so one robot's
/// silent peer stops that robot only.
pub struct RobotControl {
    /// The robot's name in messages (`None`: the node's one robot).
    label: Option<String>,
    state: CommandState,
    /// The file's commands, played until the first ROS command.
    file: FileCommands,
    /// What the commands came to.
    pub counts: Counts,
}

impl RobotControl {
    /// Nothing commanded yet to a robot of vehicle `v`, named `label` in messages.
    pub fn new(label: Option<&str>, v: &VehicleModel) -> Self {
        RobotControl {
            label: label.map(str::to_string),
            state: CommandState::new(v),
            file: FileCommands::default(),
            counts: Counts::default(),
        }
    }

    /// The same, playing `file` until the first ROS command.
    pub fn with_file_commands(mut self, file: FileCommands) -> Self {
        self.file = file;
        self
    }

    /// Takes in `received` (sanitised) commands at simulated time `t` s, applies the watchdog
    /// (its stops reported to `say`), and returns the controls in force as a command entry at
    /// `t` if they changed: every belt speed by track name, the commanded flipper targets in
    /// degrees.
    pub fn controls(
        &mut self,
        v: &VehicleModel,
        t: f64,
        received: Vec<Command>,
        say: &mut dyn FnMut(&str),
    ) -> Option<CommandSpec> {
        if self.file.playing() {
            if received.is_empty() {
                return self.file.due(t);
            }
            self.file.playing = false;
            let who = self
                .label
                .as_ref()
                .map_or(String::new(), |l| format!("`{l}`: "));
            say(&format!(
                "{who}a ROS command arrived at t = {t:.2} s: the file's [[commands]] stop here; \
                 ROS commands drive the robot from now on"
            ));
        }
        for c in received {
            self.state.take(v, &c, t);
            self.counts.received += 1;
        }
        let stopped = self.state.watchdog(t);
        if !stopped.is_empty() {
            self.counts.watchdog_stops += 1;
            let names: Vec<&str> = stopped.iter().map(|&i| v.tracks[i].name.as_str()).collect();
            let who = self
                .label
                .as_ref()
                .map_or(String::new(), |l| format!("`{l}`: "));
            say(&format!(
                "{who}watchdog: no speed command for {WATCHDOG_TIMEOUT_S} s; stopping track(s) {}",
                names.join(", ")
            ));
        }
        self.state.changed_controls(v)?;
        Some(CommandSpec {
            t_s: t,
            belt_speed_mps: Some(PerTrack::ByName(
                v.tracks
                    .iter()
                    .map(|tr| tr.name.clone())
                    .zip(self.state.belt_speeds())
                    .collect(),
            )),
            flipper_angle_deg: v
                .flippers
                .iter()
                .zip(self.state.flipper_targets())
                .filter_map(|(f, a)| a.map(|a| (f.name.clone(), a.to_degrees())))
                .collect(),
            ..CommandSpec::default()
        })
    }
}

/// One robot on the node: its topics (in its namespace), commands and published state.
struct RobotTopics {
    ns: Namespace,
    subs: Subscriptions,
    control: RobotControl,
    pubs: Publishers,
    sensors: SensorPublishers,
    encoders: messages::EncoderOdom,
    joint_names: Vec<String>,
    track_names: Vec<String>,
    /// The course's events published so far.
    course_events: EventCursor,
}

impl RobotTopics {
    /// Robot `sc` (its own scenario) on `node` in namespace `ns`, and the command topics that
    /// make no ROS name (skipped).
    fn new(
        node: &mut DdsNode,
        sc: &Scenario,
        ns: Namespace,
        raw_images: bool,
        play_commands: bool,
    ) -> Result<(Self, Vec<String>)> {
        let track_names: Vec<String> = sc.vehicle.tracks.iter().map(|t| t.name.clone()).collect();
        let flipper_names: Vec<String> =
            sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect();
        let (subs, skipped) =
            Subscriptions::new(node, &ns, &track_names, &flipper_names).map_err(dds_error)?;
        let topics = RobotTopics {
            pubs: Publishers::new(node, &ns, sc.course.is_some()).map_err(dds_error)?,
            sensors: SensorPublishers::new(node, sc, &ns, raw_images).map_err(dds_error)?,
            control: RobotControl::new(ns.name(), &sc.vehicle)
                .with_file_commands(FileCommands::new(&sc.vehicle, &sc.commands, play_commands)),
            encoders: encoder_model(sc),
            joint_names: messages::joint_names(sc),
            track_names,
            course_events: EventCursor::default(),
            subs,
            ns,
        };
        Ok((topics, skipped))
    }

    /// The robot's controls at `t` s (see [`RobotControl::controls`]).
    fn controls(&mut self, v: &VehicleModel, t: f64, rep: &mut Reporter) -> Option<CommandSpec> {
        let mut problems = Vec::new();
        let received = receive(&self.subs, &self.ns, v, t, &mut problems);
        self.control.counts.problems += problems.len() as u64;
        self.control.counts.undecodable += problems
            .iter()
            .map(|p| match p {
                Problem::Undecodable { count, .. } => *count,
                _ => 0,
            })
            .sum::<u64>();
        rep.problems(t, &problems);
        self.control
            .controls(v, t, received, &mut |m| rep.say(LogLevel::Info, t, m))
    }

    /// Publishes sample `s` (after `prev`) of robot `sc`; its transforms go into `tf`.
    fn publish(
        &mut self,
        sc: &Scenario,
        (s, prev): (&Sample, Option<&Sample>),
        map_tf: bool,
        tf: &mut Vec<TransformStamped>,
    ) {
        let odom = encoder_odometry(s, &mut self.encoders);
        let ns = &self.ns;
        tf.extend(
            ns.tf(messages::tf_of_sample(sc, s, &odom, map_tf))
                .transforms,
        );
        self.pubs.odom.publish(ns.odometry(odom));
        self.pubs.truth.publish(ns.odometry(true_odometry(s)));
        self.pubs
            .joints
            .publish(messages::joint_state(&self.joint_names, s, prev));
        self.pubs
            .tracks
            .publish(ns.track_states(track_states(s, &self.track_names)));
    }

    /// Publishes the course's score `c` at sample time `t` s on `/course`, and its events new
    /// since the last sample on `/course/events` (nothing without a course).
    fn publish_course(&mut self, t: f64, c: Option<&CourseScore>) {
        let (Some((status, events)), Some(c)) = (&self.pubs.course, c) else {
            return;
        };
        for e in self.course_events.new_events(c) {
            events.publish(course_event(e));
        }
        status.publish(course_status(t, c));
    }

    /// Publishes every new sensor reading of `set` at `t` s.
    fn publish_sensors(&mut self, set: &SensorSet, t: f64, rep: &mut Reporter) {
        self.sensors
            .publish(set, &mut |e| rep.say(LogLevel::Warn, t, e));
    }
}

/// The node's shared part: `/rosout` (with the rate-limited warnings), `/clock`, `/tf` and
/// `/tf_static`.
struct World<'w> {
    rep: Reporter<'w>,
    pubs: WorldPublishers,
    map_tf: bool,
    /// Every robot's command topics and the types each is read as.
    read_types: Vec<(String, Vec<&'static str>)>,
    /// The (topic, type) of each foreign publisher already reported.
    foreign_said: std::collections::HashSet<(String, String)>,
    /// The simulated time of the next look at the discovered publishers, s.
    next_foreign_check: f64,
}

/// Simulated time between two looks at the discovered publishers, s.
const FOREIGN_CHECK_S: f64 = 1.0;

impl World<'_> {
    /// `/clock` at `t` s, then `/tf` with `transforms` (every robot's); once a simulated
    /// second, a publisher of another type on a command topic is reported.
    fn publish(&mut self, t: f64, transforms: Vec<TransformStamped>) {
        self.pubs.clock.publish(messages::clock(t));
        self.pubs.tf.publish(TFMessage { transforms });
        if t >= self.next_foreign_check {
            self.next_foreign_check = t + FOREIGN_CHECK_S;
            self.report_foreign_types(t);
        }
    }

    /// Reports, once each, the discovered publishers on a command topic whose type the node
    /// does not read (issue 61: DDS never matches them, so nothing arrives and nothing said).
    fn report_foreign_types(&mut self, t: f64) {
        let ros = |ty: &str| ty.replacen('/', "/msg/", 1);
        for (topic, ty) in self.rep.node.discovered_publishers() {
            let Some((_, read)) = self.read_types.iter().find(|(x, _)| *x == topic) else {
                continue;
            };
            if read.contains(&ty.as_str()) || !self.foreign_said.insert((topic.clone(), ty.clone()))
            {
                continue;
            }
            let wanted: Vec<String> = read.iter().map(|r| ros(r)).collect();
            let m = format!(
                "{topic}: a publisher of {} is not read (DDS matches it to no reader): tracksim \
                 reads {topic} as {}",
                ros(&ty),
                wanted.join(" or ")
            );
            self.rep.say(LogLevel::Warn, t, &m);
        }
    }
}

/// The last sample of `samples` and the one before it.
fn last_two(samples: &crate::run::SampleLog) -> Option<(&Sample, Option<&Sample>)> {
    // The last two are always in memory (`SampleLog::recent`).
    let samples = samples.recent();
    let n = samples.len();
    samples
        .last()
        .map(|s| (s, n.checked_sub(2).map(|k| &samples[k])))
}

/// ROS 2 topics as a one-robot session's control source: commands received, sanitised and
/// taken in at every sample boundary, the watchdog applied; the sensors published after every
/// step and the state at every sample.
struct TopicSource<'a, 'w> {
    sc: &'a Scenario,
    robot: RobotTopics,
    world: World<'w>,
    /// `/tracksim/reset` and `/tracksim/set_paused`.
    services: Option<Services>,
    paused: bool,
    reset_asked: bool,
    resets: u64,
    play_commands: bool,
    interrupt: Option<&'static AtomicBool>,
}

impl TopicSource<'_, '_> {
    /// Answers the service requests received at `t` s.
    fn serve(&mut self, t: f64) {
        let Some(services) = &self.services else {
            return;
        };
        let mut said = Vec::new();
        let (paused, reset_asked) = (&mut self.paused, &mut self.reset_asked);
        services.serve(&mut |call| match call {
            ServiceCall::Reset => {
                *reset_asked = true;
                *paused = false;
                let m = format!(
                    "reset at t = {t:.2} s: the robot goes back to its start pose and the \
                     session starts again (the run written and commands.toml are the ones \
                     since the last reset)"
                );
                said.push(m.clone());
                (true, m)
            }
            ServiceCall::SetPaused(p) => {
                *paused = *p;
                let m = if *p {
                    format!("paused at t = {t:.2} s: the simulated clock stands still")
                } else {
                    format!("resumed at t = {t:.2} s")
                };
                said.push(m.clone());
                (true, m)
            }
        });
        for m in said {
            self.world.rep.say(LogLevel::Info, t, &m);
        }
    }

    fn interrupted(&self) -> bool {
        self.interrupt
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }
}

impl ControlSource for TopicSource<'_, '_> {
    fn reset(&mut self) -> bool {
        if !std::mem::take(&mut self.reset_asked) {
            return false;
        }
        let v = &self.sc.vehicle;
        self.robot.control = RobotControl::new(self.robot.ns.name(), v)
            .with_file_commands(FileCommands::new(v, &self.sc.commands, self.play_commands));
        self.robot.encoders = encoder_model(self.sc);
        self.resets += 1;
        true
    }

    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec> {
        let t = runner.time();
        self.serve(t);
        // Paused: the simulated clock stands still; the services and Ctrl-C are still heard.
        while self.paused && !self.interrupted() {
            std::thread::sleep(std::time::Duration::from_millis(10));
            self.serve(t);
        }
        if self.reset_asked {
            // The restart comes at the next boundary, before anything is commanded.
            return None;
        }
        self.robot
            .controls(&self.sc.vehicle, t, &mut self.world.rep)
    }

    fn after_step(&mut self, runner: &Runner) {
        self.robot
            .publish_sensors(runner.sensors(), runner.time(), &mut self.world.rep);
    }

    fn after_sample(&mut self, runner: &Runner) {
        if let Some(s) = last_two(runner.samples()) {
            let mut tf = Vec::new();
            self.robot.publish(self.sc, s, self.world.map_tf, &mut tf);
            self.robot.publish_course(s.0.t, runner.course().as_ref());
            self.world.publish(s.0.t, tf);
        }
    }
}

/// ROS 2 topics as the control source of a session of several robots: each robot's own
/// topics, commands and watchdog ([`RobotTopics`] per robot), one `/clock` and one `/tf`.
struct TeamTopicSource<'w> {
    robots: Vec<RobotTopics>,
    world: World<'w>,
}

impl WorldSource<TeamRunner> for TeamTopicSource<'_> {
    fn controls(&mut self, runner: &TeamRunner, k: usize) -> Option<CommandSpec> {
        let v = &runner.robot_scenario(k).vehicle;
        self.robots[k].controls(v, runner.sim().time(), &mut self.world.rep)
    }

    fn after_step(&mut self, runner: &mut TeamRunner) {
        let t = runner.sim().time();
        for (k, r) in self.robots.iter_mut().enumerate() {
            r.publish_sensors(runner.view(k).sensors, t, &mut self.world.rep);
        }
    }

    fn after_sample(&mut self, runner: &mut TeamRunner) {
        let t = runner.sim().time();
        let mut tf = Vec::new();
        for (k, r) in self.robots.iter_mut().enumerate() {
            let view = runner.view(k);
            if let Some(s) = last_two(view.samples) {
                r.publish(view.scenario, s, self.world.map_tf, &mut tf);
                r.publish_course(s.0.t, view.course.as_ref());
            }
        }
        self.world.publish(t, tf);
    }
}

/// Starts the node with a robot's topics for each of `robots` (its own scenario and
/// namespace): the shared part (reporting to `warn`) and the robots, `/tf_static` published
/// with every robot's sensor mounts.
fn start<'w>(
    node: &'w mut DdsNode,
    opts: &RosOptions,
    robots: &[(&Scenario, Namespace)],
    warn: &'w mut dyn FnMut(&str),
) -> Result<(World<'w>, Vec<RobotTopics>)> {
    let pubs = WorldPublishers::new(node).map_err(dds_error)?;
    let mut topics = Vec::new();
    let mut skipped = Vec::new();
    let mut notes = Vec::new();
    let mut statics = Vec::new();
    let mut read_types = Vec::new();
    for (sc, ns) in robots {
        let (t, s) = RobotTopics::new(node, sc, ns.clone(), opts.raw_images, opts.play_commands)?;
        t.pubs.description.publish(crate::rosmsg::RosString {
            data: crate::output::urdf_export::robot_description(sc),
        });
        let n = sc.commands.len();
        if n > 0 {
            let who = ns.name().map_or(String::new(), |l| format!("`{l}`: "));
            notes.push(if opts.play_commands {
                format!(
                    "{who}playing the file's {n} [[commands]] until the first ROS command \
                     (--play-commands)"
                )
            } else {
                format!(
                    "{who}the file's {n} [[commands]] are not played: ROS topics alone drive \
                     the robot (--play-commands plays them until the first ROS command)"
                )
            });
        }
        read_types.extend(t.subs.read_types());
        topics.push(t);
        skipped.extend(s);
        statics.extend(ns.tf(messages::tf_static(sc)).transforms);
    }
    pubs.tf_static.publish(TFMessage {
        transforms: statics,
    });
    let mut world = World {
        rep: Reporter {
            node,
            warnings: Warnings::default(),
            warn,
        },
        pubs,
        map_tf: opts.map_tf,
        read_types,
        foreign_said: Default::default(),
        next_foreign_check: 0.0,
    };
    for s in skipped {
        world
            .rep
            .say(LogLevel::Warn, 0.0, &format!("no command topic: {s}"));
    }
    for n in notes {
        world.rep.say(LogLevel::Info, 0.0, &n);
    }
    Ok((world, topics))
}

fn limits(opts: &RosOptions) -> SessionLimits {
    SessionLimits {
        max_time: opts.max_time,
        interrupt: opts.interrupt,
    }
}

/// Runs a session of `sc` (one robot; its names namespaced by `opts.namespace` if given) as
/// the ROS 2 node `/tracksim` until `opts.max_time` or the interrupt flag; `warn` receives
/// every warning also sent to `/rosout` (rate-limited).
pub fn run_ros(sc: &Scenario, opts: &RosOptions, warn: &mut dyn FnMut(&str)) -> Result<RosSession> {
    let mut node = DdsNode::start(opts.domain_id, &opts.network).map_err(dds_error)?;
    let ns = opts
        .namespace
        .as_deref()
        .map_or_else(Namespace::none, Namespace::robot);
    let mut runner = Runner::new(sc)?.without_commands().unbounded();
    if !opts.fast {
        runner = runner.paced(1.0);
    }
    let services = Services::new(&mut node).map_err(dds_error)?;
    let (world, mut robots) = start(&mut node, opts, &[(sc, ns)], warn)?;
    let mut topics = TopicSource {
        sc,
        robot: robots.remove(0),
        world,
        services: Some(services),
        paused: false,
        reset_asked: false,
        resets: 0,
        play_commands: opts.play_commands,
        interrupt: opts.interrupt,
    };
    topics.after_sample(&runner);
    topics.after_step(&runner);
    let run = crate::run::run_session(runner, &mut topics, limits(opts))?;
    let c = topics.robot.control.counts;
    Ok(RosSession {
        result: run.runner.finish(run.end),
        log: run.log,
        received: c.received,
        problems: c.problems,
        undecodable: c.undecodable,
        watchdog_stops: c.watchdog_stops,
        resets: topics.resets,
    })
}

/// A finished session of several robots.
pub struct RosTeamSession {
    /// The world's run, as `tracksim run` returns it.
    pub result: TeamResult,
    /// Each robot's name, the changes of its controls (as its `[[vehicles.commands]]`
    /// entries, at the simulated time each was applied) and what its commands came to.
    pub robots: Vec<(String, CommandLog, Counts)>,
}

/// Runs a session of `sc`, a scenario with several robots (`[[vehicles]]`), as the ROS 2 node
/// `/tracksim`: each robot's topics and frames in its namespace (`/<name>/cmd_vel`,
/// `<name>/base_link`), its own watchdog; one `/clock`, `/tf`, `/tf_static` and `/rosout`.
/// Ends as [`run_ros`].
pub fn run_ros_team(
    sc: &Scenario,
    opts: &RosOptions,
    warn: &mut dyn FnMut(&str),
) -> Result<RosTeamSession> {
    let mut node = DdsNode::start(opts.domain_id, &opts.network).map_err(dds_error)?;
    let mut runner = TeamRunner::new(sc)?.without_commands().unbounded();
    if !opts.fast {
        runner = runner.paced(1.0);
    }
    let names = runner.sim().robot_names();
    let robots: Vec<(&Scenario, Namespace)> = names
        .iter()
        .enumerate()
        .map(|(k, n)| (runner.robot_scenario(k), Namespace::robot(n)))
        .collect();
    let (world, robots) = start(&mut node, opts, &robots, warn)?;
    let mut topics = TeamTopicSource { robots, world };
    topics.after_sample(&mut runner);
    topics.after_step(&mut runner);
    let order = runner.sim().build_order().to_vec();
    let run = run_world_session(runner, &mut topics, limits(opts), &order)?;
    let logs = run.logs;
    Ok(RosTeamSession {
        result: run.world.finish(run.end),
        robots: names
            .into_iter()
            .zip(logs)
            .zip(topics.robots.iter().map(|r| r.control.counts))
            .map(|((n, l), c)| (n, l, c))
            .collect(),
    })
}

impl RosTeamSession {
    /// The session's duration, s.
    pub fn duration(&self) -> f64 {
        self.result
            .robots
            .first()
            .and_then(|r| r.1.samples.last())
            .map_or(0.0, |s| s.t)
    }

    /// Writes everything `tracksim run` writes for the world (a folder per robot,
    /// `team.json`, plots unless `plots` is false, the world's `run.mcap` if `mcap`, with colour
    /// cameras' raw images if `raw_images`) and
    /// `dir/commands.toml`, every robot's controls ([`crate::run::write_team_log`]: `tracksim
    /// run FILE --commands dir/commands.toml --duration T` replays the session); returns the
    /// paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
        (mcap, raw_images): (bool, bool),
    ) -> Result<Vec<PathBuf>> {
        let which = crate::output::Outputs {
            plots,
            mcap,
            raw_images,
            ..crate::output::Outputs::ALL
        };
        let header = LogHeader {
            what: RosSession::COMMANDS_HEADER,
            notes: &[],
            seed: None,
        };
        let logs: Vec<(&str, &CommandLog)> = self
            .robots
            .iter()
            .map(|(n, l, _)| (n.as_str(), l))
            .collect();
        crate::output::write_team_session(
            sc,
            &self.result,
            (&logs, header),
            scenario_file,
            dir,
            which,
        )
    }
}

impl RosSession {
    /// The session's duration, s (the last sample's time).
    pub fn duration(&self) -> f64 {
        self.result.samples.last().map_or(0.0, |s| s.t)
    }

    /// What `commands.toml` says the controls were.
    pub const COMMANDS_HEADER: &'static str = "The commands a `tracksim ros` session received";

    /// Writes everything `tracksim run` writes (plots unless `plots` is false, `run.mcap` if
    /// `mcap`, with colour cameras' raw images if `raw_images`) and `commands.toml` into `dir`; returns the paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
        (mcap, raw_images): (bool, bool),
    ) -> Result<Vec<PathBuf>> {
        let which = crate::output::Outputs {
            replay: true,
            plots,
            mcap,
            raw_images,
        };
        let header = LogHeader {
            what: Self::COMMANDS_HEADER,
            notes: &[],
            seed: None,
        };
        crate::output::write_session(
            sc,
            &self.result,
            (&self.log, header),
            scenario_file,
            dir,
            which,
        )
    }
}
