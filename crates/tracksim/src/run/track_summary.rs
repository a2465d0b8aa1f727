//! Per-track figures and the odometry error of a run, for `summary.json` (issue 14.2, 14.3).

use crate::world::Sample;
use serde::Serialize;

/// One track over a run, averaged over the trajectory rows.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TrackSummary {
    /// Track name.
    pub name: String,
    /// Mean commanded belt speed, m/s.
    pub mean_belt_cmd_mps: f64,
    /// Mean measured belt speed, m/s.
    pub mean_belt_speed_mps: f64,
    /// Mean slip ratio.
    pub mean_slip: f64,
    /// Mean traction along the chassis's forward axis, N.
    pub mean_traction_n: f64,
    /// Largest forward traction, N (0 if it never pushed forwards).
    pub max_traction_n: f64,
    /// Mean normal load, N.
    pub mean_normal_load_n: f64,
    /// Mean number of terrain contact points.
    pub mean_contacts: f64,
}

/// Odometry against the ground truth at the end of a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct OdometrySummary {
    /// Final odometry pose (x m, y m, yaw rad) in the odom frame.
    pub final_pose: [f64; 3],
    /// Horizontal distance between the odometry and the true final position, m.
    pub position_error_m: f64,
    /// Odometry yaw minus true yaw at the end, rad.
    pub yaw_error_rad: f64,
}

/// Per-track summaries of `samples` for tracks named `names`.
pub fn track_summaries(names: &[String], samples: &[Sample]) -> Vec<TrackSummary> {
    let n = samples.len().max(1) as f64;
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let mean = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(f).sum::<f64>() / n;
            TrackSummary {
                name: name.clone(),
                mean_belt_cmd_mps: mean(&|s| s.belt_cmd.get(i).copied().unwrap_or(0.0)),
                mean_belt_speed_mps: mean(&|s| s.belt_speed.get(i).copied().unwrap_or(0.0)),
                mean_slip: mean(&|s| s.slip.get(i).copied().unwrap_or(0.0)),
                mean_traction_n: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.traction_n)),
                max_traction_n: samples
                    .iter()
                    .filter_map(|s| s.loads.get(i).map(|l| l.traction_n))
                    .fold(0.0, f64::max),
                mean_normal_load_n: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.normal_n)),
                mean_contacts: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.contacts as f64)),
            }
        })
        .collect()
}

/// The odometry error at the last sample.
pub fn odometry_summary(samples: &[Sample]) -> OdometrySummary {
    let Some(s) = samples.last() else {
        return OdometrySummary::default();
    };
    let [x, y, yaw] = s.odom;
    OdometrySummary {
        final_pose: s.odom,
        position_error_m: (x - s.pose.x).hypot(y - s.pose.y),
        yaw_error_rad: yaw - s.pose.yaw,
    }
}
