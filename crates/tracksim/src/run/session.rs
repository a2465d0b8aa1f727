//! The session loop: a [`Runner`] whose controls come from outside (a `drive` page, ROS 2
//! topics, later an instructor), taken in at sample boundaries only, recorded in a
//! [`CommandLog`] and ended by one rule ([`time_reached`]).
//!
//! At every sample boundary (`output_interval_s`), in this order: an interrupt (Ctrl-C,
//! SIGTERM) ends the session; then the source may end it ([`ControlSource::end`]: the operator
//! stopped, the page left); then `max_time` ends it; then, while the source holds the session
//! paused ([`ControlSource::paused`]: an instructor's pause), nothing steps (simulated time
//! stands still, the end checks above go on, and the wall clock of pacing is moved on by the
//! pause when it ends, so no burst catches it up); then the source may start it again
//! ([`ControlSource::reset`]: the attempt so far is kept, [`SessionWorld::end_attempt`]); then its new controls, if any, are compiled as a scenario's
//! command and applied before the next step, and logged. The world then steps to the next
//! sample ([`ControlSource::after_step`] after every step, [`ControlSource::after_sample`] at
//! the sample). A step that stops the world (a blow-up, robots further apart than one world
//! holds) ends the session there as [`End::Stopped`], every robot's run kept (issue 59).
//!
//! Determinism: a control is applied exactly as a `[[commands]]` entry at that time is (the
//! same compilation, at the same step), so the log's `commands.toml` replays the session.

use super::command_log::CommandLog;
use super::runner::{End, Runner};
use super::team::TeamRunner;
use crate::error::{Error, Result};
use crate::model::Command;
use crate::spec::CommandSpec;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How often a paused session asks its source whether it is still paused.
pub const PAUSE_POLL: Duration = Duration::from_millis(5);

/// Where a session's controls come from. Every method is called at a sample boundary except
/// [`ControlSource::after_step`].
pub trait ControlSource {
    /// Whether the session ends here for a reason of the source's own (the operator stopped
    /// it, the page left); `None` to go on.
    fn end(&mut self, _runner: &Runner) -> Option<End> {
        None
    }

    /// Whether the session starts again from its scenario here (the attempt so far is kept,
    /// the runner is reset and the log starts afresh; the source clears its own state before
    /// returning true).
    fn reset(&mut self) -> bool {
        false
    }

    /// Whether the session is held paused now (asked at a sample boundary, and every few
    /// milliseconds while it is).
    fn paused(&mut self, _runner: &Runner) -> bool {
        false
    }

    /// The controls to apply from now on, as a command entry at `runner.time()`, if they
    /// changed.
    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec>;

    /// After every step.
    fn after_step(&mut self, _runner: &Runner) {}

    /// After the step that reached a sample.
    fn after_sample(&mut self, _runner: &Runner) {}
}

/// When a session ends besides its source's own reasons.
#[derive(Clone, Copy, Debug, Default)]
pub struct SessionLimits {
    /// End at this simulated time, s (None: only on the source's word or an interrupt).
    pub max_time: Option<f64>,
    /// When set (by a Ctrl-C or SIGTERM handler), the session ends at the next sample as
    /// interrupted.
    pub interrupt: Option<&'static AtomicBool>,
}

impl SessionLimits {
    /// Whether the interrupt flag is set.
    pub fn interrupted(&self) -> bool {
        self.interrupt.is_some_and(|i| i.load(Ordering::SeqCst))
    }

    /// Whether `max_time` is reached at simulated time `t` s with step `dt` s (see
    /// [`time_reached`]).
    pub fn reached(&self, t: f64, dt: f64) -> bool {
        self.max_time.is_some_and(|m| time_reached(t, m, dt))
    }
}

/// The one rule for "the session's time is up": simulated time `t` s has reached `limit` s to
/// within half a step `dt` s (a duration is counted in whole steps; time is a sum of steps).
pub fn time_reached(t: f64, limit: f64, dt: f64) -> bool {
    t >= limit - 0.5 * dt
}

