//! Per-track figures and the odometry error of a run, for `summary.json` (issue 14.2, 14.3).

use super::SampleLog;
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
    /// Largest forward traction, N (0 if it never pushed forwards): friction and the
    /// surfaces' reactions together.
    pub max_traction_n: f64,
    /// Mean friction traction (the belt's grip: what drives), N.
    pub mean_friction_traction_n: f64,
    /// Largest forward friction traction, N (0 if it never pushed forwards).
    pub max_friction_traction_n: f64,
    /// Mean forward component of the surfaces' normal reactions, N (negative: an obstacle
    /// pushes back, e.g. a wall the track is pressed against).
    pub mean_reaction_n: f64,
    /// Mean normal load, N.
    pub mean_normal_load_n: f64,
    /// Mean number of terrain contact points.
    pub mean_contacts: f64,
    /// The drive motor's figures (tracks with `[tracks.motor]` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveSummary>,
}

/// A drive motor over a run: energies integrated over the trajectory rows (trapezoid rule at
/// the output interval), peaks.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DriveSummary {
    /// Largest motor torque, N m (magnitude).
    pub peak_motor_torque_nm: f64,
    /// Mechanical energy delivered to the belt, J (negative: absorbed braking).
    pub mechanical_energy_j: f64,
    /// Largest motor current, A (magnitude; with the electrical model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_current_a: Option<f64>,
    /// Electrical energy drawn from the supply, J (with the electrical model; regeneration
    /// counted negative).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub electrical_energy_j: Option<f64>,
}

/// The drive summary of track `i` (None if it has no motor).
fn drive_summary(i: usize, samples: &SampleLog) -> Option<DriveSummary> {
    let d = |s: &Sample| s.drive.get(i).copied().flatten();
    d(samples.first()?)?;
    let trapezoid = |f: &dyn Fn(&Sample) -> f64| {
        samples
            .pairs()
            .map(|(a, b)| 0.5 * (f(&a) + f(&b)) * (b.t - a.t))
            .sum::<f64>()
    };
    let peak = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(|s| f(&s).abs()).fold(0.0, f64::max);
    let electrical = d(samples.first()?)?.electrical.is_some();
    let elec = |s: &Sample, g: fn(&crate::model::ElectricalState) -> f64| {
        d(s).and_then(|x| x.electrical).map_or(0.0, |e| g(&e))
    };
    Some(DriveSummary {
        peak_motor_torque_nm: peak(&|s| d(s).map_or(0.0, |x| x.motor_torque_nm)),
        mechanical_energy_j: trapezoid(&|s| d(s).map_or(0.0, |x| x.power_w)),
        peak_current_a: electrical.then(|| peak(&|s| elec(s, |e| e.current))),
        electrical_energy_j: electrical.then(|| trapezoid(&|s| elec(s, |e| e.power))),
    })
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
pub fn track_summaries(names: &[String], samples: &SampleLog) -> Vec<TrackSummary> {
    let n = samples.len().max(1) as f64;
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let mean = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(|s| f(&s)).sum::<f64>() / n;
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
                mean_friction_traction_n: mean(&|s| {
                    s.loads.get(i).map_or(0.0, |l| l.friction_traction_n)
                }),
                max_friction_traction_n: samples
                    .iter()
                    .filter_map(|s| s.loads.get(i).map(|l| l.friction_traction_n))
                    .fold(0.0, f64::max),
                mean_reaction_n: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.reaction_n)),
                mean_normal_load_n: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.normal_n)),
                mean_contacts: mean(&|s| s.loads.get(i).map_or(0.0, |l| l.contacts as f64)),
                drive: drive_summary(i, samples),
            }
        })
        .collect()
}

/// The odometry error at the last sample.
pub fn odometry_summary(samples: &SampleLog) -> OdometrySummary {
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
