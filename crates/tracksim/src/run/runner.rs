//! The one run loop ([`Runner`]): every way of running a scenario (`tracksim run`, a live
//! `drive` session, the learning environment, a sweep, a controller) steps a `Runner`, which
//! owns the clock, applies the file's commands as they fall due and the caller's controls when
//! given, records a [`Sample`] at every output interval, decides the outcome there, paces to
//! the wall clock if asked, and produces the [`RunResult`].
//!
//! Determinism: the physics sees only the controls and the step count; pacing, recording and
//! the checks never change a trajectory (the golden hashes are those of the loop this
//! replaced).

use super::RunResult;
use super::course::{CourseScore, CourseTracker};
use super::outcome::{self, Outcome, check_outcome};
use super::sample_log::SampleLog;
use super::scripted::Scripted;
use super::summary::{Summary, WallTimes};
use crate::error::Result;
use crate::model::{Controls, Scenario};
use crate::sensors::SensorSet;
use crate::world::Simulation;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Refuses a scenario with several robots (`[[vehicles]]`) in a front end that runs one: what
/// `Runner` (and so the env, drive, ros, compare, ensembles and sweeps) says of it.
pub fn one_robot(sc: &Scenario) -> Result<()> {
    if sc.robot_count() > 1 {
        return Err(crate::error::Error::Settings {
            what: "the scenario's robots".into(),
            issues: vec![crate::error::SpecIssue::new(
                "vehicles",
                format!(
                    "this front end runs one robot; the scenario has {} ({}): run it with \
                     `tracksim run` (each robot's outputs in its own folder, docs/TEAMS.md)",
                    sc.robot_count(),
                    sc.robot_names().join(", ")
                ),
            )],
        });
    }
    Ok(())
}

/// How a run ended, as the caller of [`Runner::finish`] says.
#[derive(Clone, Debug, PartialEq)]
pub enum End {
    /// The run reached its end (its duration, or its decided outcome with `stop`); the
    /// outcome is the scenario's.
    Reached,
    /// Stopped from outside (Ctrl-C, SIGTERM) before its end.
    Interrupted,
    /// The operator of a live session ended it.
    ByOperator,
    /// The attempt of a live session ended with a reset (the driver's or an instructor's):
    /// the session goes on with a new attempt (issue 43).
    Reset,
    /// The driver's page of a live session left and did not come back within the grace
    /// period, s, with no other page connected.
    Abandoned(f64),
    /// The world stopped (its message): it blew up (the stability check), or its robots
    /// spread further apart than one world holds (`model::MAX_ROBOT_SPREAD_M`). The run stops
    /// there and keeps what was simulated, every robot's (issue 59); its outcome is a failure
    /// that says so, and `Summary::stopped` says why.
    Stopped(String),
}

impl End {
    /// The world's stop message, when the run ended with [`End::Stopped`].
    pub fn stopped(&self) -> Option<&str> {
        match self {
            End::Stopped(why) => Some(why),
            _ => None,
        }
    }

    /// How a run ends when its step returned `e`: `Ok(End::Stopped)` for an error that stops
    /// the world but keeps what was simulated (a blow-up, robots spread too far apart), else
    /// the error itself.
    pub fn from_step_error(e: crate::error::Error) -> crate::error::Result<End> {
        if e.stops_world() {
            Ok(End::Stopped(e.to_string()))
        } else {
            Err(e)
        }
    }
}

/// A scenario being run: the simulation, its command timeline, the samples so far and the
/// outcome once decided.
pub struct Runner {
    sc: Arc<Scenario>,
    sim: Scripted,
    /// Steps between two samples.
    every: u64,
    /// Steps to the end of the scenario's duration (`None`: no end, a live session).
    end_step: Option<u64>,
    /// Record samples (the environments do not need them).
    record: bool,
    /// Stop stepping once the outcome is decided (the file's `outcome.stop`).
    stop_on_outcome: bool,
    /// Simulated seconds per wall-clock second when paced.
    pace: Option<f64>,
    samples: SampleLog,
    /// The vehicle's sensors, updated after every step at their rates.
    sensors: SensorSet,
    decided: Option<(Outcome, f64)>,
    stepping: f64,
    wall: Instant,
    /// Wall-clock date of the start (or the last reset).
    started: std::time::SystemTime,
    sampled: bool,
    /// The course being scored (`[course]`), if any.
    course: Option<CourseTracker>,
}

