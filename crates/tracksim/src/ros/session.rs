//! A `tracksim ros` session: the scenario's [`Runner`] (the one run loop; paced to the wall
//! clock unless `fast`) with its controls from ROS topics, recorded as a run.
//!
//! At every sample boundary (`output_interval_s`, 10 ms by default) and only there, as in a
//! `drive` session: the received commands are sanitised and taken in, the watchdog is
//! applied, changed controls go to the physics (recorded as a `[[commands]]` entry at that
//! time, so `commands.toml` replays the session with `tracksim run`); then the world steps
//! to the next sample, which is published.

use super::commands::{Command, CommandState, WATCHDOG_TIMEOUT_S};
use super::dds::{DdsNode, Publishers, Subscriptions};
use super::network::NetworkRange;
use super::sanitize::{self, Problem, Warnings};
use super::sensors::SensorPublishers;
use super::topics;
use crate::error::{Error, Result};
use crate::model::{Scenario, VehicleModel};
use crate::output::ros_messages::{
    self as messages, encoder_model, encoder_odometry, track_states, true_odometry,
};
use crate::run::{CommandLog, ControlSource, LogHeader, RunResult, Runner, SessionLimits};
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
    /// The network the node is reachable on.
    pub network: NetworkRange,
    /// When set (by a Ctrl-C or SIGTERM handler), the session ends at the next sample as
    /// interrupted.
    pub interrupt: Option<&'static AtomicBool>,
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
    /// Times the watchdog stopped the robot.
    pub watchdog_stops: u64,
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
    }
}

/// Every command received since the last call, sanitised (problems into `problems`).
fn receive(subs: &Subscriptions, v: &VehicleModel, problems: &mut Vec<Problem>) -> Vec<Command> {
    let mut out = Vec::new();
    for tw in subs.cmd_vel.drain() {
        if let Some((f, w)) = sanitize::twist(topics::CMD_VEL, &tw, problems) {
            out.push(Command::Twist {
                forward_mps: f,
                yaw_rate_rad_s: w,
            });
        }
    }
    for (track, sub) in subs.track_speed.iter().enumerate() {
        for m in sub.iter().flat_map(|s| s.drain()) {
            let topic = &sub.as_ref().expect("drained").topic;
            if let Some(mps) = sanitize::belt_speed(topic, m.data, problems) {
                out.push(Command::BeltSpeed { track, mps });
            }
        }
    }
    for (flipper, sub) in subs.flipper_position.iter().enumerate() {
        for m in sub.iter().flat_map(|s| s.drain()) {
            let topic = &sub.as_ref().expect("drained").topic;
            if let Some(rad) = sanitize::flipper_angle(topic, m.data, problems) {
                out.push(Command::Flipper { flipper, rad });
            }
        }
    }
    for js in subs.flipper_positions.drain() {
        let targets = sanitize::joint_command(topics::FLIPPER_POSITIONS, v, &js, problems);
        out.extend(
            targets
                .into_iter()
                .map(|(flipper, rad)| Command::Flipper { flipper, rad }),
        );
    }
    out
}

/// What is published at every sample.
struct SamplePublisher {
    pubs: Publishers,
    encoders: crate::world::Odometry,
    joint_names: Vec<String>,
    track_names: Vec<String>,
    map_tf: bool,
}

impl SamplePublisher {
    fn publish(&self, sc: &Scenario, s: &Sample, prev: Option<&Sample>) {
        let odom = encoder_odometry(s, &self.encoders);
        self.pubs.clock.publish(messages::clock(s.t));
        self.pubs
            .tf
            .publish(messages::tf_of_sample(sc, s, &odom, self.map_tf));
        self.pubs.odom.publish(odom);
        self.pubs.truth.publish(true_odometry(s));
        self.pubs
            .joints
            .publish(messages::joint_state(&self.joint_names, s, prev));
        self.pubs.tracks.publish(track_states(s, &self.track_names));
    }
}

fn dds_error(e: String) -> Error {
    Error::Io {
        path: PathBuf::from("(ROS 2 / DDS)"),
        source: std::io::Error::other(e),
    }
}

/// What the session counts besides the run.
#[derive(Default)]
struct Counts {
    received: u64,
    problems: u64,
    watchdog_stops: u64,
}

/// ROS 2 topics as a session's control source: commands received, sanitised and taken in at
/// every sample boundary, the watchdog applied; the sensors published after every step and
/// the state at every sample.
struct TopicSource<'a, 'w> {
    sc: &'a Scenario,
    subs: Subscriptions,
    state: CommandState,
    rep: Reporter<'w>,
    counts: Counts,
    publisher: SamplePublisher,
    sensors: SensorPublishers,
}

