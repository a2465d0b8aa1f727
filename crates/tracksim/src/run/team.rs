//! Several robots run in one world (`[[vehicles]]`, issue 40): [`TeamRunner`] steps the world
//! with each robot's `[[commands]]`, updates each robot's sensors, records each robot's samples
//! and decides each robot's outcome at every output interval, and the world's by its rule
//! ([`TeamRule`]); [`TeamResult`] holds a [`RunResult`] per robot (what a one-robot run gives,
//! so every one-robot output is written per robot) and the world's outcome.

use super::course::CourseTracker;
use super::outcome::{Outcome, at_end, check_outcome};
use super::runner::End;
use super::summary::{Summary, WallTimes};
use super::timeline::Timeline;
use super::view::RunView;
use super::{RunOptions, RunResult, SensorSummary};
use crate::error::{Error, Result};
use crate::model::{Scenario, TeamRule};
use crate::sensors::SensorSet;
use crate::world::Simulation;
use std::sync::Arc;
use std::time::Instant;

/// One robot of a team run: its own scenario, commands, sensors, samples and outcome.
struct RobotRun {
    view: Arc<Scenario>,
    timeline: Timeline,
    sensors: SensorSet,
    samples: super::SampleLog,
    decided: Option<(Outcome, f64)>,
    course: Option<CourseTracker>,
    /// The attempts a reset of this robot ended (`reset = true`), in order.
    attempts: Vec<RunResult>,
}

/// A run of a world with several robots.
pub struct TeamRunner {
    sim: Simulation,
    robots: Vec<RobotRun>,
    rule: TeamRule,
    /// Stop once the world's outcome is decided (the file's `outcome.stop`).
    stop: bool,
    every: u64,
    /// Steps to the end of the duration (`None`: no end, a live session).
    end_step: Option<u64>,
    /// Apply each robot's `[[commands]]` (false: controls come only from the caller).
    commands: bool,
    /// Whether the last step reached an output interval.
    sampled: bool,
    decided: Option<(Outcome, f64)>,
    stepping: f64,
    wall: Instant,
    started: std::time::SystemTime,
    pace: Option<f64>,
}

/// What a team run produced: each robot's run, in file order, and the world's outcome.
#[derive(Clone, Debug)]
pub struct TeamResult {
    /// Each robot's name and run (its samples, summary, outcome, sensors).
    pub robots: Vec<(String, RunResult)>,
    /// The world's outcome by its rule.
    pub outcome: Outcome,
    /// When the world's outcome was decided (or the run ended), s.
    pub outcome_time: f64,
    /// The rule that decided it.
    pub rule: TeamRule,
    /// The robots' race or team score on the scenario's course (`None` without `[course]`).
    pub standings: Option<super::Standings>,
    /// Each robot's attempts that a reset of it ended (a `reset = true` entry, issue 43), in
    /// order, by robot index (empty: never reset); `robots` holds each robot's last attempt,
    /// whose summary lists them all (`attempts`). Times are the world's: an attempt after a
    /// reset at t s starts at t.
    pub attempts: Vec<Vec<RunResult>>,
    /// Why the world stopped before its end, when it did ([`End::Stopped`]: a blow-up, or
    /// robots further apart than one world holds): every robot's run holds what was
    /// simulated up to there (issue 59).
    pub stopped: Option<String>,
}

impl TeamRunner {
    /// A run of `sc` (a scenario with [`Scenario::team`]) with every robot's commands.
    pub fn new(sc: &Scenario) -> Result<Self> {
        let team = sc
            .team
            .as_ref()
            .ok_or_else(|| Error::Build("a team run needs a scenario with [[vehicles]]".into()))?;
        let sc = Arc::new(sc.clone());
        let mut sim = Simulation::from_shared(sc.clone())?;
        let robots = robot_runs(&mut sim, true);
        let dt = sc.solver.dt;
        Ok(TeamRunner {
            every: ((sc.output_interval / dt).round() as u64).max(1),
            end_step: Some((sc.duration / dt).round().max(1.0) as u64),
            rule: team.rule,
            stop: team.stop,
            sim,
            robots,
            commands: true,
            sampled: true,
            decided: None,
            stepping: 0.0,
            wall: Instant::now(),
            started: std::time::SystemTime::now(),
            pace: None,
        })
    }

