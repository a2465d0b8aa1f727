//! A live session: the scenario's [`Runner`] paced to the wall clock with the operator's
//! controls from the [`Hub`], recorded as a run.
//!
//! Determinism: a control from the page is applied only at a sample boundary (every
//! `output_interval_s`), before the next step, exactly as a scenario's `[[commands]]` entry
//! with that `t_s` is (`run::Timeline`), and through the same conversion (skid-steer twist,
//! degrees to radians). The session's `commands.toml` therefore replays it:
//! `tracksim run FILE --commands DIR/commands.toml --duration T` writes the same
//! `trajectory.csv`.

use super::hub::{DriveControl, Hub};
use super::hud_feed::HudFeed;
use super::instructor::Desk;
use super::latency::Delayed;
use super::seat::DriverStatus;
use super::sensor_feed::SensorFeed;
use crate::error::Result;
use crate::model::Scenario;
use crate::run::events::RunEvent;
use crate::run::{
    AttemptRecord, CommandLog, ControlSource, End, LogHeader, Outcome, RunResult, RunView, Runner,
    SessionLimits, SpillLog, attempt_folder,
};
use crate::spec::CommandSpec;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Shortest wall time between two published states, s (at most 60 states per second).
pub const PUBLISH_INTERVAL_S: f64 = 1.0 / 60.0;

/// Course events a live state carries (the latest), at most.
pub const LIVE_COURSE_EVENTS: usize = 10;

/// Options of a session.
#[derive(Clone, Copy, Debug)]
pub struct DriveOptions {
    /// Simulated seconds per wall-clock second (1: real time; 0.5 slower, 2 faster).
    pub speed: f64,
    /// End the session at this simulated time, s (None: when the operator stops).
    pub max_time: Option<f64>,
    /// Start simulating only once a page has connected (the clock starts then).
    pub wait_for_page: bool,
    /// When set (by a Ctrl-C or SIGTERM handler), the session ends at the next sample as
    /// interrupted (not as ended by the operator).
    pub interrupt: Option<&'static std::sync::atomic::AtomicBool>,
}

impl Default for DriveOptions {
    fn default() -> Self {
        DriveOptions {
            speed: 1.0,
            max_time: None,
            wait_for_page: false,
            interrupt: None,
        }
    }
}

/// An attempt of a session that a reset ended (issue 43): kept as a run of its own.
pub struct Attempt {
    /// Its run (`summary.json` `events` with the instructor's actions in it).
    pub result: RunResult,
    /// Its controls, as `[[commands]]` entries.
    pub log: CommandLog,
    /// The controls in force at each of its samples (spilled to disk with them).
    pub controls: SpillLog<DriveControl>,
}

/// A finished session: the run, and the controls the operator gave.
pub struct Session {
    /// The run (since the last reset: the last attempt), as `tracksim run` returns it; its
    /// summary lists every attempt (`attempts`).
    pub result: RunResult,
    /// The attempts resets ended, in order (written in `attempts/N/`).
    pub attempts: Vec<Attempt>,
    /// Each control change, as a scenario's `[[commands]]` entry at the simulated time it
    /// was applied.
    pub log: CommandLog,
    /// The controls in force at each sample of `result.samples` (spilled to disk with them).
    pub controls: SpillLog<DriveControl>,
    /// Flipper names, by index.
    pub flipper_names: Vec<String>,
    /// Initial flipper angles, degrees (what an uncommanded flipper holds).
    pub flipper_initial_deg: Vec<f64>,
}

/// A page's control as a scenario's command entry at `t` s (skid-steer twist, flipper
/// targets in degrees by name): applied and recorded as such.
pub(super) fn to_command(sc: &Scenario, t: f64, c: &DriveControl) -> CommandSpec {
    CommandSpec {
        t_s: t,
        forward_mps: Some(c.forward_mps),
        yaw_rate_rad_s: Some(c.yaw_rate_rad_s),
        flipper_angle_deg: sc
            .vehicle
            .flippers
            .iter()
            .zip(&c.flipper_angle_deg)
            .filter_map(|(f, a)| a.map(|a| (f.name.clone(), a)))
            .collect(),
        ..CommandSpec::default()
    }
}