impl TopicSource<'_, '_> {
    /// The controls in force as a command entry at `t` s: every belt speed by track name,
    /// the commanded flipper targets in degrees.
    fn command(&self, t: f64) -> CommandSpec {
        let v = &self.sc.vehicle;
        CommandSpec {
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
        }
    }
}

impl ControlSource for TopicSource<'_, '_> {
    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec> {
        let (sc, t) = (self.sc, runner.time());
        let mut problems = Vec::new();
        for c in receive(&self.subs, &sc.vehicle, &mut problems) {
            self.state.take(&sc.vehicle, &c, t);
            self.counts.received += 1;
        }
        self.counts.problems += problems.len() as u64;
        self.rep.problems(t, &problems);
        let stopped = self.state.watchdog(t);
        if !stopped.is_empty() {
            self.counts.watchdog_stops += 1;
            let names: Vec<&str> = stopped
                .iter()
                .map(|&i| sc.vehicle.tracks[i].name.as_str())
                .collect();
            self.rep.say(
                LogLevel::Info,
                t,
                &format!(
                    "watchdog: no speed command for {WATCHDOG_TIMEOUT_S} s; stopping track(s) {}",
                    names.join(", ")
                ),
            );
        }
        self.state.changed_controls(&sc.vehicle)?;
        Some(self.command(t))
    }

    fn after_step(&mut self, runner: &Runner) {
        let now = runner.time();
        let rep = &mut self.rep;
        self.sensors
            .publish(runner.sensors(), &mut |e| rep.say(LogLevel::Warn, now, e));
    }

    fn after_sample(&mut self, runner: &Runner) {
        let samples = runner.samples();
        if let Some(s) = samples.last() {
            self.publisher.publish(
                self.sc,
                s,
                samples.len().checked_sub(2).map(|k| &samples[k]),
            );
        }
    }
}

/// Runs a session of `sc` as the ROS 2 node `/tracksim` until `opts.max_time` or the
/// interrupt flag; `warn` receives every warning also sent to `/rosout` (rate-limited).
pub fn run_ros(sc: &Scenario, opts: &RosOptions, warn: &mut dyn FnMut(&str)) -> Result<RosSession> {
    let mut node = DdsNode::start(opts.domain_id, &opts.network).map_err(dds_error)?;
    let pubs = Publishers::new(&mut node).map_err(dds_error)?;
    let track_names: Vec<String> = sc.vehicle.tracks.iter().map(|t| t.name.clone()).collect();
    let flipper_names: Vec<String> = sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect();
    let (subs, skipped) =
        Subscriptions::new(&mut node, &track_names, &flipper_names).map_err(dds_error)?;
    let publisher = SamplePublisher {
        pubs,
        encoders: encoder_model(sc),
        joint_names: messages::joint_names(sc),
        track_names,
        map_tf: opts.map_tf,
    };
    let mut sensors = SensorPublishers::new(&mut node, sc).map_err(dds_error)?;
    let mut runner = Runner::new(sc)?.without_commands().unbounded();
    if !opts.fast {
        runner = runner.paced(1.0);
    }
    let mut rep = Reporter {
        node: &node,
        warnings: Warnings::default(),
        warn,
    };
    for s in skipped {
        rep.say(LogLevel::Warn, 0.0, &format!("no command topic: {s}"));
    }
    publisher.pubs.tf_static.publish(messages::tf_static(sc));
    if let Some(s) = runner.samples().last() {
        publisher.publish(sc, s, None);
    }
    sensors.publish(runner.sensors(), &mut |e| rep.say(LogLevel::Warn, 0.0, e));
    let mut topics = TopicSource {
        sc,
        subs,
        state: CommandState::new(&sc.vehicle),
        rep,
        counts: Counts::default(),
        publisher,
        sensors,
    };
    let limits = SessionLimits {
        max_time: opts.max_time,
        interrupt: opts.interrupt,
    };
    let run = crate::run::run_session(runner, &mut topics, limits)?;
    Ok(RosSession {
        result: run.runner.finish(run.end),
        log: run.log,
        received: topics.counts.received,
        problems: topics.counts.problems,
        watchdog_stops: topics.counts.watchdog_stops,
    })
}

impl RosSession {
    /// The session's duration, s (the last sample's time).
    pub fn duration(&self) -> f64 {
        self.result.samples.last().map_or(0.0, |s| s.t)
    }

    /// What `commands.toml` says the controls were.
    pub const COMMANDS_HEADER: &'static str = "The commands a `tracksim ros` session received";

    /// Writes everything `tracksim run` writes (plots unless `plots` is false, `run.mcap` if
    /// `mcap`) and `commands.toml` into `dir`; returns the paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
        mcap: bool,
    ) -> Result<Vec<PathBuf>> {
        let which = crate::output::Outputs {
            replay: true,
            plots,
            mcap,
        };
        let header = LogHeader {
            what: Self::COMMANDS_HEADER,
            notes: &[],
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