    /// Paces the run to the wall clock at `speed` simulated seconds per wall second.
    pub fn paced(mut self, speed: f64) -> Self {
        self.pace = Some(speed);
        self
    }

    /// Controls come only from the caller ([`TeamRunner::apply`]): no robot's `[[commands]]`
    /// are applied (a live session).
    pub fn without_commands(mut self) -> Self {
        self.commands = false;
        for r in &mut self.robots {
            r.timeline = Timeline::new(&[]);
        }
        self
    }

    /// Runs on past the duration until the caller stops (a live session); outcomes are
    /// decided but never stop the run.
    pub fn unbounded(mut self) -> Self {
        self.end_step = None;
        self.stop = false;
        self
    }

    /// Applies the caller's controls to robot `k` before the next step (a `reset` in them is
    /// not applied: [`TeamRunner::apply_controls`]).
    pub fn apply(&mut self, k: usize, c: &crate::model::Controls) {
        self.sim.select(k);
        self.sim.apply(c);
        self.sim.select(0);
    }

    /// Applies controls `c` to robot `k` as a `[[vehicles.commands]]` entry is applied: its
    /// reset first ([`TeamRunner::reset_robot`]), then the rest.
    pub fn apply_controls(&mut self, k: usize, c: &crate::model::Controls) -> Result<()> {
        if c.reset {
            self.reset_robot(k)?;
        }
        self.apply(k, c);
        Ok(())
    }

    /// Puts robot `k` back at its start while the world and the other robots go on
    /// ([`Simulation::reset_robot`]): its attempt so far ends (kept, with the outcome
    /// `ended_by_operator`, "reset at t = ..."), and a new one begins at this time: its samples
    /// from the start pose, its sensors, outcome and course afresh (a course counts the reset
    /// as a fault, as a one-robot session's does). Its remaining commands go on.
    pub fn reset_robot(&mut self, k: usize) -> Result<()> {
        let t = self.sim.time();
        let times = self.wall_times();
        self.sim.select(k);
        let ended = take_robot_result(&mut self.sim, &mut self.robots[k], &End::Reset, t, times);
        let reset = self.sim.reset_robot();
        if reset.is_ok() {
            let r = &mut self.robots[k];
            r.attempts.push(ended);
            r.sensors = SensorSet::new(&self.sim, true);
            r.samples = super::SampleLog::from(vec![self.sim.sample()]);
            r.decided = None;
            if let Some(c) = &mut r.course {
                c.reset_at(t);
            }
        }
        self.sim.select(0);
        reset
    }

    fn wall_times(&self) -> WallTimes {
        WallTimes {
            stepping: self.stepping,
            elapsed: self.wall.elapsed().as_secs_f64(),
            paced: self.pace.is_some(),
            started: Some(self.started),
        }
    }

    /// Robot `k`'s scenario (the world with it as its one robot).
    pub fn robot_scenario(&self, k: usize) -> &Scenario {
        &self.robots[k].view
    }