impl Runner {
    /// A run of `sc` with the file's `[[commands]]`, to the end of its duration.
    pub fn new(sc: &Scenario) -> Result<Self> {
        Self::from_shared(Arc::new(sc.clone()))
    }

    /// [`Runner::new`] of a shared scenario (not copied).
    pub fn from_shared(sc: Arc<Scenario>) -> Result<Self> {
        one_robot(&sc)?;
        let sim = Scripted::from_shared(sc.clone())?;
        let dt = sc.solver.dt;
        let every = ((sc.output_interval / dt).round() as u64).max(1);
        let end_step = Some((sc.duration / dt).round().max(1.0) as u64);
        let sensors = SensorSet::new(&sim, true);
        let mut r = Runner {
            stop_on_outcome: sc.outcome.stop,
            sim,
            every,
            end_step,
            record: true,
            pace: None,
            samples: SampleLog::new(),
            sensors,
            decided: None,
            stepping: 0.0,
            wall: Instant::now(),
            started: std::time::SystemTime::now(),
            sampled: true,
            course: sc
                .course
                .as_ref()
                .map(|c| CourseTracker::new(c, sc.outcome.max_tilt)),
            sc,
        };
        r.samples.push(r.sim.sample());
        Ok(r)
    }

    /// Controls come only from the caller ([`Runner::apply`]): the file's `[[commands]]` are
    /// not applied (a live session, an environment).
    pub fn without_commands(mut self) -> Self {
        self.sim.clear_commands();
        self
    }

    /// Runs on past the scenario's duration until the caller stops (a live session); the
    /// outcome is decided but never stops the run.
    pub fn unbounded(mut self) -> Self {
        self.end_step = None;
        self.stop_on_outcome = false;
        self
    }

    /// Paces the run to the wall clock at `speed` simulated seconds per wall second (1: real
    /// time); the run is never faster, and slower only if stepping is.
    pub fn paced(mut self, speed: f64) -> Self {
        self.pace = Some(speed);
        self
    }

    /// Records no samples beyond the first (the outcome is still decided at every output
    /// interval).
    pub fn unrecorded(mut self) -> Self {
        self.record = false;
        if !self.sensors.is_empty() {
            self.sensors = SensorSet::new(&self.sim, false);
        }
        self
    }

    /// Runs no sensors (an environment whose observation does not read them): sensing costs
    /// nothing and the trajectory is the same.
    pub fn without_sensors(mut self) -> Self {
        self.sensors = SensorSet::none();
        self
    }

    /// The vehicle's sensors and their latest readings.
    pub fn sensors(&self) -> &SensorSet {
        &self.sensors
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.sc
    }

    /// The running simulation.
    pub fn sim(&self) -> &Simulation {
        &self.sim
    }

    /// The running simulation, to set controls or query it mutably.
    pub fn sim_mut(&mut self) -> &mut Simulation {
        &mut self.sim
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.sim.time()
    }

    /// The samples so far (the first at t = 0).
    pub fn samples(&self) -> &SampleLog {
        &self.samples
    }

    /// The outcome and its time, s, once decided.
    pub fn decided(&self) -> Option<&(Outcome, f64)> {
        self.decided.as_ref()
    }

    /// Whether the last step ended at an output interval (a sample was taken, the outcome
    /// checked); true before the first step. Callers apply controls at these boundaries.
    pub fn at_sample(&self) -> bool {
        self.sampled
    }

    /// Wall-clock seconds since the start (or the last reset).
    pub fn wall_elapsed(&self) -> f64 {
        self.wall.elapsed().as_secs_f64()
    }

    /// Wall-clock seconds spent stepping.
    pub fn stepping(&self) -> f64 {
        self.stepping
    }

