//! Running a scenario: the one loop ([`Runner`]) that feeds the scenario's command timeline
//! and the caller's controls to the world, records samples and decides the outcome. A run returns a [`RunResult`]; files are
//! written by [`crate::output`].
//!
//! - [`runner`]: the one run loop ([`Runner`]) that every way of running steps;
//! - [`sample_log`]: a run's samples at a bounded memory, the older ones spilled to disk
//!   ([`SampleLog`]);
//! - [`timeline`]: the file's `[[commands]]` as a source of controls;
//! - [`scripted`]: a simulation driven by its timeline, step by step;
//! - [`session`]: the session loop of a runner (or a team's) whose controls come from outside
//!   (a page, ROS topics), with one end rule;
//! - [`attempt`]: a session's attempts (a reset starts the next), as `summary.json` lists
//!   them ([`AttemptRecord`]);
//! - [`command_log`]: the controls a session or an episode gave ([`CommandLog`]) and the one
//!   writer of `commands.toml`;
//! - [`outcome`]: success and failure conditions;
//! - [`course`]: a `[course]` scored at every sample ([`CourseTracker`], [`CourseScore`]);
//! - [`standings`]: several robots' course scores ranked, a race's winner, a team's score;
//! - [`expect`]: a run checked against its scenario's `[expect]` table;
//! - [`events`]: stalls, the largest tilt and the outcome, for a review (and the stall live);
//! - [`summary`]: the numbers of `summary.json`;
//! - [`track_summary`]: per-track figures and the odometry error in it;
//! - [`drawbar_summary`]: the steady drawbar pull and slip of a `[drawbar]` run;
//! - [`soil_summary`]: sinkage, soil thrust and the rut grid's memory of a run on soil;
//! - [`turn_summary`]: commanded against achieved turns;
//! - [`team`]: a world with several robots run ([`TeamRunner`]), each robot's run and the
//!   world's outcome by its rule;
//! - [`view`]: one robot of a running world as a live front end reads it ([`RunView`]).

pub mod attempt;
pub mod command_log;
pub mod course;
pub mod drawbar_summary;
pub mod events;
pub mod expect;
pub mod margins;
pub mod outcome;
pub mod runner;
pub mod sample_log;
pub mod scripted;
pub mod session;
pub mod soil_summary;
pub mod standings;
pub mod summary;
pub mod team;
pub mod timeline;
pub mod track_summary;
pub mod turn_summary;
pub mod view;

pub use attempt::{AttemptRecord, attempt_folder};
pub use command_log::{CommandLog, LogHeader, duration_arg, team_toml, write_team_log};
pub use course::{
    CourseEvent, CourseScore, CourseTracker, FaultCounts, MAX_COURSE_EVENTS, ScoreSummary,
};
pub use drawbar_summary::{DrawbarSummary, drawbar_summary};
pub use expect::{check_expectations, expect_verdict};
pub use margins::{Margins, Peak, TrackMargin};
pub use outcome::{Outcome, check_outcome};
pub use runner::{End, Runner, one_robot};
pub use sample_log::{SPILL_CHUNK, SampleIter, SampleLog, SpillLog};
pub use scripted::Scripted;
pub use session::{
    ControlSource, SessionLimits, SessionRun, SessionWorld, WorldSessionRun, WorldSource,
    run_session, run_world_session, time_reached,
};
pub use soil_summary::{SoilSummary, TrackSoilSummary, soil_summary};
pub use standings::{Standing, Standings};
pub use summary::{SensorSummary, SolverSummary, Summary, WallTimes, iso8601_utc};
pub use team::{TeamResult, TeamRunner, run_team, run_team_kept};
pub use timeline::Timeline;
pub use track_summary::{
    DriveSummary, OdometrySummary, TrackSummary, odometry_summary, track_summaries,
};
pub use turn_summary::{TurnSummary, turn_summaries};
pub use view::RunView;

use crate::error::Result;
use crate::model::Scenario;

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Samples at the output interval (the first at t = 0), the older ones on disk.
    pub samples: SampleLog,
    /// Track names (column order of per-track values).
    pub track_names: Vec<String>,
    /// Flipper names.
    pub flipper_names: Vec<String>,
    /// Summary numbers.
    pub summary: Summary,
    /// How it ended.
    pub outcome: Outcome,
    /// Every sensor's readings (`[[sensors]]` of the vehicle; empty when not recorded).
    pub sensors: Vec<crate::sensors::SensorStream>,
    /// The soil's ruts at the end (empty without soil; `ruts.csv`).
    pub ruts: Vec<crate::world::RutCell>,
    /// Every change of the world's low-friction patch during the run, in order (`fault.patch`,
    /// issue 43; empty without one): the replay draws the patch from these (`scene.json`
    /// `patches`).
    pub patches: Vec<crate::world::PatchChange>,
}

/// Options of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunOptions {
    /// Pace the simulation to the wall clock (never faster than real time).
    pub realtime: bool,
    /// When set (by a Ctrl-C or SIGTERM handler), the run stops at the next step and returns what was
    /// simulated so far with [`Outcome::Interrupted`].
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
}

impl RunOptions {
    /// Whether a stop was asked (the `stop` flag is set).
    pub fn stop_asked(&self) -> bool {
        self.stop
            .is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// Runs a scenario for its duration (or until its outcome is decided, if it says to stop).
/// `progress` is called after every output sample with (simulated time, duration) in seconds.
pub fn run_scenario(sc: &Scenario, progress: impl FnMut(f64, f64)) -> Result<RunResult> {
    run_scenario_with(sc, RunOptions::default(), progress)
}

/// [`run_scenario_with`], keeping what was simulated when the world stops (it blows up): the run ends
/// there ([`End::Stopped`], its outcome a failure that says so) and the error comes back
/// beside the result, for the caller to write the outputs and then report it.
pub fn run_scenario_kept(
    sc: &Scenario,
    opts: RunOptions,
    progress: impl FnMut(f64, f64),
) -> Result<(RunResult, Option<crate::error::Error>)> {
    let mut runner = Runner::new(sc)?;
    if opts.realtime {
        runner = runner.paced(1.0);
    }
    match runner.run_to_end(progress, || opts.stop_asked()) {
        Ok(end) => Ok((runner.finish(end), None)),
        Err(e) if e.stops_world() => Ok((runner.finish(End::Stopped(e.to_string())), Some(e))),
        Err(e) => Err(e),
    }
}

/// [`run_scenario`] with options: a [`Runner`] stepped to its end.
pub fn run_scenario_with(
    sc: &Scenario,
    opts: RunOptions,
    progress: impl FnMut(f64, f64),
) -> Result<RunResult> {
    let mut runner = Runner::new(sc)?;
    if opts.realtime {
        runner = runner.paced(1.0);
    }
    let end = runner.run_to_end(progress, || opts.stop_asked())?;
    Ok(runner.finish(end))
}