    /// Robot `k` as a live front end reads it (selects it in the world).
    pub fn view(&mut self, k: usize) -> RunView<'_> {
        self.sim.select(k);
        let r = &self.robots[k];
        RunView {
            sim: &self.sim,
            scenario: &r.view,
            samples: &r.samples,
            sensors: &r.sensors,
            decided: r.decided.as_ref(),
            course: r.course.as_ref().map(CourseTracker::score),
        }
    }

    /// Robot `k`'s outcome if the run ended now with `end`, and its time, s.
    pub fn robot_outcome(&self, k: usize, end: &End) -> (Outcome, f64) {
        robot_outcome(&self.robots[k], end, self.sim.time())
    }

    /// The robots' race or team score on the course so far (`None` without `[course]`).
    pub fn standings(&self) -> Option<super::Standings> {
        let names = self.names();
        let scores: Vec<_> = names
            .into_iter()
            .zip(&self.robots)
            .map(|(n, r)| (n, r.course.as_ref().map(CourseTracker::score)))
            .collect();
        super::Standings::of(self.rule, &scores)
    }

    /// Whether the last step reached an output interval (true before the first step).
    pub fn at_sample(&self) -> bool {
        self.sampled
    }

    /// Wall-clock seconds since the start (or the last reset).
    pub fn wall_elapsed(&self) -> f64 {
        self.wall.elapsed().as_secs_f64()
    }

    /// A live session was paused for `wall` of wall-clock time: pacing goes on from here,
    /// without catching up the pause in a burst.
    pub fn paused_for(&mut self, wall: std::time::Duration) {
        self.wall += wall;
    }

    /// Wall-clock seconds spent stepping.
    pub fn stepping(&self) -> f64 {
        self.stepping
    }

    /// Starts every robot again from the scenario ([`Simulation::reset`]): the clock, the
    /// commands, the samples and the outcomes (a course keeps its reset count, as a one-robot
    /// run's does).
    pub fn reset(&mut self) -> Result<()> {
        self.sim.reset(None)?;
        let mut fresh = robot_runs(&mut self.sim, self.commands);
        for (r, f) in self.robots.iter_mut().zip(&mut fresh) {
            if let Some(mut c) = r.course.take() {
                c.reset();
                f.course = Some(c);
            }
        }
        self.robots = fresh;
        self.decided = None;
        self.stepping = 0.0;
        self.wall = Instant::now();
        self.started = std::time::SystemTime::now();
        self.sampled = true;
        Ok(())
    }

    /// The running world.
    pub fn sim(&self) -> &Simulation {
        &self.sim
    }

    /// The world's outcome and its time, s, once decided.
    pub fn decided(&self) -> Option<&(Outcome, f64)> {
        self.decided.as_ref()
    }

    /// Robot `k`'s outcome and its time, s, once decided.
    pub fn robot_decided(&self, k: usize) -> Option<&(Outcome, f64)> {
        self.robots[k].decided.as_ref()
    }

    /// Whether the run has reached its end: its duration, or the world's decided outcome when
    /// the file's `outcome.stop` says to stop there.
    pub fn finished(&self) -> bool {
        self.end_step.is_some_and(|e| self.sim.steps() >= e)
            || (self.stop && self.decided.is_some())
    }

    /// Advances one step: every robot's commands that have fallen due, the world's step, every
    /// robot's sensors, and at an output interval every robot's sample and outcome and the
    /// world's.
    pub fn step(&mut self) -> Result<()> {
        if let Some(speed) = self.pace {
            let ahead = self.sim.time() / speed - self.wall.elapsed().as_secs_f64();
            if ahead > 0.002 {
                std::thread::sleep(std::time::Duration::from_secs_f64(ahead));
            }
        }
        let t0 = Instant::now();
        let t = self.sim.time();
        // In the world's build order, not the file's (`Simulation::build_order`).
        for i in 0..self.robots.len() {
            let k = self.sim.build_order()[i];
            let due = self.robots[k].timeline.due(t);
            for c in due {
                self.apply_controls(k, &c)?;
            }
        }
        self.sim.select(0);
        self.sim.step()?;
        for (k, r) in self.robots.iter_mut().enumerate() {
            self.sim.select(k);
            r.sensors.update(&self.sim);
        }
        self.stepping += t0.elapsed().as_secs_f64();
        let i = self.sim.steps();
        self.sampled = i.is_multiple_of(self.every) || self.end_step == Some(i);
        if self.sampled {
            let now = self.sim.time();
            for (k, r) in self.robots.iter_mut().enumerate() {
                self.sim.select(k);
                if let Some(c) = &mut r.course {
                    c.update(&self.sim, now);
                }
                if r.decided.is_none() {
                    let course = || r.course.as_ref().and_then(CourseTracker::outcome);
                    r.decided = check_outcome(&r.view.outcome, &self.sim)
                        .or_else(course)
                        .map(|o| (o, now));
                }
                r.samples.push(self.sim.sample());
            }
            self.sim.select(0);
            if self.decided.is_none() {
                let outcomes: Vec<_> = self.robots.iter().map(|r| r.decided.clone()).collect();
                self.decided = decide(self.rule, &self.names(), &outcomes, false);
            }
        }
        Ok(())
    }

    fn names(&self) -> Vec<String> {
        self.sim.robot_names()
    }

    /// Steps to the end ([`TeamRunner::finished`]); `stop` is asked before every step.
    pub fn run_to_end(&mut self, stop: impl Fn() -> bool) -> Result<bool> {
        while !self.finished() {
            if stop() {
                return Ok(false);
            }
            self.step()?;
        }
        Ok(true)
    }

    /// The run as it ended with `end`: each robot's [`RunResult`] (its outcome: decided, or
    /// at the end by its own conditions; a live session's end for every robot) and the
    /// world's outcome.
    pub fn finish(mut self, end: End) -> TeamResult {
        let reached = matches!(end, End::Reached);
        let t = self.sim.time();
        let times = self.wall_times();
        let names = self.names();
        let mut finals = Vec::new();
        let mut robots = Vec::new();
        let mut attempts = Vec::new();
        for (k, mut r) in std::mem::take(&mut self.robots).into_iter().enumerate() {
            self.sim.select(k);
            let mut last = take_robot_result(&mut self.sim, &mut r, &end, t, times);
            finals.push(Some((last.outcome.clone(), last.summary.outcome_time_s)));
            let mut kept = std::mem::take(&mut r.attempts);
            list_attempts(&mut last, &mut kept);
            robots.push((names[k].clone(), last));
            attempts.push(kept);
        }
        self.sim.select(0);
        let (outcome, outcome_time) = match (self.decided.take(), reached) {
            (d, _) if operator(&end).is_some() => (operator_outcome(&end, t, d.as_ref()), t),
            (None, _) if end.stopped().is_some() => (
                Outcome::Failure(end.stopped().unwrap_or_default().into()),
                t,
            ),
            (Some(d), _) => d,
            (None, true) => {
                decide(self.rule, &names, &finals, true).unwrap_or((Outcome::Completed, t))
            }
            (None, false) => (
                Outcome::Interrupted(format!("interrupted at t = {t:.3} s")),
                t,
            ),
        };
        let scores: Vec<_> = robots
            .iter()
            .map(|(n, r): &(String, RunResult)| (n.clone(), r.summary.course.clone()))
            .collect();
        TeamResult {
            standings: super::Standings::of(self.rule, &scores),
            attempts,
            robots,
            outcome,
            outcome_time,
            rule: self.rule,
            stopped: end.stopped().map(str::to_string),
        }
    }
}