    /// Whether the run has reached its end: its duration, or its decided outcome when the
    /// scenario says to stop there.
    pub fn finished(&self) -> bool {
        let steps = self.sim.steps();
        self.end_step.is_some_and(|e| steps >= e)
            || (self.stop_on_outcome && self.decided.is_some())
    }

    /// Applies the caller's controls before the next step (in force until changed, like a
    /// `[[commands]]` entry at this time).
    pub fn apply(&mut self, c: &Controls) {
        self.sim.apply(c);
    }

    /// Advances one physics step: the commands that have fallen due, the step (paced if
    /// asked), then at an output interval (or the end) a sample and the outcome check.
    pub fn step(&mut self) -> Result<()> {
        if let Some(speed) = self.pace {
            let ahead = self.sim.time() / speed - self.wall.elapsed().as_secs_f64();
            if ahead > 0.002 {
                std::thread::sleep(Duration::from_secs_f64(ahead));
            }
        }
        let t0 = Instant::now();
        self.sim.step()?;
        self.sensors.update(&self.sim);
        self.stepping += t0.elapsed().as_secs_f64();
        let i = self.sim.steps();
        self.sampled = i.is_multiple_of(self.every) || self.end_step == Some(i);
        if self.sampled {
            if let Some(c) = &mut self.course {
                c.update(&self.sim, self.sim.time());
            }
            if self.decided.is_none() {
                self.decide();
            }
            if self.record {
                self.samples.push(self.sim.sample());
            }
        }
        Ok(())
    }

    /// Steps to the end ([`Runner::finished`]), calling `progress` with (simulated time,
    /// duration) in seconds after every sample; `stop` is asked before every step and ends
    /// the run early (false: go on).
    pub fn run_to_end(
        &mut self,
        mut progress: impl FnMut(f64, f64),
        stop: impl Fn() -> bool,
    ) -> Result<End> {
        while !self.finished() {
            if stop() {
                return Ok(End::Interrupted);
            }
            self.step()?;
            if self.sampled {
                progress(self.sim.time(), self.sc.duration);
            }
        }
        Ok(End::Reached)
    }

    /// Checks the outcome conditions now (if still undecided).
    pub fn decide(&mut self) {
        if self.decided.is_none() {
            let course = || self.course.as_ref().and_then(CourseTracker::outcome);
            self.decided = check_outcome(&self.sc.outcome, &self.sim)
                .or_else(course)
                .map(|o| (o, self.time()));
        }
    }

    /// The scenario's outcome so far in words ("undecided" until decided).
    fn decided_text(&self) -> String {
        match &self.decided {
            Some((o, when)) => format!("{}: {} (t = {when:.3} s)", o.name(), o.reason()),
            None => "undecided".into(),
        }
    }

    /// The outcome a run ending now with `end` has, and its time, s.
    pub fn outcome(&self, end: &End) -> (Outcome, f64) {
        let t = self.time();
        match end {
            End::Interrupted => (
                Outcome::Interrupted(format!(
                    "interrupted at t = {t:.3} s of {:.3} s",
                    self.sc.duration
                )),
                t,
            ),
            End::ByOperator => (
                Outcome::EndedByOperator(format!(
                    "ended by the operator at t = {t:.3} s; the scenario's outcome: {}",
                    self.decided_text()
                )),
                t,
            ),
            End::Reset => (
                Outcome::EndedByOperator(format!(
                    "reset at t = {t:.3} s (a new attempt began); the scenario's outcome: {}",
                    self.decided_text()
                )),
                t,
            ),
            End::Abandoned(grace) => (
                Outcome::EndedByOperator(format!(
                    "the driver's page left and no page came back within the {grace} s grace; \
                     ended at t = {t:.3} s; the scenario's outcome: {}",
                    self.decided_text()
                )),
                t,
            ),
            End::Stopped(why) => (Outcome::Failure(why.clone()), t),
            End::Reached => self.decided.clone().unwrap_or_else(|| match &self.course {
                Some(c) => (c.unfinished(t), t),
                None => (outcome::at_end(&self.sc.outcome, t), t),
            }),
        }
    }

