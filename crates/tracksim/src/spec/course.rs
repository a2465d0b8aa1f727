//! A scenario's `[course]` table: an operator-training course after the ASTM E54 practice for
//! response robots (docs/COURSES.md): gates or waypoints passed in order, a number of
//! repetitions, a time limit, the penalties of faults and marked obstacles not to be touched.
//! It changes nothing in the simulation: the run layer scores it (`run::course`).

use serde::{Deserialize, Serialize};

/// A course (`[course]`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CourseSpec {
    /// Name shown live and in `summary.json` (default `"course"`).
    #[serde(default)]
    pub name: Option<String>,
    /// The gates and waypoints, passed in this order; a repetition ends at the last one.
    pub gates: Vec<GateSpec>,
    /// Repetitions (laps) to complete, a whole number >= 1 (default 1).
    #[serde(default = "default_repetitions")]
    pub repetitions: u32,
    /// Time limit of the whole trial, s (default: none).
    #[serde(default)]
    pub time_limit_s: Option<f64>,
    /// Penalty time added to the score per fault, s (`[course.penalty_s]`).
    #[serde(default)]
    pub penalty_s: PenaltySpec,
    /// Marked obstacles the vehicle must not touch (`[[course.obstacles]]`).
    #[serde(default)]
    pub obstacles: Vec<CourseObstacleSpec>,
}

fn default_repetitions() -> u32 {
    1
}

/// A gate (`[[course.gates]]`): a waypoint (`radius_m`: the body's origin passes within it)
/// or a gate line (`width_m` and `yaw_deg`: crossed in the direction of its normal).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GateSpec {
    /// Centre x (world frame), m.
    pub x_m: f64,
    /// Centre y (world frame), m.
    pub y_m: f64,
    /// Radius of a waypoint, m (give this or `width_m`).
    #[serde(default)]
    pub radius_m: Option<f64>,
    /// Width of a gate line, m (give this or `radius_m`).
    #[serde(default)]
    pub width_m: Option<f64>,
    /// Direction a gate line is crossed in, degrees about z from +x (the line runs across it;
    /// only with `width_m`, default 0).
    #[serde(default)]
    pub yaw_deg: Option<f64>,
}

/// Penalty seconds per fault (`[course.penalty_s]`); each defaults to 0 (counted, not timed).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PenaltySpec {
    /// Per reset of the vehicle by the operator, s.
    #[serde(default)]
    pub reset: f64,
    /// Per tip-over (|roll| or |pitch| beyond `outcome.max_tilt_deg`), s.
    #[serde(default)]
    pub tip_over: f64,
    /// Per touch of a marked obstacle (counted once per contact), s.
    #[serde(default)]
    pub touch: f64,
}

/// A marked obstacle (`[[course.obstacles]]`): a box the vehicle must not touch. It is a
/// marked volume, not a solid: add a `[[terrain.boxes]]` at the same place to make it one.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CourseObstacleSpec {
    /// Name in the fault events (default `obstacle N`).
    #[serde(default)]
    pub name: Option<String>,
    /// Centre x (world frame), m.
    pub x_m: f64,
    /// Centre y, m.
    pub y_m: f64,
    /// Centre z, m.
    pub z_m: f64,
    /// Half extents along the box's axes, m.
    pub half_m: [f64; 3],
    /// Yaw of the box about z, degrees (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
}