/// Mean forward speed of the body over the last 0.1 s of samples (along its heading), m/s.
fn mean_forward_speed(samples: &crate::run::SampleLog, interval: f64) -> f64 {
    // The last 0.1 s are always in memory (`SampleLog::recent`).
    let samples = samples.recent();
    let k = ((0.1 / interval).round() as usize).max(1);
    let n = samples.len();
    if n <= k {
        return 0.0;
    }
    let (a, b) = (&samples[n - 1 - k].pose, &samples[n - 1].pose);
    let dt = samples[n - 1].t - samples[n - 1 - k].t;
    let heading = (
        b.yaw.cos() * b.pitch.cos(),
        b.yaw.sin() * b.pitch.cos(),
        -b.pitch.sin(),
    );
    ((b.x - a.x) * heading.0 + (b.y - a.y) * heading.1 + (b.z - a.z) * heading.2) / dt
}

/// What successive states of a session carry besides the pose: sensor readings new since the
/// last state, and the warnings' data.
#[derive(Default)]
pub(super) struct Feeds {
    pub(super) sensors: SensorFeed,
    pub(super) hud: HudFeed,
    /// Sequence number of the next rut cell to send ([`crate::world::Simulation::ruts_since`]).
    pub(super) rut_seq: u64,
}

/// Most rut cells handed to the hub's log per state (the rest follow with the next states).
const MAX_RUTS_PER_STATE: usize = 4096;

impl Feeds {
    /// Hands the soil cells deepened since the last call to the hub's rut log, as
    /// `[x, y, surface_z, depth, cell]` rows (m; at most [`MAX_RUTS_PER_STATE`] per call, the
    /// rest next time).
    fn push_ruts(&mut self, runner: &Runner, hub: &Hub) {
        let (cells, next) = runner.sim().ruts_since(self.rut_seq, MAX_RUTS_PER_STATE);
        self.rut_seq = next;
        let rows: Vec<[f64; 5]> = cells
            .iter()
            .map(|c| [c.x_m, c.y_m, c.surface_z_m, c.depth_m, c.cell_m])
            .collect();
        hub.append_ruts(&rows);
    }
}

/// The clock figures of a live state: the requested speed (simulated seconds per wall
/// second), wall seconds since the start and wall seconds spent stepping.
#[derive(Clone, Copy, Debug)]
pub(super) struct LiveClock {
    pub(super) speed: f64,
    pub(super) wall_s: f64,
    pub(super) stepping_s: f64,
}