/// Robot `r`'s run so far as it ends with `end` at `t` s (the selected robot of `sim`): its
/// samples (the state now added if it was not the last sample), summary, outcome and sensor
/// streams move into the result; its course is closed.
fn take_robot_result(
    sim: &mut Simulation,
    r: &mut RobotRun,
    end: &End,
    t: f64,
    times: WallTimes,
) -> RunResult {
    let (outcome, when) = robot_outcome(r, end, t);
    if let Some(c) = &mut r.course {
        c.close();
    }
    let mut samples = std::mem::take(&mut r.samples);
    if samples.last().is_some_and(|s| s.t < t) {
        samples.push(sim.sample());
    }
    let mut summary = Summary::new(&r.view, sim, &samples, (&outcome, when), times);
    let sensors = std::mem::replace(&mut r.sensors, SensorSet::none()).into_streams();
    summary.sensors = sensors.iter().map(SensorSummary::of).collect();
    summary.course = r.course.as_ref().map(CourseTracker::score);
    summary.stopped = end.stopped().map(str::to_string);
    RunResult {
        samples,
        track_names: sim.track_names().to_vec(),
        flipper_names: sim.flipper_names().to_vec(),
        summary,
        outcome,
        sensors,
        ruts: Vec::new(),
        patches: sim.patch_changes().to_vec(),
    }
}

