//! A live session of several robots (`[[vehicles]]`): a seat per robot ([`super::seat`]), so
//! several trainees drive at once, each from their own page, and any page can watch any robot.
//! The world ([`TeamRunner`]) is paced to the wall clock; each seat's controls are taken at
//! sample boundaries, in the world's build order, through the session loop
//! ([`crate::run::run_world_session`]) and recorded per robot; the session's `commands.toml`
//! (`[[vehicles]]`, each robot's `[[vehicles.commands]]`) replays it with
//! `tracksim run FILE --commands DIR/commands.toml --duration T`.
//!
//! Each robot's state (`drive::robot_state`) goes to the pages that drive or follow
//! it, with `robot` (its name), `others` (every other robot's name, pose, flipper angles and
//! belt positions, to draw them) and `team` (the world's rule and outcome, and on a course the
//! standings: [`crate::run::Standings`]). A driver's stop
//! closes their seat (the robot stops); the session ends when every seat that was taken has
//! closed, on Ctrl-C/SIGTERM, at `--duration`, or when every page has left past its grace.

use super::drive::{
    DriveOptions, Feeds, LiveClock, PUBLISH_INTERVAL_S, controls_csv, next_control, robot_state,
    to_command,
};
use super::hub::{DriveControl, Hub};
use super::instructor::Desk;
use super::latency::Delayed;
use crate::error::Result;
use crate::model::Scenario;
use crate::run::{
    CommandLog, End, LogHeader, Outcome, SessionLimits, TeamResult, TeamRunner, WorldSource,
};
use crate::spec::CommandSpec;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A finished session of several robots.
pub struct TeamSession {
    /// The world's run (each robot's, and the world's outcome).
    pub result: TeamResult,
    /// Each robot's control changes (by robot index), as `[[commands]]` entries.
    pub logs: Vec<CommandLog>,
    /// Each robot's controls in force at each of its samples (of its last attempt).
    pub controls: Vec<crate::run::SpillLog<DriveControl>>,
    /// Each robot's controls of each attempt a reset of it (the instructor's or its driver's)
    /// ended, in order.
    pub kept_controls: Vec<Vec<crate::run::SpillLog<DriveControl>>>,
}

/// One seat's side of the session: the driver's latest control, those on their way (an
/// instructor's added latency), the controls in force and recorded, the state feeds.
struct SeatState {
    /// The driver's latest control (what it wants).
    wanted: DriveControl,
    /// The driver's controls on their way to the robot (`fault.latency_s`).
    delayed: Delayed,
    /// The controls in force (applied, after any latency).
    current: DriveControl,
    /// No control: belts at 0, flippers held (what a reset leaves in force).
    idle: DriveControl,
    controls: crate::run::SpillLog<DriveControl>,
    /// The controls of each attempt a reset of this robot ended.
    kept: Vec<crate::run::SpillLog<DriveControl>>,
    feeds: Feeds,
}

/// The seats as the session's control source.
struct Seats<'a> {
    hub: &'a Hub,
    speed: f64,
    seats: Vec<SeatState>,
    last_publish: Option<Instant>,
    /// The instructor's seat: pause, end, faults, each robot's latency and reset.
    desk: Desk,
    names: Vec<String>,
}

impl WorldSource<TeamRunner> for Seats<'_> {
    fn end(&mut self, _world: &TeamRunner) -> Option<End> {
        if self.hub.stop_requested() || self.hub.all_stopped() || self.desk.ended() {
            Some(End::ByOperator)
        } else if self.hub.abandoned() {
            Some(End::Abandoned(self.hub.grace_s()))
        } else {
            None
        }
    }

    fn paused(&mut self, world: &mut TeamRunner) -> bool {
        let t = world.sim().time();
        self.desk.take(self.hub.take_actions(), t, &self.names);
        // A driver's reset of their own robot (the others go on), as the instructor's.
        for k in 0..self.names.len() {
            if self.hub.take_reset_of(k) {
                self.desk.driver_reset(k, t, &self.names);
            }
        }
        let paused = self.desk.paused();
        if paused
            && self
                .last_publish
                .is_none_or(|l| l.elapsed().as_secs_f64() >= PUBLISH_INTERVAL_S)
        {
            self.last_publish = Some(Instant::now());
            self.publish(world, None);
        }
        paused
    }

    fn controls(&mut self, world: &TeamRunner, k: usize) -> Option<CommandSpec> {
        let t = world.sim().time();
        let seat = &mut self.seats[k];
        // A reset of this robot by the instructor or its driver (the others go on): a
        // `reset = true` entry, its controls zeroed, its faults, latency and queued controls
        // gone; its attempt so far is kept (`TeamRunner::reset_robot`), with the controls it
        // had.
        let reset = self.desk.take_reset_of(k);
        if reset {
            let fresh = crate::run::SpillLog::from(vec![seat.idle.clone()]);
            seat.kept.push(std::mem::replace(&mut seat.controls, fresh));
            seat.wanted = seat.idle.clone();
            seat.current = seat.idle.clone();
            seat.delayed = Delayed::default();
        }
        if let Some(c) = next_control(self.hub, k, &seat.wanted) {
            seat.wanted = c.clone();
            seat.delayed.push(t + self.desk.latency_s(k), c);
        }
        let applied = seat.delayed.due(t).filter(|c| *c != seat.current);
        let fault = self.desk.take_fault(k);
        if applied.is_none() && fault.is_none() && !reset {
            return None;
        }
        if let Some(c) = applied {
            seat.current = c;
        }
        let mut cmd = to_command(world.robot_scenario(k), t, &seat.current);
        cmd.fault = fault;
        cmd.reset = reset.then_some(true);
        Some(cmd)
    }

    fn after_step(&mut self, world: &mut TeamRunner) {
        if self
            .last_publish
            .is_none_or(|l| l.elapsed().as_secs_f64() >= PUBLISH_INTERVAL_S)
        {
            self.last_publish = Some(Instant::now());
            self.publish(world, None);
        }
    }

    fn after_sample(&mut self, _world: &mut TeamRunner) {
        for s in &mut self.seats {
            s.controls.push(s.current.clone());
        }
    }
}