/// The state of robot `run` streamed to the page (JSON): pose, belts, flippers, the real-time
/// factors (paced and of stepping alone), the body's mean forward speed over the last 0.1 s
/// (m/s), the controls in force, the outcome (`ended`: the session's; else the robot's, once
/// decided), `sensors`: the lidar and depth camera readings new since the last state
/// ([`SensorFeed`]: world-frame lidar points, decimated; depth images in millimetres), the
/// warnings' data ([`HudFeed::fields`]: `slip`, `stall`, `stall_since_s`, `tilt_limit_deg`,
/// `ahead`), `course` (the live score of a `[course]` scenario, [`crate::run::CourseScore`],
/// with its latest [`LIVE_COURSE_EVENTS`] events; null without one), `driver` (`connected`,
/// `grace_left_s`, `reconnects`) and `session_ended` (true in the last state: the page should
/// not reconnect).
pub(super) fn robot_state(
    run: &RunView,
    control: &DriveControl,
    (clock, driver): (LiveClock, DriverStatus),
    ended: Option<&(Outcome, f64)>,
    feeds: &mut Feeds,
) -> serde_json::Value {
    let sim = run.sim;
    let p = sim.body_pose();
    let n = sim.track_names().len();
    let nf = sim.flipper_names().len();
    let outcome = ended.or(run.decided);
    let mut state = serde_json::json!({
        "type": "state",
        "t": sim.time(),
        "pose": [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
        "forward_mps": mean_forward_speed(run.samples, run.scenario.output_interval),
        "belt_position": (0..n).map(|i| sim.belt_position(i)).collect::<Vec<_>>(),
        "belt_speed": (0..n).map(|i| sim.commanded_belt_speed(i)).collect::<Vec<_>>(),
        "flipper": (0..nf).map(|i| sim.flipper_angle(i)).collect::<Vec<_>>(),
        "rtf_paced": sim.time() / clock.wall_s.max(1e-9),
        "rtf_compute": sim.time() / clock.stepping_s.max(1e-9),
        "speed": clock.speed,
        "outcome": outcome.map(|(o, t)| serde_json::json!({
            "name": o.name(), "reason": o.reason(), "t": t
        })),
        "control": {
            "forward_mps": control.forward_mps,
            "yaw_rate_rad_s": control.yaw_rate_rad_s,
            "flipper_angle_deg": control.flipper_angle_deg,
        },
        "sensors": feeds.sensors.new_readings(run),
        "session_ended": ended.is_some(),
        "course": run.course.clone().map(|mut c| {
            // Only the latest events: the whole list grows with the session (summary.json
            // has it all), and the state goes out up to 60 times a second.
            let n = c.events.len().saturating_sub(LIVE_COURSE_EVENTS);
            c.events.drain(..n);
            c
        }),
        "driver": {
            "connected": driver.connected,
            "grace_left_s": driver.grace_left_s,
            "reconnects": driver.reconnects,
        },
    });
    if let serde_json::Value::Object(m) = &mut state {
        m.extend(feeds.hud.fields(run));
    }
    state
}

/// The state of a one-robot session's `runner` ([`robot_state`]) with, in a drive session,
/// the instructor's seat's fields ([`Desk::fields`]) and the attempt's number; its new rut
/// cells handed to the hub first. A watch-only hub's state has `driver` null (nobody drives).
pub(super) fn state_json(
    runner: &Runner,
    control: &DriveControl,
    (speed, hub, desk): (f64, &Hub, Option<(&Desk, usize)>),
    ended: Option<&(Outcome, f64)>,
    feeds: &mut Feeds,
) -> String {
    state_value(runner, control, (speed, hub, desk), ended, feeds).to_string()
}

/// [`state_json`] as a JSON value.
pub(super) fn state_value(
    runner: &Runner,
    control: &DriveControl,
    (speed, hub, desk): (f64, &Hub, Option<(&Desk, usize)>),
    ended: Option<&(Outcome, f64)>,
    feeds: &mut Feeds,
) -> serde_json::Value {
    let driver = hub.driver_status();
    feeds.push_ruts(runner, hub);
    let clock = LiveClock {
        speed,
        wall_s: runner.wall_elapsed(),
        stepping_s: runner.stepping(),
    };
    let mut state = robot_state(&runner.view(), control, (clock, driver), ended, feeds);
    if hub.is_watch_only() {
        // Nobody drives a watch-only session: no driver to be connected or disconnected.
        state["driver"] = serde_json::Value::Null;
    }
    if let (serde_json::Value::Object(m), Some((desk, attempt))) = (&mut state, desk) {
        m.extend(desk.fields(0, runner.sim()));
        m.insert("attempt".into(), serde_json::json!(attempt));
    }
    state
}

/// Robot `k`'s new controls from its seat, if they changed from `current`: its driver's
/// newest; without a driver (the page dropped, none yet, or it stopped) the robot stops, as a
/// dead-man would, the flippers holding their targets.
pub(super) fn next_control(hub: &Hub, k: usize, current: &DriveControl) -> Option<DriveControl> {
    let wanted = if hub.driver_status_of(k).connected {
        hub.take_control_of(k)
    } else {
        Some(DriveControl {
            forward_mps: 0.0,
            yaw_rate_rad_s: 0.0,
            ..current.clone()
        })
    };
    wanted.filter(|c| c != current)
}

/// What the page source keeps of an attempt a reset ended: its controls and events, and who
/// reset it.
struct Kept {
    controls: SpillLog<DriveControl>,
    events: Vec<RunEvent>,
    by: &'static str,
}

/// The page (and the instructor's) as a session's control source: its controls, reset and
/// stop, the instructor's pause and faults, and the states it is sent.
struct PageSource<'a> {
    hub: &'a Hub,
    speed: f64,
    idle: DriveControl,
    /// The driver's latest control (what it wants).
    wanted: DriveControl,
    /// The controls in force (applied, after any latency).
    current: DriveControl,
    /// The driver's controls on their way (an injected latency).
    delayed: Delayed,
    /// The controls in force at each sample.
    controls: SpillLog<DriveControl>,
    last_publish: Option<Instant>,
    feeds: Feeds,
    desk: Desk,
    /// Simulated time at the last sample boundary, s.
    t: f64,
    /// The attempts resets ended.
    kept: Vec<Kept>,
    names: Vec<String>,
}

