//! The session loop: a [`Runner`] whose controls come from outside (a `drive` page, ROS 2
//! topics, later an instructor), taken in at sample boundaries only, recorded in a
//! [`CommandLog`] and ended by one rule ([`time_reached`]).
//!
//! At every sample boundary (`output_interval_s`), in this order: an interrupt (Ctrl-C,
//! SIGTERM) ends the session; then the source may end it ([`ControlSource::end`]: the operator
//! stopped, the page left); then `max_time` ends it; then the source may start it again
//! ([`ControlSource::reset`]); then its new controls, if any, are compiled as a scenario's
//! command and applied before the next step, and logged. The world then steps to the next
//! sample ([`ControlSource::after_step`] after every step, [`ControlSource::after_sample`] at
//! the sample).
//!
//! Determinism: a control is applied exactly as a `[[commands]]` entry at that time is (the
//! same compilation, at the same step), so the log's `commands.toml` replays the session.
//!
//! The loop runs any [`SessionWorld`]: one robot's [`Runner`] (controls a [`CommandSpec`],
//! one [`CommandLog`]) or a world of several robots' [`TeamRunner`] (controls per robot,
//! applied in the world's build order, a [`CommandLog`] per robot).

use super::command_log::CommandLog;
use super::runner::{End, Runner};
use super::team::TeamRunner;
use crate::error::{Error, Result};
use crate::spec::CommandSpec;
use std::sync::atomic::{AtomicBool, Ordering};

/// What a session loop steps: a run whose controls come from outside, taken in at sample
/// boundaries.
pub trait SessionWorld {
    /// The controls of one sample boundary.
    type Controls;
    /// The record of the controls applied.
    type Log: Default;
    /// Simulated time, s.
    fn time(&self) -> f64;
    /// The physics step, s.
    fn dt(&self) -> f64;
    /// Starts again from the scenario.
    fn restart(&mut self) -> Result<()>;
    /// Applies `c` before the next step, as a file's `[[commands]]` at this time are.
    fn apply_controls(&mut self, c: &Self::Controls) -> Result<()>;
    /// Records `c` in `log`.
    fn record(log: &mut Self::Log, c: Self::Controls);
    /// Forgets what `log` holds (a session that starts again).
    fn clear(log: &mut Self::Log);
    /// Advances one physics step.
    fn step(&mut self) -> Result<()>;
    /// Whether the last step reached a sample.
    fn at_sample(&self) -> bool;
}

impl SessionWorld for Runner {
    type Controls = CommandSpec;
    type Log = CommandLog;
    fn time(&self) -> f64 {
        Runner::time(self)
    }
    fn dt(&self) -> f64 {
        self.sim().dt()
    }
    fn restart(&mut self) -> Result<()> {
        self.reset(None)
    }
    fn apply_controls(&mut self, c: &CommandSpec) -> Result<()> {
        apply(self, c)
    }
    fn record(log: &mut CommandLog, c: CommandSpec) {
        log.push(c);
    }
    fn clear(log: &mut CommandLog) {
        log.clear();
    }
    fn step(&mut self) -> Result<()> {
        Runner::step(self)
    }
    fn at_sample(&self) -> bool {
        Runner::at_sample(self)
    }
}

/// A world of several robots in a session: the controls of a boundary are `(robot index,
/// command entry)` pairs, applied in the world's build order
/// ([`crate::world::Simulation::build_order`], as [`TeamRunner`] applies a file's commands),
/// each robot's logged in its own [`CommandLog`] (indexed by robot).
impl SessionWorld for TeamRunner {
    type Controls = Vec<(usize, CommandSpec)>;
    type Log = Vec<CommandLog>;
    fn time(&self) -> f64 {
        TeamRunner::time(self)
    }
    fn dt(&self) -> f64 {
        self.sim().dt()
    }
    fn restart(&mut self) -> Result<()> {
        Err(Error::Build(
            "a session of several robots does not start again".into(),
        ))
    }
    fn apply_controls(&mut self, c: &Self::Controls) -> Result<()> {
        let order = self.sim().build_order().to_vec();
        for k in order {
            for (_, spec) in c.iter().filter(|(j, _)| *j == k) {
                self.apply_robot(k, spec)?;
            }
        }
        Ok(())
    }
    fn record(log: &mut Vec<CommandLog>, c: Self::Controls) {
        for (k, spec) in c {
            if log.len() <= k {
                log.resize_with(k + 1, CommandLog::new);
            }
            log[k].push(spec);
        }
    }
    fn clear(log: &mut Vec<CommandLog>) {
        log.iter_mut().for_each(CommandLog::clear);
    }
    fn step(&mut self) -> Result<()> {
        TeamRunner::step(self)
    }
    fn at_sample(&self) -> bool {
        TeamRunner::at_sample(self)
    }
}

/// Where a session's controls come from. Every method is called at a sample boundary except
/// [`ControlSource::after_step`].
pub trait ControlSource<W: SessionWorld = Runner> {
    /// Whether the session ends here for a reason of the source's own (the operator stopped
    /// it, the page left); `None` to go on.
    fn end(&mut self, _runner: &W) -> Option<End> {
        None
    }

    /// Whether the session starts again from its scenario here (the runner is reset and the
    /// log cleared; the source clears its own state before returning true).
    fn reset(&mut self) -> bool {
        false
    }

    /// The controls to apply from now on, as a command entry at `runner.time()`, if they
    /// changed.
    fn controls(&mut self, runner: &W) -> Option<W::Controls>;

    /// After every step.
    fn after_step(&mut self, _runner: &W) {}

    /// After the step that reached a sample.
    fn after_sample(&mut self, _runner: &W) {}
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

/// A finished session loop: the runner (to finish or publish from), how it ended and the
/// controls it took.
pub struct SessionRun<W: SessionWorld = Runner> {
    /// The runner as the session left it.
    pub runner: W,
    /// How the session ended.
    pub end: End,
    /// The controls applied, as `[[commands]]` entries.
    pub log: W::Log,
}

/// Runs `runner` (built without the file's commands, unbounded, paced if wanted) with
/// controls from `source` until an end (see the module docs).
pub fn run_session<W: SessionWorld>(
    mut runner: W,
    source: &mut dyn ControlSource<W>,
    limits: SessionLimits,
) -> Result<SessionRun<W>> {
    let mut log = W::Log::default();
    let dt = runner.dt();
    let end = loop {
        if limits.interrupted() {
            break End::Interrupted;
        }
        if let Some(end) = source.end(&runner) {
            break end;
        }
        if limits.reached(runner.time(), dt) {
            break End::Reached;
        }
        if source.reset() {
            runner.restart()?;
            W::clear(&mut log);
        }
        if let Some(c) = source.controls(&runner) {
            runner.apply_controls(&c)?;
            W::record(&mut log, c);
        }
        loop {
            runner.step()?;
            source.after_step(&runner);
            if runner.at_sample() {
                break;
            }
        }
        source.after_sample(&runner);
    };
    Ok(SessionRun { runner, end, log })
}

/// Applies command entry `c` to `runner` as a file's `[[commands]]` entry is applied.
pub fn apply(runner: &mut Runner, c: &CommandSpec) -> Result<()> {
    let compiled =
        crate::model::compile_commands(std::slice::from_ref(c), &runner.scenario().vehicle)
            .map_err(|issues| Error::Settings {
                what: format!("session control at t = {} s", c.t_s),
                issues,
            })?;
    for cmd in compiled {
        runner.apply(&cmd.controls);
    }
    Ok(())
}