impl Seats<'_> {
    /// Publishes every robot's state (`ended`: the session's end, in its last states).
    fn publish(&mut self, world: &mut TeamRunner, ended: Option<&End>) {
        let clock = LiveClock {
            speed: self.speed,
            wall_s: world.wall_elapsed(),
            stepping_s: world.stepping(),
        };
        let names = world.sim().robot_names();
        let n = names.len();
        let bodies: Vec<Value> = (0..n)
            .map(|k| {
                let v = world.view(k);
                let p = v.sim.body_pose();
                json!({
                    "name": names[k],
                    "pose": [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
                    "flipper": (0..v.sim.flipper_names().len()).map(|i| v.sim.flipper_angle(i)).collect::<Vec<_>>(),
                    "belt_position": (0..v.sim.track_names().len()).map(|i| v.sim.belt_position(i)).collect::<Vec<_>>(),
                })
            })
            .collect();
        let team = json!({
            "rule": world.sim().world_scenario().team.as_ref().map(|t| t.rule.name()),
            "outcome": world.decided().map(|(o, t)| json!({
                "name": o.name(), "reason": o.reason(), "t": t
            })),
            "standings": world.standings(),
        });
        for (k, seat) in self.seats.iter_mut().enumerate() {
            let outcome = ended.map(|e| world.robot_outcome(k, e));
            let driver = self.hub.driver_status_of(k);
            let v = world.view(k);
            let mut state = robot_state(
                &v,
                &seat.current,
                (clock, driver),
                outcome.as_ref(),
                &mut seat.feeds,
            );
            if let Value::Object(m) = &mut state {
                m.extend(self.desk.fields(k, v.sim));
                m.insert("robot".into(), json!(names[k]));
                // Why the world stopped, when it did (issue 59): the pages say so.
                if let Some(why) = ended.and_then(End::stopped) {
                    m.insert("stopped".into(), json!(why));
                }
                let others: Vec<&Value> = (0..n).filter(|&j| j != k).map(|j| &bodies[j]).collect();
                m.insert("others".into(), json!(others));
                m.insert("team".into(), team.clone());
            }
            self.hub.publish_robot(k, state.to_string());
        }
    }
}