impl PageSource<'_> {
    fn publish(&mut self, runner: &Runner, ended: Option<&(Outcome, f64)>) {
        self.last_publish = Some(Instant::now());
        let attempt = self.kept.len() + 1;
        self.hub.publish(state_json(
            runner,
            &self.current,
            (self.speed, self.hub, Some((&self.desk, attempt))),
            ended,
            &mut self.feeds,
        ));
    }

    fn due_publish(&self) -> bool {
        self.last_publish
            .is_none_or(|l| l.elapsed().as_secs_f64() >= PUBLISH_INTERVAL_S)
    }
}

impl ControlSource for PageSource<'_> {
    fn end(&mut self, _runner: &Runner) -> Option<End> {
        if self.hub.stop_requested() || self.desk.ended() {
            Some(End::ByOperator)
        } else if self.hub.abandoned() {
            Some(End::Abandoned(self.hub.grace_s()))
        } else {
            None
        }
    }

    fn paused(&mut self, runner: &Runner) -> bool {
        self.t = runner.time();
        self.desk.take(self.hub.take_actions(), self.t, &self.names);
        let paused = self.desk.paused();
        if paused && self.due_publish() {
            self.publish(runner, None);
        }
        paused
    }

    fn reset(&mut self) -> bool {
        let by = if self.hub.take_reset() {
            "the driver"
        } else if self.desk.take_reset() {
            "the instructor"
        } else {
            return false;
        };
        if by == "the driver" {
            self.desk.event(
                self.t,
                "reset",
                "the driver reset: a new attempt begins".into(),
            );
        }
        self.kept.push(Kept {
            controls: std::mem::replace(
                &mut self.controls,
                SpillLog::from(vec![self.idle.clone()]),
            ),
            events: self.desk.next_attempt(),
            by,
        });
        self.current = self.idle.clone();
        self.wanted = self.idle.clone();
        self.delayed.clear();
        self.feeds.hud.reset();
        self.feeds.rut_seq = 0;
        self.hub.clear_ruts();
        true
    }

    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec> {
        let t = runner.time();
        if let Some(c) = next_control(self.hub, 0, &self.wanted) {
            self.wanted = c.clone();
            self.delayed.push(t + self.desk.latency_s(0), c);
        }
        let applied = self.delayed.due(t).filter(|c| *c != self.current);
        let fault = self.desk.take_fault(0);
        if applied.is_none() && fault.is_none() {
            return None;
        }
        if let Some(c) = applied {
            self.current = c;
        }
        let mut cmd = to_command(runner.scenario(), t, &self.current);
        cmd.fault = fault;
        Some(cmd)
    }

    fn after_step(&mut self, runner: &Runner) {
        if self.due_publish() {
            self.publish(runner, None);
        }
    }

    fn after_sample(&mut self, _runner: &Runner) {
        self.controls.push(self.current.clone());
    }
}

