//! Scoring a course (`[course]`, [`CourseModel`]) as a run goes: the [`Runner`] updates a
//! [`CourseTracker`] at every output sample, so every front end (`run`, `drive`, `ros`, the
//! environments) scores it the same way; [`CourseScore`] is what a HUD shows live and what
//! `summary.json` holds. The rules (docs/COURSES.md), after the ASTM E54 practice:
//!
//! - the reference point is the body frame's origin (x, y, world frame);
//! - gates are passed in order; a waypoint when the point is within its radius, a gate line
//!   when the point's path between two samples crosses the line (within its width) in the
//!   line's direction (crossing it backwards does not count); a waypoint just passed does not
//!   count again until the point has left it (a one-gate course, a loop whose last gate is
//!   where it starts);
//! - a repetition ends when the last gate is passed; the next starts at gate 0 (put a start
//!   and finish line last: the vehicle starts on it);
//! - the time of a repetition is that of its last gate's sample less that of the previous
//!   repetition's end (0 for the first);
//! - faults: a tip-over (|roll| or |pitch| beyond `outcome.max_tilt_deg`, once per episode
//!   beyond it), a touch of a marked obstacle (once per contact episode: the sample it starts),
//!   a reset (`Runner::reset`: the course restarts with the simulation, the resets so far carry
//!   over);
//! - the course is finished when its repetitions are done (the run's outcome: success) or when
//!   the time passes the time limit (failure "time limit").
//!
//! Touches are found by an intersection query of each obstacle's box against the vehicle's
//! colliders (Rapier's query pipeline, filtered to the vehicle's collision group): a query
//! changes nothing in the physics.
//!
//! [`Runner`]: super::Runner

use super::Outcome;
use crate::check::{f, q};
use crate::model::{CourseModel, GateKind};
use crate::tracks::common::VEHICLE_GROUP;
use crate::world::Simulation;
use glam::{DQuat, DVec2};
use rapier3d::prelude::*;
use serde::Serialize;

/// Most events a score keeps (later ones are counted in the faults and repetitions but not
/// listed): a bound on what a long live session sends.
pub const MAX_COURSE_EVENTS: usize = 10_000;

/// Faults by kind (counts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FaultCounts {
    /// Resets by the operator.
    pub reset: u32,
    /// Tip-overs.
    pub tip_over: u32,
    /// Touches of marked obstacles.
    pub touch: u32,
}

impl FaultCounts {
    /// Every fault.
    pub fn total(&self) -> u32 {
        self.reset + self.tip_over + self.touch
    }
}

/// Something that happened on the course.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CourseEvent {
    /// Simulated time of the sample it was seen at, s.
    pub t_s: f64,
    /// `gate`, `repetition`, `fault` or `finished`.
    pub kind: &'static str,
    /// In words (which gate, repetition time, which fault).
    pub detail: String,
    /// A fault's kind: `reset`, `tip_over` or `touch` (absent for other events), so that a
    /// replay counts the faults up to any time without reading `detail`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fault: Option<&'static str>,
    /// A fault's penalty, s (the course's `penalty_s` of its kind; absent for other events).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub penalty_s: Option<f64>,
}

/// The compact score: what a table of sessions lists.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ScoreSummary {
    /// Repetitions completed.
    pub repetitions: u32,
    /// Time of the trial, s: to the end of the last repetition once finished, else elapsed.
    pub time_s: f64,
    /// Faults of every kind.
    pub faults: u32,
    /// Penalty time of the faults, s.
    pub penalty_s: f64,
    /// `time_s + penalty_s`, s (lower is better).
    pub score_s: f64,
}

