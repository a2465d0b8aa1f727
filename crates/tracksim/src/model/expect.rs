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
    /// Bounds on an ensemble of perturbed runs (`ensemble_members`, `success_fraction`,
    /// `outcome_time_spread_s`); None: none given.
    pub ensemble: Option<EnsembleExpectation>,
}

/// Members of an ensemble when `[expect]` gives ensemble bounds without `ensemble_members`.
pub const DEFAULT_ENSEMBLE_MEMBERS: usize = 16;

/// What an ensemble of the scenario must show (issue 38; docs/ENSEMBLE.md).
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleExpectation {
    /// Members (2 or more).
    pub members: usize,
    /// Success fraction.
    pub success_fraction: Option<Range>,
    /// Spread (latest - earliest) of the success times, s.
    pub outcome_time_spread: Option<Range>,
}

impl Expectation {
    /// Whether the table asks for anything.
    pub fn is_empty(&self) -> bool {
        *self == Expectation::default()
    }
}

/// Most members `expect.ensemble_members` may ask for (each is a whole run).
const MAX_EXPECT_MEMBERS: usize = 256;

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
    let success_fraction = range("success_fraction", e.success_fraction, 1.0);
    let outcome_time_spread = range("outcome_time_spread_s", e.outcome_time_spread_s, 1.0);
    let ensemble = (e.ensemble_members.is_some()
        || success_fraction.is_some()
        || outcome_time_spread.is_some())
    .then(|| EnsembleExpectation {
        members: e.ensemble_members.unwrap_or(DEFAULT_ENSEMBLE_MEMBERS),
        success_fraction,
        outcome_time_spread,
    });
    let expectation = Expectation {
        ensemble,
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
    };
    if let Some([lo, hi]) = success_fraction
        && !((0.0..=1.0).contains(&lo) && (0.0..=1.0).contains(&hi))
    {
        c.push(
            "expect.success_fraction",
            format!("must lie within [0, 1], got [{lo}, {hi}]"),
        );
    }
    if let Some(n) = e.ensemble_members
        && !(2..=MAX_EXPECT_MEMBERS).contains(&n)
    {
        c.push(
            "expect.ensemble_members",
            format!("must be from 2 to {MAX_EXPECT_MEMBERS}, got {n}"),
        );
    }
    expectation
}