/// Runs a session of the robots of `sc` (a scenario with [`Scenario::team`]) until it ends
/// (see the module docs): a [`TeamRunner`] paced to the wall clock at `opts.speed`, without
/// the robots' commands, each seat's controls applied at sample boundaries.
pub fn run_team_session(sc: &Scenario, hub: &Hub, opts: DriveOptions) -> Result<TeamSession> {
    if opts.wait_for_page {
        hub.wait_for_page();
    }
    let world = TeamRunner::new(sc)?
        .without_commands()
        .unbounded()
        .paced(opts.speed);
    let order = world.sim().build_order().to_vec();
    for k in 0..world.sim().robot_count() {
        hub.set_flipper_count(k, world.robot_scenario(k).vehicle.flippers.len());
    }
    let seats = (0..world.sim().robot_count())
        .map(|k| {
            let idle = DriveControl {
                flipper_angle_deg: vec![None; world.robot_scenario(k).vehicle.flippers.len()],
                ..DriveControl::default()
            };
            SeatState {
                controls: crate::run::SpillLog::from(vec![idle.clone()]),
                wanted: idle.clone(),
                delayed: Delayed::default(),
                current: idle.clone(),
                idle,
                kept: Vec::new(),
                feeds: Feeds::default(),
            }
        })
        .collect();
    let checks: Vec<_> = (0..world.sim().robot_count())
        .map(|k| super::drive::fault_check(world.robot_scenario(k)))
        .collect();
    hub.set_fault_check(Box::new(move |k, f| match checks.get(k) {
        Some(check) => check(k, f),
        None => Err(format!("no robot {k}")),
    }));
    let mut source = Seats {
        hub,
        speed: opts.speed,
        seats,
        last_publish: None,
        desk: Desk::new(hub.robots().len()),
        names: hub.robots().to_vec(),
    };
    let limits = SessionLimits {
        max_time: opts.max_time,
        interrupt: opts.interrupt,
    };
    let run = crate::run::run_world_session(world, &mut source, limits, &order)?;
    let mut world = run.world;
    source.publish(&mut world, Some(&run.end));
    let mut result = world.finish(run.end);
    // The instructor's actions: events of every robot's run; a robot reset has them by
    // attempt (an attempt from `start` to `end` s has those after its start up to its end:
    // the reset that ended it is its last).
    let events = source.desk.take_events();
    let span = |r: &crate::run::RunResult| {
        let t = |s: Option<&crate::world::Sample>| s.map_or(0.0, |s| s.t);
        (t(r.samples.first()), t(r.samples.last()))
    };
    for ((_, last), kept) in result.robots.iter_mut().zip(&mut result.attempts) {
        let mut runs: Vec<&mut crate::run::RunResult> = kept.iter_mut().collect();
        runs.push(last);
        let n = runs.len();
        for (i, r) in runs.into_iter().enumerate() {
            let (start, end) = span(r);
            let mine = events
                .iter()
                .filter(|e| (i == 0 || e.t_s > start) && (i + 1 == n || e.t_s <= end));
            r.summary.events.extend(mine.cloned());
            r.summary.events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        }
    }
    let (controls, kept_controls) = source
        .seats
        .into_iter()
        .map(|s| (s.controls, s.kept))
        .unzip();
    Ok(TeamSession {
        result,
        logs: run.logs,
        controls,
        kept_controls,
    })
}

impl TeamSession {
    /// Robot `name`'s trainee (`--trainee ROBOT=NAME`) in every attempt of it: the last and
    /// each a reset ended, so that every attempt counts for its trainee (issue 59).
    pub fn set_trainee(&mut self, name: &str, trainee: Option<String>) {
        let r = &mut self.result;
        for (k, (n, run)) in r.robots.iter_mut().enumerate() {
            if n != name {
                continue;
            }
            for a in r.attempts.get_mut(k).into_iter().flatten() {
                a.summary.trainee.clone_from(&trainee);
            }
            run.summary.trainee.clone_from(&trainee);
        }
    }

    /// The session's duration, s (the last sample's time).
    pub fn duration(&self) -> f64 {
        self.result
            .robots
            .first()
            .and_then(|(_, r)| r.samples.last())
            .map_or(0.0, |s| s.t)
    }

    /// What `commands.toml` says the controls were.
    pub const COMMANDS_HEADER: &'static str =
        "The operators' controls of a `tracksim drive` session of several robots";

    /// Writes what `tracksim run` writes for the file (a folder per robot, `team.json`, plots
    /// unless `plots` is false), each robot's `controls.csv` in its folder, and
    /// `commands.toml` (every robot's controls) into `dir`; returns the paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
    ) -> Result<Vec<PathBuf>> {
        let logs: Vec<(&str, &CommandLog)> = self
            .result
            .robots
            .iter()
            .zip(&self.logs)
            .map(|((name, _), log)| (name.as_str(), log))
            .collect();
        let header = LogHeader {
            what: Self::COMMANDS_HEADER,
            notes: &[],
            seed: None,
        };
        let which = crate::output::Outputs {
            plots,
            ..crate::output::Outputs::ALL
        };
        let mut written = crate::output::write_team_session(
            sc,
            &self.result,
            (&logs, header),
            scenario_file,
            dir,
            which,
        )?;
        for (k, (name, run)) in self.result.robots.iter().enumerate() {
            let view = sc.robot_view(k);
            let flippers = &view.vehicle.flippers;
            let initial: Vec<f64> = flippers
                .iter()
                .map(|f| f.initial_angle.to_degrees())
                .collect();
            let text = controls_csv(
                &run.samples,
                &self.controls[k],
                &run.flipper_names,
                &initial,
            );
            let p = dir.join(name).join("controls.csv");
            crate::files::write_atomic(&p, text.as_bytes())?;
            written.push(p);
            // Each attempt an instructor's reset of this robot ended: its controls.
            for (i, (a, c)) in self.result.attempts[k]
                .iter()
                .zip(&self.kept_controls[k])
                .enumerate()
            {
                let text = controls_csv(&a.samples, c, &a.flipper_names, &initial);
                let p = dir
                    .join(name)
                    .join(crate::run::attempt_folder(i + 1))
                    .join("controls.csv");
                crate::files::write_atomic(&p, text.as_bytes())?;
                written.push(p);
            }
        }
        Ok(written)
    }

    /// The world's outcome.
    pub fn outcome(&self) -> &Outcome {
        &self.result.outcome
    }
}