    /// The run's one robot as a live front end reads it.
    pub fn view(&self) -> super::RunView<'_> {
        super::RunView {
            sim: self.sim(),
            scenario: &self.sc,
            samples: &self.samples,
            sensors: &self.sensors,
            decided: self.decided.as_ref(),
            course: self.course(),
        }
    }

    /// The course's score so far (`[course]`; `None` without one): what a HUD shows live.
    pub fn course(&self) -> Option<CourseScore> {
        self.course.as_ref().map(CourseTracker::score)
    }

    /// The course's score were the run to end now, as its `summary.json` would have it (a
    /// course still running is `not_completed`: [`CourseTracker::close`]).
    pub fn course_as_ended(&self) -> Option<CourseScore> {
        let mut c = self.course.clone()?;
        c.close();
        Some(c.score())
    }

    /// Starts again from the compiled scenario ([`Simulation::reset`]): the clock, the
    /// commands, the samples and the outcome. A course restarts too, with one reset fault
    /// more (the resets carry over: [`CourseTracker::reset`]).
    pub fn reset(&mut self, seed: Option<u64>) -> Result<()> {
        self.sim.reset(seed)?;
        if let Some(c) = &mut self.course {
            c.reset();
        }
        self.started = std::time::SystemTime::now();
        self.samples = SampleLog::from(vec![self.sim.sample()]);
        if !self.sensors.is_empty() {
            self.sensors = SensorSet::new(&self.sim, self.record);
        }
        self.decided = None;
        self.stepping = 0.0;
        self.wall = Instant::now();
        self.sampled = true;
        Ok(())
    }

    /// The run as it ended with `end`: its samples (the state now added if it was not the
    /// last sample), summary and outcome.
    pub fn finish(mut self, end: End) -> RunResult {
        self.take_result(&end)
    }

    /// A session's attempt ends with `end` (a reset, issue 43): its result as
    /// [`Runner::finish`] gives it, and the run starts again ([`Runner::reset`]) as the next
    /// attempt.
    pub fn end_attempt(&mut self, end: End) -> Result<RunResult> {
        let sensing = !self.sensors.is_empty();
        let result = self.take_result(&end);
        if sensing {
            self.sensors = SensorSet::new(&self.sim, self.record);
        }
        self.reset(None)?;
        Ok(result)
    }

    /// A live session was paused for `wall` of wall-clock time (simulated time stood still):
    /// pacing goes on from here at its speed, without catching up the pause in a burst.
    pub fn paused_for(&mut self, wall: Duration) {
        self.wall += wall;
    }

    /// The result of the run so far (see [`Runner::finish`]); the samples and sensor streams
    /// move into it.
    fn take_result(&mut self, end: &End) -> RunResult {
        if self.record && self.samples.last().is_some_and(|s| s.t < self.sim.time()) {
            self.samples.push(self.sim.sample());
        }
        let (outcome, t) = self.outcome(end);
        let times = WallTimes {
            stepping: self.stepping,
            elapsed: self.wall.elapsed().as_secs_f64(),
            paced: self.pace.is_some(),
            started: Some(self.started),
        };
        if let Some(c) = &mut self.course {
            c.close();
        }
        let mut summary = Summary::new(&self.sc, &self.sim, &self.samples, (&outcome, t), times);
        let sensors = std::mem::replace(&mut self.sensors, SensorSet::none()).into_streams();
        summary.sensors = sensors.iter().map(super::SensorSummary::of).collect();
        summary.course = self.course.as_ref().map(CourseTracker::score);
        summary.stopped = end.stopped().map(str::to_string);
        RunResult {
            samples: std::mem::take(&mut self.samples),
            track_names: self.sim.track_names().to_vec(),
            flipper_names: self.sim.flipper_names().to_vec(),
            summary,
            outcome,
            sensors,
            ruts: self.sim.ruts(),
            patches: self.sim.patch_changes().to_vec(),
        }
    }
}