/// A course's score so far (`summary.json` `course`, the live page's `course`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CourseScore {
    /// The course's name.
    pub name: String,
    /// Index of the gate to pass next (0-based).
    pub next_gate: usize,
    /// Gates passed since the start (or the last reset), every repetition's.
    pub gates_passed: u32,
    /// Gates of one repetition.
    pub gates_total: usize,
    /// The repetition under way (1-based; the last one once finished).
    pub repetition: u32,
    /// Repetitions completed.
    pub repetitions_done: u32,
    /// Repetitions to complete.
    pub repetitions_required: u32,
    /// Time of each completed repetition, s.
    pub rep_times_s: Vec<f64>,
    /// Simulated time since the start (or the last reset), s.
    pub elapsed_s: f64,
    /// The time limit, s (absent: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_limit_s: Option<f64>,
    /// Faults by kind.
    pub faults: FaultCounts,
    /// Penalty time of the faults, s.
    pub penalty_s: f64,
    /// Whether the course is finished (completed or out of time).
    pub finished: bool,
    /// `running`, `completed`, `time_limit` or `not_completed` (the run ended first).
    pub status: &'static str,
    /// The compact score.
    pub score: ScoreSummary,
    /// What happened, in order (at most [`MAX_COURSE_EVENTS`]).
    pub events: Vec<CourseEvent>,
}

/// Scores a course during a run (module docs).
#[derive(Clone, Debug)]
pub struct CourseTracker {
    model: CourseModel,
    /// Tip-over limit on |roll| and |pitch|, rad.
    max_tilt: f64,
    next: usize,
    /// The gate passed last while the point has not yet left it (waypoints).
    just_passed: Option<usize>,
    passed: u32,
    rep_times: Vec<f64>,
    last_rep_end: f64,
    prev: Option<DVec2>,
    tipped: bool,
    touching: Vec<bool>,
    faults: FaultCounts,
    /// Simulated time since the attempt's start, s.
    elapsed: f64,
    /// The simulated time the attempt started at, s (0; a reset of one robot in a world that
    /// goes on: the reset's time, [`CourseTracker::reset_at`]).
    start: f64,
    /// The time of the last sample scored, s (also once the course is decided).
    last_t: f64,
    status: &'static str,
    events: Vec<CourseEvent>,
}

impl CourseTracker {
    /// A tracker at the start of `model`, with the scenario's tip-over limit `max_tilt` rad.
    pub fn new(model: &CourseModel, max_tilt: f64) -> Self {
        CourseTracker {
            model: model.clone(),
            max_tilt,
            next: 0,
            just_passed: None,
            passed: 0,
            rep_times: Vec::new(),
            last_rep_end: 0.0,
            prev: None,
            tipped: false,
            touching: vec![false; model.obstacles.len()],
            faults: FaultCounts::default(),
            elapsed: 0.0,
            start: 0.0,
            last_t: 0.0,
            status: "running",
            events: Vec::new(),
        }
    }

    /// The course.
    pub fn model(&self) -> &CourseModel {
        &self.model
    }

    fn event(&mut self, t: f64, kind: &'static str, detail: String) {
        self.push(CourseEvent {
            t_s: t,
            kind,
            detail,
            fault: None,
            penalty_s: None,
        });
    }

    /// A fault event of kind `fault` (`reset`, `tip_over`, `touch`) with its penalty, s.
    fn fault_event(&mut self, t: f64, fault: &'static str, detail: String) {
        let p = &self.model.penalties;
        let penalty = match fault {
            "reset" => p.reset,
            "tip_over" => p.tip_over,
            _ => p.touch,
        };
        self.push(CourseEvent {
            t_s: t,
            kind: "fault",
            detail,
            fault: Some(fault),
            penalty_s: Some(penalty),
        });
    }

    fn push(&mut self, e: CourseEvent) {
        if self.events.len() < MAX_COURSE_EVENTS {
            self.events.push(e);
        }
    }

    /// Whether the course is finished (completed or out of time).
    pub fn finished(&self) -> bool {
        matches!(self.status, "completed" | "time_limit")
    }