/// A world a session drives: one robot's [`Runner`], or several robots' [`TeamRunner`].
pub trait SessionWorld {
    /// Simulated time, s.
    fn time(&self) -> f64;
    /// The physics step, s.
    fn dt(&self) -> f64;
    /// Robots driven (1 for a [`Runner`]).
    fn robot_count(&self) -> usize;
    /// One physics step.
    fn step(&mut self) -> Result<()>;
    /// Whether the last step reached an output interval (true before the first).
    fn at_sample(&self) -> bool;
    /// Starts again from the scenario.
    fn restart(&mut self) -> Result<()>;
    /// Applies command entry `c` to robot `k` as a file's `[[commands]]` entry is applied.
    fn apply_command(&mut self, k: usize, c: &CommandSpec) -> Result<()>;
    /// The world was held paused for `wall` of wall-clock time: pacing goes on from here.
    fn paused_for(&mut self, wall: Duration);
    /// What a finished attempt keeps.
    type Attempt;
    /// Ends the attempt so far (a reset): returns what it keeps, if the world keeps attempts,
    /// and starts again from the scenario ([`SessionWorld::restart`]).
    fn end_attempt(&mut self) -> Result<Option<Self::Attempt>> {
        self.restart()?;
        Ok(None)
    }
}

impl SessionWorld for Runner {
    fn time(&self) -> f64 {
        Runner::time(self)
    }
    fn dt(&self) -> f64 {
        self.sim().dt()
    }
    fn robot_count(&self) -> usize {
        1
    }
    fn step(&mut self) -> Result<()> {
        Runner::step(self)
    }
    fn at_sample(&self) -> bool {
        Runner::at_sample(self)
    }
    fn restart(&mut self) -> Result<()> {
        self.reset(None)
    }
    fn apply_command(&mut self, _k: usize, c: &CommandSpec) -> Result<()> {
        apply(self, c)
    }
    fn paused_for(&mut self, wall: Duration) {
        Runner::paused_for(self, wall)
    }
    type Attempt = super::RunResult;
    fn end_attempt(&mut self) -> Result<Option<super::RunResult>> {
        Ok(Some(Runner::end_attempt(self, End::Reset)?))
    }
}

impl SessionWorld for TeamRunner {
    fn time(&self) -> f64 {
        self.sim().time()
    }
    fn dt(&self) -> f64 {
        self.sim().dt()
    }
    fn robot_count(&self) -> usize {
        self.sim().robot_count()
    }
    fn step(&mut self) -> Result<()> {
        TeamRunner::step(self)
    }
    fn at_sample(&self) -> bool {
        TeamRunner::at_sample(self)
    }
    fn restart(&mut self) -> Result<()> {
        self.reset()
    }
    fn apply_command(&mut self, k: usize, c: &CommandSpec) -> Result<()> {
        let compiled = compile(c, &self.robot_scenario(k).vehicle)?;
        for cmd in compiled {
            self.apply_controls(k, &cmd.controls)?;
        }
        Ok(())
    }
    fn paused_for(&mut self, wall: Duration) {
        TeamRunner::paused_for(self, wall)
    }
    /// A reset of the whole world is not kept (a reset of one robot is its `reset` command:
    /// [`TeamRunner::reset_robot`] keeps that robot's attempts).
    type Attempt = ();
}

/// Where the controls of a session of world `W` come from, robot by robot: a
/// [`ControlSource`] for several robots. The hooks after a step and a sample take the world
/// mutably only to read a robot of a team ([`TeamRunner::view`] selects it).
pub trait WorldSource<W> {
    /// As [`ControlSource::end`].
    fn end(&mut self, _world: &W) -> Option<End> {
        None
    }
    /// As [`ControlSource::reset`] (every robot starts again).
    fn reset(&mut self) -> bool {
        false
    }
    /// As [`ControlSource::paused`].
    fn paused(&mut self, _world: &mut W) -> bool {
        false
    }
    /// Robot `k`'s controls from now on, if they changed (asked for every robot, in the
    /// world's build order, at every sample boundary).
    fn controls(&mut self, world: &W, k: usize) -> Option<CommandSpec>;
    /// After every step.
    fn after_step(&mut self, _world: &mut W) {}
    /// After the step that reached a sample.
    fn after_sample(&mut self, _world: &mut W) {}
}

/// A one-robot [`ControlSource`] as a [`WorldSource`] of a [`Runner`].
struct OneRobot<'a>(&'a mut dyn ControlSource);

impl WorldSource<Runner> for OneRobot<'_> {
    fn end(&mut self, w: &Runner) -> Option<End> {
        self.0.end(w)
    }
    fn reset(&mut self) -> bool {
        self.0.reset()
    }
    fn paused(&mut self, w: &mut Runner) -> bool {
        self.0.paused(w)
    }
    fn controls(&mut self, w: &Runner, _k: usize) -> Option<CommandSpec> {
        self.0.controls(w)
    }
    fn after_step(&mut self, w: &mut Runner) {
        self.0.after_step(w)
    }
    fn after_sample(&mut self, w: &mut Runner) {
        self.0.after_sample(w)
    }
}