/// The session's check of an instructor's fault for the robot of scenario `sc`: compiled as a
/// `[[commands]]` entry's `fault` table, an unpowered track refused where the method does not
/// model it.
pub(super) fn fault_check(sc: &Scenario) -> super::hub::FaultCheck {
    let vehicle = sc.vehicle.clone();
    let method = sc.method;
    Box::new(move |_k, f| {
        let c = CommandSpec {
            fault: Some(f.clone()),
            ..CommandSpec::default()
        };
        let compiled = crate::model::compile_commands(std::slice::from_ref(&c), &vehicle).map_err(
            |issues| {
                issues
                    .iter()
                    .map(|i| i.to_string().replacen("commands[0].", "", 1))
                    .collect::<Vec<_>>()
                    .join("; ")
            },
        )?;
        if compiled.iter().any(|c| c.controls.faults.unpowers())
            && !crate::model::models_unpowered(method)
        {
            return Err(format!(
                "an unpowered track is not modelled by method {method} (its belt is a speed \
                 imposed on its contacts, with no drive to let go); use \"stopped\""
            ));
        }
        Ok(())
    })
}

/// Runs a session until the hub is asked to stop (or `opts.max_time`): a [`Runner`] paced to
/// the wall clock at `opts.speed`, without the file's commands, controls from the hub applied
/// at sample boundaries (the session loop, [`crate::run::session`]), the state published at
/// most every [`PUBLISH_INTERVAL_S`]. Never waits for a client. A session the operator ends
/// has the outcome "ended_by_operator" (with the scenario's outcome if it was decided); one
/// that reaches `opts.max_time` the scenario's.
pub fn run_session(sc: &Scenario, hub: &Hub, opts: DriveOptions) -> Result<Session> {
    let idle = DriveControl {
        flipper_angle_deg: vec![None; sc.vehicle.flippers.len()],
        ..DriveControl::default()
    };
    hub.set_flipper_count(0, sc.vehicle.flippers.len());
    hub.set_fault_check(fault_check(sc));
    if opts.wait_for_page {
        hub.wait_for_page();
    }
    let runner = Runner::new(sc)?
        .without_commands()
        .unbounded()
        .paced(opts.speed);
    let mut page = PageSource {
        hub,
        speed: opts.speed,
        wanted: idle.clone(),
        current: idle.clone(),
        delayed: Delayed::default(),
        controls: SpillLog::from(vec![idle.clone()]),
        idle,
        last_publish: None,
        feeds: Feeds::default(),
        desk: Desk::new(1),
        t: 0.0,
        kept: Vec::new(),
        names: hub.robots().to_vec(),
    };
    let limits = SessionLimits {
        max_time: opts.max_time,
        interrupt: opts.interrupt,
    };
    let run = crate::run::run_session(runner, &mut page, limits)?;
    page.publish(&run.runner, Some(&run.runner.outcome(&run.end)));
    let mut result = run.runner.finish(run.end);
    with_events(&mut result, page.desk.take_events());
    let mut attempts = Vec::new();
    for ((mut r, log), kept) in run.attempts.into_iter().zip(page.kept) {
        with_events(&mut r, kept.events);
        let n = attempts.len() + 1;
        let record = AttemptRecord::of(n, attempt_folder(n), kept.by, &r);
        result.summary.attempts.push(record);
        attempts.push(Attempt {
            result: r,
            log,
            controls: kept.controls,
        });
    }
    if !attempts.is_empty() {
        let n = attempts.len() + 1;
        let record = AttemptRecord::of(n, ".".into(), "the session's end", &result);
        result.summary.attempts.push(record);
        for a in &mut attempts {
            a.result.summary.attempts = result.summary.attempts.clone();
        }
    }
    Ok(Session {
        result,
        attempts,
        log: run.log,
        controls: page.controls,
        flipper_names: sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect(),
        flipper_initial_deg: sc
            .vehicle
            .flippers
            .iter()
            .map(|f| f.initial_angle.to_degrees())
            .collect(),
    })
}

