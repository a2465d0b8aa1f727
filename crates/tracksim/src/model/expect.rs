//! A scenario's compiled `[expect]` table ([`Expectation`]): ranges in SI units and radians.
//! The run layer checks a run against it (`run::expect`).

use crate::check::Checker;
use crate::spec::ExpectSpec;

/// A closed range `[min, max]`.
pub type Range = [f64; 2];

/// What a run of the scenario must show (`[expect]`); `None`: not checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Expectation {
    /// Outcome: `success`, `failure` or `completed`.
    pub outcome: Option<String>,
    /// Text the outcome reason must contain.
    pub reason_contains: Option<String>,
    /// Time the outcome was decided, s.
    pub outcome_time: Option<Range>,
    /// Final body x, m.
    pub final_x: Option<Range>,
    /// Final body y, m.
    pub final_y: Option<Range>,
    /// Final body z, m.
    pub final_z: Option<Range>,
    /// Final body yaw, rad.
    pub final_yaw: Option<Range>,
    /// Mean speed, m/s.
    pub mean_speed: Option<Range>,
    /// Progress along the start heading, m.
    pub progress: Option<Range>,
    /// Every loose box's final x, m.
    pub loose_box_final_x: Option<Range>,
    /// Every loose box's final z, m.
    pub loose_box_final_z: Option<Range>,
    /// Every conveyor's belt travel, m.
    pub conveyor_travel: Option<Range>,
    /// Repetitions of the course completed.
    pub course_repetitions: Option<Range>,
    /// Faults on the course (every kind).
    pub course_faults: Option<Range>,
    /// The course's score time (time plus penalties), s.
    pub course_score: Option<Range>,
}

impl Expectation {
    /// Whether the table asks for anything.
    pub fn is_empty(&self) -> bool {
        *self == Expectation::default()
    }
}

/// Checks `[expect]` (outcome names, finite ranges with min <= max) and compiles it.
pub(crate) fn compile_expect(c: &mut Checker, e: &ExpectSpec) -> Expectation {
    if let Some(o) = &e.outcome
        && !["success", "failure", "completed"].contains(&o.as_str())
    {
        c.push(
            "expect.outcome",
            format!("must be \"success\", \"failure\" or \"completed\", got {o:?}"),
        );
    }
    let mut range = |key: &str, r: Option<Range>, scale: f64| {
        let r = r?;
        c.finite(&format!("expect.{key}"), &r);
        if r[0] > r[1] {
            c.push(
                format!("expect.{key}"),
                format!(
                    "must be [min, max] with min <= max, got [{}, {}]",
                    r[0], r[1]
                ),
            );
        }
        Some([r[0] * scale, r[1] * scale])
    };
    Expectation {
        outcome: e.outcome.clone(),
        reason_contains: e.reason_contains.clone(),
        outcome_time: range("outcome_time_s", e.outcome_time_s, 1.0),
        final_x: range("final_x_m", e.final_x_m, 1.0),
        final_y: range("final_y_m", e.final_y_m, 1.0),
        final_z: range("final_z_m", e.final_z_m, 1.0),
        final_yaw: range("final_yaw_deg", e.final_yaw_deg, 1f64.to_radians()),
        mean_speed: range("mean_speed_mps", e.mean_speed_mps, 1.0),
        progress: range("progress_m", e.progress_m, 1.0),
        loose_box_final_x: range("loose_box_final_x_m", e.loose_box_final_x_m, 1.0),
        loose_box_final_z: range("loose_box_final_z_m", e.loose_box_final_z_m, 1.0),
        conveyor_travel: range("conveyor_travel_m", e.conveyor_travel_m, 1.0),
        course_repetitions: range("course_repetitions", e.course_repetitions, 1.0),
        course_faults: range("course_faults", e.course_faults, 1.0),
        course_score: range("course_score_s", e.course_score_s, 1.0),
    }
}
