//! Running a scenario to the end: the loop that feeds the scenario's command timeline to the
//! world, records samples and decides the outcome. A run returns a [`RunResult`]; files are
//! written by [`crate::output`].
//!
//! - [`timeline`]: the file's `[[commands]]` as a source of controls;
//! - [`scripted`]: a simulation driven by its timeline, step by step;
//! - [`outcome`]: success and failure conditions;
//! - [`expect`]: a run checked against its scenario's `[expect]` table;
//! - [`summary`]: the numbers of `summary.json`;
//! - [`track_summary`]: per-track figures and the odometry error in it;
//! - [`drawbar_summary`]: the steady drawbar pull and slip of a `[drawbar]` run;
//! - [`turn_summary`]: commanded against achieved turns.

pub mod drawbar_summary;
pub mod expect;
pub mod outcome;
pub mod scripted;
pub mod summary;
pub mod timeline;
pub mod track_summary;
pub mod turn_summary;

pub use drawbar_summary::{DrawbarSummary, drawbar_summary};
pub use expect::check_expectations;
pub use outcome::{Outcome, check_outcome};
pub use scripted::Scripted;
pub use summary::{SolverSummary, Summary, WallTimes};
pub use timeline::Timeline;
pub use track_summary::{
    DriveSummary, OdometrySummary, TrackSummary, odometry_summary, track_summaries,
};
pub use turn_summary::{TurnSummary, turn_summaries};

use crate::error::Result;
use crate::model::Scenario;
use crate::world::Sample;
use std::time::Instant;

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Samples at the output interval (the first at t = 0).
    pub samples: Vec<Sample>,
    /// Track names (column order of per-track values).
    pub track_names: Vec<String>,
    /// Flipper names.
    pub flipper_names: Vec<String>,
    /// Summary numbers.
    pub summary: Summary,
    /// How it ended.
    pub outcome: Outcome,
}

/// Options of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunOptions {
    /// Pace the simulation to the wall clock (never faster than real time).
    pub realtime: bool,
    /// When set (by a Ctrl-C handler), the run stops at the next step and returns what was
    /// simulated so far with [`Outcome::Interrupted`].
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
}

/// Runs a scenario for its duration (or until its outcome is decided, if it says to stop).
/// `progress` is called after every output sample with (simulated time, duration) in seconds.
pub fn run_scenario(sc: &Scenario, progress: impl FnMut(f64, f64)) -> Result<RunResult> {
    run_scenario_with(sc, RunOptions::default(), progress)
}

/// [`run_scenario`] with options.
pub fn run_scenario_with(
    sc: &Scenario,
    opts: RunOptions,
    mut progress: impl FnMut(f64, f64),
) -> Result<RunResult> {
    let mut sim = Scripted::new(sc)?;
    let dt = sc.solver.dt;
    let steps = (sc.duration / dt).round().max(1.0) as u64;
    let every = ((sc.output_interval / dt).round() as u64).max(1);
    let mut samples = vec![sim.sample()];
    let wall = Instant::now();
    let mut stepping = 0.0;
    let mut outcome = None;
    let mut outcome_time = 0.0;
    for i in 1..=steps {
        if opts
            .stop
            .is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed))
        {
            if samples.last().is_some_and(|s| s.t < sim.time()) {
                samples.push(sim.sample());
            }
            outcome = Some(Outcome::Interrupted(format!(
                "interrupted at t = {:.3} s of {:.3} s",
                sim.time(),
                sc.duration
            )));
            outcome_time = sim.time();
            break;
        }
        let t0 = Instant::now();
        sim.step()?;
        stepping += t0.elapsed().as_secs_f64();
        let sample_now = i % every == 0 || i == steps;
        if outcome.is_none() && sample_now {
            outcome = check_outcome(&sc.outcome, &sim);
            outcome_time = sim.time();
        }
        if sample_now || (outcome.is_some() && sc.outcome.stop) {
            samples.push(sim.sample());
            progress(sim.time(), sc.duration);
        }
        if outcome.is_some() && sc.outcome.stop {
            break;
        }
        if opts.realtime {
            let ahead = sim.time() - wall.elapsed().as_secs_f64();
            if ahead > 0.002 {
                std::thread::sleep(std::time::Duration::from_secs_f64(ahead));
            }
        }
    }
    let outcome = outcome.unwrap_or_else(|| {
        outcome_time = sim.time();
        outcome::at_end(&sc.outcome, sim.time())
    });
    let times = WallTimes {
        stepping,
        elapsed: wall.elapsed().as_secs_f64(),
        paced: opts.realtime,
    };
    let summary = Summary::new(sc, &sim, &samples, (&outcome, outcome_time), times);
    Ok(RunResult {
        samples,
        track_names: sim.track_names().to_vec(),
        flipper_names: sim.flipper_names().to_vec(),
        summary,
        outcome,
    })
}
