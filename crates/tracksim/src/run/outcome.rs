//! How a run ends: the scenario's success and failure conditions checked on the state.

use crate::model::OutcomeModel;
use crate::world::Simulation;

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// A success condition was met.
    Success(String),
    /// A failure condition was met (tip-over, off the terrain, timeout).
    Failure(String),
    /// Ran to the end; no success condition was set.
    Completed,
    /// Stopped before its end from outside (Ctrl-C, SIGTERM): the reason says when.
    Interrupted(String),
    /// A live session the operator ended: the reason says when, and the scenario's own
    /// outcome if it was decided by then.
    EndedByOperator(String),
}

impl Outcome {
    /// "success", "failure", "completed", "interrupted" or "ended_by_operator".
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Success(_) => "success",
            Outcome::Failure(_) => "failure",
            Outcome::Completed => "completed",
            Outcome::Interrupted(_) => "interrupted",
            Outcome::EndedByOperator(_) => "ended_by_operator",
        }
    }

    /// Why, in words.
    pub fn reason(&self) -> String {
        match self {
            Outcome::Success(r)
            | Outcome::Failure(r)
            | Outcome::Interrupted(r)
            | Outcome::EndedByOperator(r) => r.clone(),
            Outcome::Completed => "ran to the end".into(),
        }
    }
}

/// Checks the outcome conditions at the current state; `None` while undecided.
pub fn check_outcome(o: &OutcomeModel, sim: &Simulation) -> Option<Outcome> {
    let p = sim.body_pose();
    if p.roll.abs() > o.max_tilt || p.pitch.abs() > o.max_tilt {
        return Some(Outcome::Failure(format!(
            "tipped over (roll {:.1} deg, pitch {:.1} deg, limit {:.1} deg)",
            p.roll.to_degrees(),
            p.pitch.to_degrees(),
            o.max_tilt.to_degrees()
        )));
    }
    if let Some(x) = o.success_x.filter(|x| p.x >= *x) {
        return Some(Outcome::Success(format!("body passed x = {x} m")));
    }
    if let Some(z) = o.success_z.filter(|z| p.z >= *z) {
        return Some(Outcome::Success(format!("body reached z = {z} m")));
    }
    if o.fail_off_terrain && sim.terrain_below(p.x, p.y).is_none() {
        return Some(Outcome::Failure(format!(
            "left the terrain at x = {:.3} m, y = {:.3} m",
            p.x, p.y
        )));
    }
    None
}

/// The outcome of a run that reached its end undecided: completed, or a timeout failure when
/// it had a success condition.
pub fn at_end(o: &OutcomeModel, t: f64) -> Outcome {
    match (o.success_x, o.success_z) {
        (None, None) => Outcome::Completed,
        _ => Outcome::Failure(format!("timeout: no success condition met in {t:.3} s")),
    }
}