/// A robot reset during the run: every summary (its last attempt's, `last`, and each of the
/// `kept` ones a reset ended) lists all its attempts ([`super::AttemptRecord`]; kept in
/// `attempts/N`, the last in the robot's folder). Nothing for a robot never reset.
fn list_attempts(last: &mut RunResult, kept: &mut [RunResult]) {
    if kept.is_empty() {
        return;
    }
    let mut list: Vec<_> = kept
        .iter()
        .enumerate()
        .map(|(i, r)| super::AttemptRecord::of(i + 1, super::attempt_folder(i + 1), "reset", r))
        .collect();
    list.push(super::AttemptRecord::of(
        kept.len() + 1,
        ".".into(),
        "the run's end",
        last,
    ));
    for r in kept.iter_mut() {
        r.summary.attempts.clone_from(&list);
    }
    last.summary.attempts = list;
}

/// Robot `r`'s outcome when the run ends with `end` at `t` s: its decided one (a live
/// session's end by the operator says it), or at the end by its own conditions.
fn robot_outcome(r: &RobotRun, end: &End, t: f64) -> (Outcome, f64) {
    match (&r.decided, end) {
        _ if operator(end).is_some() => (operator_outcome(end, t, r.decided.as_ref()), t),
        (Some(d), _) => d.clone(),
        (None, End::Reached) => (at_end(&r.view.outcome, t), t),
        (None, End::Stopped(why)) => (Outcome::Failure(why.clone()), t),
        (None, _) => (
            Outcome::Interrupted(format!("interrupted at t = {t:.3} s")),
            t,
        ),
    }
}

/// Each robot's run state at the start: timelines (empty unless `commands`), sensors, the
/// first sample, a course tracker.
fn robot_runs(sim: &mut Simulation, commands: bool) -> Vec<RobotRun> {
    let mut robots = Vec::new();
    for k in 0..sim.robot_count() {
        sim.select(k);
        let view = Arc::new(sim.scenario().clone());
        robots.push(RobotRun {
            timeline: Timeline::new(if commands { &view.commands } else { &[] }),
            sensors: SensorSet::new(sim, true),
            samples: super::SampleLog::from(vec![sim.sample()]),
            decided: None,
            attempts: Vec::new(),
            course: view
                .course
                .as_ref()
                .map(|c| CourseTracker::new(c, view.outcome.max_tilt)),
            view,
        });
    }
    sim.select(0);
    robots
}

/// The words of a live session's end by the operator (`None`: not such an end).
fn operator(end: &End) -> Option<String> {
    match end {
        End::ByOperator => Some("ended by the operator".into()),
        End::Reset => Some("reset (a new attempt began)".into()),
        End::Abandoned(grace) => Some(format!(
            "every driver's page left and none came back within the {grace} s grace; ended"
        )),
        _ => None,
    }
}

/// The outcome of a session ended by the operator at `t` s, saying the outcome `decided` so
/// far.
fn operator_outcome(end: &End, t: f64, decided: Option<&(Outcome, f64)>) -> Outcome {
    let so_far = match decided {
        Some((o, when)) => format!("{}: {} (t = {when:.3} s)", o.name(), o.reason()),
        None => "undecided".into(),
    };
    Outcome::EndedByOperator(format!(
        "{} at t = {t:.3} s; the scenario's outcome: {so_far}",
        operator(end).unwrap_or_default()
    ))
}