    /// Scores the state of `sim` at its sample time `t` s.
    pub fn update(&mut self, sim: &Simulation, t: f64) {
        self.last_t = t;
        if self.finished() {
            return;
        }
        self.elapsed = t - self.start;
        let p = sim.body_pose();
        let at = DVec2::new(p.x, p.y);
        self.gates(at, t);
        self.prev = Some(at);
        let tilt = p.roll.abs().max(p.pitch.abs());
        if tilt > self.max_tilt && !self.tipped {
            self.faults.tip_over += 1;
            self.fault_event(
                t,
                "tip_over",
                format!(
                    "tip-over (roll {:.1} deg, pitch {:.1} deg)",
                    p.roll.to_degrees(),
                    p.pitch.to_degrees()
                ),
            );
        }
        self.tipped = tilt > self.max_tilt;
        for i in 0..self.model.obstacles.len() {
            let now = touches(sim, &self.model.obstacles[i]);
            if now && !self.touching[i] {
                self.faults.touch += 1;
                let name = self.model.obstacles[i].name.clone();
                self.fault_event(t, "touch", format!("touched {name}"));
            }
            self.touching[i] = now;
        }
        if self.status == "running"
            && self
                .model
                .time_limit
                .is_some_and(|l| self.elapsed > l + 1e-9)
        {
            self.status = "time_limit";
            let detail = format!(
                "time limit of {} s passed: {} of {} repetitions",
                self.model.time_limit.unwrap_or(0.0),
                self.rep_times.len(),
                self.model.repetitions
            );
            self.event(t, "finished", detail);
        }
    }

    /// Passes the gates the point reached on its way from the last sample to `at`.
    fn gates(&mut self, at: DVec2, t: f64) {
        if let Some(j) = self.just_passed
            && let GateKind::Waypoint { radius } = self.model.gates[j].kind
        {
            let g = &self.model.gates[j];
            if at.distance(DVec2::new(g.x, g.y)) > radius {
                self.just_passed = None;
            }
        }
        for _ in 0..self.model.gates.len() {
            if self.status != "running" || !self.passes(self.next, at) {
                break;
            }
            let i = self.next;
            self.event(t, "gate", format!("gate {i} passed"));
            self.passed += 1;
            self.just_passed = Some(i);
            self.next += 1;
            if self.next == self.model.gates.len() {
                self.next = 0;
                let rep = t - self.last_rep_end;
                self.last_rep_end = t;
                self.rep_times.push(rep);
                let n = self.rep_times.len();
                self.event(t, "repetition", format!("repetition {n} in {rep:.2} s"));
                if n as u32 >= self.model.repetitions {
                    self.status = "completed";
                    let detail = format!("completed {n} repetitions in {:.2} s", t - self.start);
                    self.event(t, "finished", detail);
                }
            }
        }
    }

    /// Whether the point, now at `at`, passes gate `i`.
    fn passes(&self, i: usize, at: DVec2) -> bool {
        let g = &self.model.gates[i];
        let c = DVec2::new(g.x, g.y);
        match g.kind {
            GateKind::Waypoint { radius } => {
                self.just_passed != Some(i) && at.distance(c) <= radius
            }
            GateKind::Line { width, yaw } => {
                let Some(prev) = self.prev else {
                    return false;
                };
                let n = DVec2::new(yaw.cos(), yaw.sin());
                let (d0, d1) = ((prev - c).dot(n), (at - c).dot(n));
                if !(d0 < 0.0 && d1 >= 0.0) {
                    return false;
                }
                let cross = prev + (at - prev) * (-d0 / (d1 - d0));
                (cross - c).perp_dot(n).abs() <= 0.5 * width
            }
        }
    }

    /// Counts a reset (the operator's, `Runner::reset`) and restarts the course: gates,
    /// repetitions, time and the other faults start again with the simulation; the resets so
    /// far carry over (with their penalty).
    pub fn reset(&mut self) {
        self.reset_at(0.0);
    }

