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

use super::command_log::CommandLog;
use super::runner::{End, Runner};
use crate::error::{Error, Result};
use crate::spec::CommandSpec;
use std::sync::atomic::{AtomicBool, Ordering};

/// Where a session's controls come from. Every method is called at a sample boundary except
/// [`ControlSource::after_step`].
pub trait ControlSource {
    /// Whether the session ends here for a reason of the source's own (the operator stopped
    /// it, the page left); `None` to go on.
    fn end(&mut self, _runner: &Runner) -> Option<End> {
        None
    }

    /// Whether the session starts again from its scenario here (the runner is reset and the
    /// log cleared; the source clears its own state before returning true).
    fn reset(&mut self) -> bool {
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

/// A finished session loop: the runner (to finish or publish from), how it ended and the
/// controls it took.
pub struct SessionRun {
    /// The runner as the session left it.
    pub runner: Runner,
    /// How the session ended.
    pub end: End,
    /// The controls applied, as `[[commands]]` entries.
    pub log: CommandLog,
}

/// Runs `runner` (built without the file's commands, unbounded, paced if wanted) with
/// controls from `source` until an end (see the module docs).
pub fn run_session(
    mut runner: Runner,
    source: &mut dyn ControlSource,
    limits: SessionLimits,
) -> Result<SessionRun> {
    let mut log = CommandLog::new();
    let dt = runner.sim().dt();
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
            runner.reset(None)?;
            log.clear();
        }
        if let Some(c) = source.controls(&runner) {
            apply(&mut runner, &c)?;
            log.push(c);
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
