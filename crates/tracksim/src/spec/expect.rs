//! A scenario's `[expect]` table: what a run of the file must show to do what its description
//! says (issue 23). It changes nothing in the simulation; `run` prints whether it was met and
//! the bundled-scenario test runs every bundled file to its end against it, so a file can never
//! again silently stop doing what it says.

use serde::{Deserialize, Serialize};

/// Expected results of a run of the scenario (`[expect]`); every key is optional.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectSpec {
    /// The run's outcome: `success`, `failure` or `completed`.
    #[serde(default)]
    pub outcome: Option<String>,
    /// Text the outcome reason must contain (e.g. `timeout`, `tipped over`).
    #[serde(default)]
    pub reason_contains: Option<String>,
    /// Range of the time the outcome was decided, `[min, max]` s.
    #[serde(default)]
    pub outcome_time_s: Option<[f64; 2]>,
    /// Range of the body's final x (world frame), `[min, max]` m.
    #[serde(default)]
    pub final_x_m: Option<[f64; 2]>,
    /// Range of the body's final y, `[min, max]` m.
    #[serde(default)]
    pub final_y_m: Option<[f64; 2]>,
    /// Range of the body's final z, `[min, max]` m.
    #[serde(default)]
    pub final_z_m: Option<[f64; 2]>,
    /// Range of the body's final yaw, `[min, max]` degrees.
    #[serde(default)]
    pub final_yaw_deg: Option<[f64; 2]>,
    /// Range of the run's mean speed (`summary.json` `mean_speed_mps`), `[min, max]` m/s.
    #[serde(default)]
    pub mean_speed_mps: Option<[f64; 2]>,
    /// Range of the progress along the start heading, `[min, max]` m.
    #[serde(default)]
    pub progress_m: Option<[f64; 2]>,
    /// Range of every loose box's final x, `[min, max]` m.
    #[serde(default)]
    pub loose_box_final_x_m: Option<[f64; 2]>,
    /// Range of every loose box's final z, `[min, max]` m.
    #[serde(default)]
    pub loose_box_final_z_m: Option<[f64; 2]>,
    /// Range of every conveyor's belt travel over the run, `[min, max]` m.
    #[serde(default)]
    pub conveyor_travel_m: Option<[f64; 2]>,
    /// Range of the repetitions of the `[course]` completed, `[min, max]`.
    #[serde(default)]
    pub course_repetitions: Option<[f64; 2]>,
    /// Range of the course's faults (every kind), `[min, max]`.
    #[serde(default)]
    pub course_faults: Option<[f64; 2]>,
    /// Range of the course's score time (time plus penalties), `[min, max]` s.
    #[serde(default)]
    pub course_score_s: Option<[f64; 2]>,
    /// Members of the ensemble the ensemble bounds below are checked on (default 16; run by
    /// `tracksim run --ensemble`, the bundled-scenario test and `check_ensemble`; docs/ENSEMBLE.md).
    #[serde(default)]
    pub ensemble_members: Option<usize>,
    /// Range of the ensemble's success fraction, `[min, max]` (e.g. `[0.9, 1]`).
    #[serde(default)]
    pub success_fraction: Option<[f64; 2]>,
    /// Range of the spread (latest - earliest) of the ensemble's success times, `[min, max]` s.
    #[serde(default)]
    pub outcome_time_spread_s: Option<[f64; 2]>,
}