    /// [`CourseTracker::reset`] of an attempt that starts at simulated time `t0` s (one robot
    /// reset in a world whose clock goes on: `TeamRunner::reset_robot`): its time, time limit
    /// and repetitions count from `t0`; its events keep the world's times.
    pub fn reset_at(&mut self, t0: f64) {
        let resets = self.faults.reset + 1;
        // The world's time of the reset and the attempt's own time then: its course clock
        // stops once the course is decided (a time limit), so it is counted to the last sample
        // here (issue 63: a reset at 56.26 s of a session was reported "at t = 30.01 s").
        let at = self.last_t.max(t0);
        let before = at - self.start;
        *self = CourseTracker::new(&self.model, self.max_tilt);
        self.faults.reset = resets;
        self.start = t0;
        self.last_rep_end = t0;
        self.fault_event(
            t0,
            "reset",
            format!(
                "reset {resets} at t = {at:.2} s ({before:.2} s into the previous attempt): the \
                 course restarts"
            ),
        );
    }

    /// The run's outcome once the course decides it: success when completed, failure when
    /// out of time; `None` while running.
    pub fn outcome(&self) -> Option<Outcome> {
        let s = self.score();
        let faults = format!("{} faults, {:.1} s penalty", s.faults.total(), s.penalty_s);
        match self.status {
            "completed" => Some(Outcome::Success(format!(
                "course completed: {} repetitions in {:.2} s, {faults}: score {:.2} s",
                s.repetitions_done, s.score.time_s, s.score.score_s
            ))),
            "time_limit" => Some(Outcome::Failure(format!(
                "time limit: {} of {} repetitions in {} s, {faults}",
                s.repetitions_done,
                s.repetitions_required,
                s.time_limit_s.unwrap_or(0.0)
            ))),
            _ => None,
        }
    }

    /// The outcome of a run that ended at `t` s with the course unfinished.
    pub fn unfinished(&self, t: f64) -> Outcome {
        Outcome::Failure(format!(
            "course not completed: {} of {} repetitions, next gate {} of {}, in {t:.2} s",
            self.rep_times.len(),
            self.model.repetitions,
            self.next,
            self.model.gates.len()
        ))
    }

    /// Marks a course still running as `not_completed` (the run ended first).
    pub fn close(&mut self) {
        if self.status == "running" {
            self.status = "not_completed";
        }
    }

    /// The score so far.
    pub fn score(&self) -> CourseScore {
        let p = &self.model.penalties;
        let f = self.faults;
        let penalty = f64::from(f.reset) * p.reset
            + f64::from(f.tip_over) * p.tip_over
            + f64::from(f.touch) * p.touch;
        let done = self.rep_times.len() as u32;
        let time = if self.status == "completed" {
            self.last_rep_end - self.start
        } else {
            self.elapsed
        };
        CourseScore {
            name: self.model.name.clone(),
            next_gate: self.next,
            gates_passed: self.passed,
            gates_total: self.model.gates.len(),
            repetition: (done + 1).min(self.model.repetitions),
            repetitions_done: done,
            repetitions_required: self.model.repetitions,
            rep_times_s: self.rep_times.clone(),
            elapsed_s: self.elapsed,
            time_limit_s: self.model.time_limit,
            faults: f,
            penalty_s: penalty,
            finished: self.finished(),
            status: self.status,
            score: ScoreSummary {
                repetitions: done,
                time_s: time,
                faults: f.total(),
                penalty_s: penalty,
                score_s: time + penalty,
            },
            events: self.events.clone(),
        }
    }
}

/// Whether marked obstacle `o` intersects a collider of the vehicle: one intersection query
/// of its box against the colliders of the vehicle's collision group (nothing is changed).
fn touches(sim: &Simulation, o: &crate::model::CourseObstacle) -> bool {
    let pose = Pose::from_parts(f(o.centre - sim.origin()), q(DQuat::from_rotation_z(o.yaw)));
    let shape = Cuboid::new(f(o.half));
    let groups = InteractionGroups::new(Group::ALL, VEHICLE_GROUP, InteractionTestMode::And);
    let qp = sim
        .world
        .query_pipeline_with_filter(QueryFilter::default().groups(groups));
    qp.intersect_shape(pose, &shape).next().is_some()
}