/// Adds the instructor's actions (and the driver's resets) `events` to a run's review events,
/// in time order.
fn with_events(r: &mut RunResult, events: Vec<RunEvent>) {
    r.summary.events.extend(events);
    r.summary.events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
}

impl Session {
    /// The session's duration, s (the last sample's time).
    pub fn duration(&self) -> f64 {
        self.result.samples.last().map_or(0.0, |s| s.t)
    }

    /// What `commands.toml` says the controls were.
    pub const COMMANDS_HEADER: &'static str =
        "The operator's controls of a `tracksim drive` session";

    /// `controls.csv`: the controls in force at each sample (`t_s`, m/s, rad/s, flipper
    /// targets in degrees).
    pub fn controls_csv(&self) -> String {
        controls_csv(
            &self.result.samples,
            &self.controls,
            &self.flipper_names,
            &self.flipper_initial_deg,
        )
    }

    /// Writes everything `tracksim run` writes (summary, trajectory, replay data, plots unless
    /// `plots` is false) and `commands.toml`, `controls.csv` into `dir`; returns the paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
    ) -> Result<Vec<PathBuf>> {
        let which = crate::output::Outputs {
            plots,
            ..crate::output::Outputs::ALL
        };
        let header = LogHeader {
            what: Self::COMMANDS_HEADER,
            notes: &[],
            seed: None,
        };
        let mut written = crate::output::write_session(
            sc,
            &self.result,
            (&self.log, header),
            scenario_file,
            dir,
            which,
        )?;
        let p = dir.join("controls.csv");
        crate::files::write_atomic(&p, self.controls_csv().as_bytes())?;
        written.push(p);
        for (i, a) in self.attempts.iter().enumerate() {
            let sub = dir.join(attempt_folder(i + 1));
            written.extend(crate::output::write_session(
                sc,
                &a.result,
                (&a.log, header),
                scenario_file,
                &sub,
                which,
            )?);
            let text = controls_csv(
                &a.result.samples,
                &a.controls,
                &self.flipper_names,
                &self.flipper_initial_deg,
            );
            let p = sub.join("controls.csv");
            crate::files::write_atomic(&p, text.as_bytes())?;
            written.push(p);
        }
        Ok(written)
    }

    /// Records the trainee's name in the summary of the session and of every attempt.
    pub fn set_trainee(&mut self, trainee: Option<String>) {
        for a in &mut self.attempts {
            a.result.summary.trainee.clone_from(&trainee);
        }
        self.result.summary.trainee = trainee;
    }
}

/// `controls.csv`: the controls in force at each of `samples` (`t_s`, m/s, rad/s, flipper
/// targets in degrees: an uncommanded flipper's is its last target, from `initial_deg`).
pub(super) fn controls_csv(
    samples: &crate::run::SampleLog,
    controls: &SpillLog<DriveControl>,
    flipper_names: &[String],
    initial_deg: &[f64],
) -> String {
    let mut text = String::from("t_s,forward_mps,yaw_rate_rad_s");
    for n in flipper_names {
        text.push_str(&format!(",flipper_{n}_target_deg"));
    }
    text.push('\n');
    let mut held = initial_deg.to_vec();
    for (s, c) in samples.iter().zip(controls.iter()) {
        text.push_str(&format!(
            "{:.6},{:.6},{:.6}",
            s.t, c.forward_mps, c.yaw_rate_rad_s
        ));
        for (h, a) in held.iter_mut().zip(&c.flipper_angle_deg) {
            if let Some(a) = a {
                *h = *a;
            }
            text.push_str(&format!(",{h:.6}"));
        }
        text.push('\n');
    }
    text
}