/// A finished session loop: the runner (to finish or publish from), how it ended and the
/// controls it took.
pub struct SessionRun {
    /// The runner as the session left it.
    pub runner: Runner,
    /// How the session ended.
    pub end: End,
    /// The controls applied (of the last attempt), as `[[commands]]` entries.
    pub log: CommandLog,
    /// Each attempt a reset ended, in order: its run and its controls.
    pub attempts: Vec<(super::RunResult, CommandLog)>,
}

/// A finished session of a world of several robots: the world, how it ended, and each
/// robot's controls (by robot index).
pub struct WorldSessionRun<W: SessionWorld> {
    /// The world as the session left it.
    pub world: W,
    /// How the session ended.
    pub end: End,
    /// Each robot's controls (of the last attempt), as `[[commands]]` entries.
    pub logs: Vec<CommandLog>,
    /// Each attempt a reset ended and the world kept ([`SessionWorld::end_attempt`]), with
    /// each robot's controls.
    pub attempts: Vec<(W::Attempt, Vec<CommandLog>)>,
}

/// Runs `runner` (built without the file's commands, unbounded, paced if wanted) with
/// controls from `source` until an end (see the module docs).
pub fn run_session(
    runner: Runner,
    source: &mut dyn ControlSource,
    limits: SessionLimits,
) -> Result<SessionRun> {
    let run = run_world_session(runner, &mut OneRobot(source), limits, &[0])?;
    let WorldSessionRun {
        world,
        end,
        mut logs,
        attempts,
    } = run;
    Ok(SessionRun {
        runner: world,
        end,
        log: logs.remove(0),
        attempts: attempts
            .into_iter()
            .map(|(r, mut l)| (r, l.remove(0)))
            .collect(),
    })
}

/// The session loop of any [`SessionWorld`] (see the module docs): robot by robot in `order`
/// (the world's build order, so that the physics never sees the robots' file order), each
/// robot's controls applied and logged.
pub fn run_world_session<W: SessionWorld>(
    mut world: W,
    source: &mut dyn WorldSource<W>,
    limits: SessionLimits,
    order: &[usize],
) -> Result<WorldSessionRun<W>> {
    let mut logs = vec![CommandLog::new(); world.robot_count()];
    let mut attempts = Vec::new();
    let mut paused_since: Option<Instant> = None;
    let dt = world.dt();
    let end = 'session: loop {
        if limits.interrupted() {
            break End::Interrupted;
        }
        if let Some(end) = source.end(&world) {
            break end;
        }
        if limits.reached(world.time(), dt) {
            break End::Reached;
        }
        if source.paused(&mut world) {
            paused_since.get_or_insert_with(Instant::now);
            std::thread::sleep(PAUSE_POLL);
            continue;
        }
        if let Some(since) = paused_since.take() {
            world.paused_for(since.elapsed());
        }
        if source.reset() {
            let fresh = vec![CommandLog::new(); world.robot_count()];
            let log = std::mem::replace(&mut logs, fresh);
            if let Some(a) = world.end_attempt()? {
                attempts.push((a, log));
            }
        }
        for &k in order {
            if let Some(c) = source.controls(&world, k) {
                world.apply_command(k, &c)?;
                logs[k].push(c);
            }
        }
        loop {
            // A world that stops (a blow-up, robots too far apart) ends the session with
            // every robot's run kept up to there (issue 59); any other error is returned.
            if let Err(e) = world.step() {
                break 'session End::from_step_error(e)?;
            }
            source.after_step(&mut world);
            if world.at_sample() {
                break;
            }
        }
        source.after_sample(&mut world);
    };
    Ok(WorldSessionRun {
        world,
        end,
        logs,
        attempts,
    })
}

/// Applies command entry `c` to `runner` as a file's `[[commands]]` entry is applied.
pub fn apply(runner: &mut Runner, c: &CommandSpec) -> Result<()> {
    for cmd in compile(c, &runner.scenario().vehicle)? {
        if cmd.controls.reset {
            runner.sim_mut().reset_robot()?;
        }
        runner.apply(&cmd.controls);
    }
    Ok(())
}

/// Command entry `c` compiled for `vehicle` as a file's entry is.
fn compile(c: &CommandSpec, vehicle: &crate::model::VehicleModel) -> Result<Vec<Command>> {
    crate::model::compile_commands(std::slice::from_ref(c), vehicle).map_err(|issues| {
        Error::Settings {
            what: format!("session control at t = {} s", c.t_s),
            issues,
        }
    })
}