/// The world's outcome from its robots' (`None`: undecided) by `rule`; `at_end`: every robot's
/// is final (the run reached its end), so a race nobody won is lost and a team whose robots all
/// completed has completed.
pub fn decide(
    rule: TeamRule,
    names: &[String],
    outcomes: &[Option<(Outcome, f64)>],
    at_end: bool,
) -> Option<(Outcome, f64)> {
    let of = |pred: fn(&Outcome) -> bool| {
        outcomes
            .iter()
            .zip(names)
            .filter_map(|(o, n)| o.as_ref().filter(|(o, _)| pred(o)).map(|(o, t)| (n, o, *t)))
            .collect::<Vec<_>>()
    };
    let successes = of(|o| matches!(o, Outcome::Success(_)));
    let failures = of(|o| matches!(o, Outcome::Failure(_)));
    let last = |v: &[(&String, &Outcome, f64)]| v.iter().map(|x| x.2).fold(0.0, f64::max);
    let first = |v: &[(&String, &Outcome, f64)]| {
        v.iter()
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(n, o, t)| ((*n).clone(), o.reason(), *t))
    };
    let n = names.len();
    match rule {
        TeamRule::All => {
            if let Some((name, why, t)) = first(&failures) {
                Some((Outcome::Failure(format!("`{name}` failed: {why}")), t))
            } else if successes.len() == n {
                Some((
                    Outcome::Success(format!(
                        "every robot succeeded (the last at t = {:.3} s)",
                        last(&successes)
                    )),
                    last(&successes),
                ))
            } else if at_end
                && outcomes.iter().all(|o| {
                    matches!(
                        o,
                        Some((Outcome::Completed, _)) | Some((Outcome::Success(_), _))
                    )
                })
            {
                let t = outcomes.iter().flatten().map(|o| o.1).fold(0.0, f64::max);
                Some((Outcome::Completed, t))
            } else {
                None
            }
        }
        TeamRule::First => {
            if let Some((name, why, t)) = first(&successes) {
                Some((
                    Outcome::Success(format!("`{name}` finished first: {why}")),
                    t,
                ))
            } else if failures.len() == n {
                Some((
                    Outcome::Failure("every robot failed".to_string()),
                    last(&failures),
                ))
            } else if at_end {
                let t = outcomes.iter().flatten().map(|o| o.1).fold(0.0, f64::max);
                Some((Outcome::Failure("no robot finished".to_string()), t))
            } else {
                None
            }
        }
    }
}

/// Runs a scenario with several robots to its end ([`TeamRunner`]); a world that stops (a
/// blow-up, robots too far apart) is an error ([`run_team_kept`] keeps its runs).
pub fn run_team(sc: &Scenario, opts: RunOptions) -> Result<TeamResult> {
    match run_team_kept(sc, opts)? {
        (_, Some(e)) => Err(e),
        (result, None) => Ok(result),
    }
}

/// [`run_team`], keeping what was simulated when the world stops (a blow-up, robots spread
/// further apart than one world holds): every robot's run ends there ([`End::Stopped`]) and
/// the error comes back beside the result, for the caller to write the outputs and then
/// report it (issue 59).
pub fn run_team_kept(
    sc: &Scenario,
    opts: RunOptions,
) -> Result<(TeamResult, Option<crate::error::Error>)> {
    let mut runner = TeamRunner::new(sc)?;
    if opts.realtime {
        runner = runner.paced(1.0);
    }
    match runner.run_to_end(|| opts.stop_asked()) {
        Ok(true) => Ok((runner.finish(End::Reached), None)),
        Ok(false) => Ok((runner.finish(End::Interrupted), None)),
        Err(e) if e.stops_world() => Ok((runner.finish(End::Stopped(e.to_string())), Some(e))),
        Err(e) => Err(e),
    }
}

/// Every way a team run misses its file's expectations, one line each (empty: met): the
/// world's `[expect]` (outcome, reason, outcome time) and each robot's `[vehicles.expect]`,
/// named by its robot.
pub fn team_misses(sc: &Scenario, r: &TeamResult) -> Vec<String> {
    let mut misses = Vec::new();
    if let Some(team) = &sc.team {
        let e = &team.expect;
        if let Some(o) = &e.outcome
            && o != r.outcome.name()
        {
            misses.push(format!(
                "the world's outcome {} ({}) where {o} was expected",
                r.outcome.name(),
                r.outcome.reason()
            ));
        }
        if let Some(want) = &e.reason_contains
            && !r.outcome.reason().contains(want.as_str())
        {
            misses.push(format!(
                "the world's outcome reason {:?} does not contain {want:?}",
                r.outcome.reason()
            ));
        }
        if let Some([lo, hi]) = e.outcome_time
            && !(lo..=hi).contains(&r.outcome_time)
        {
            misses.push(format!(
                "the world's outcome time {:.3} s outside [{lo}, {hi}] s",
                r.outcome_time
            ));
        }
        for ((name, run), model) in r.robots.iter().zip(&team.robots) {
            misses.extend(
                super::check_expectations(&model.expect, run)
                    .into_iter()
                    .map(|m| format!("`{name}`: {m}")),
            );
        }
    }
    misses
}
