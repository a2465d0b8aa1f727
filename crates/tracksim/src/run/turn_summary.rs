//! Commanded against achieved turns (issue 14.5), for `summary.json`: every stretch of a run
//! with constant belt commands that asks the chassis to turn, with the turn its belt commands
//! describe (the skid-steer kinematics the commands were made with) and the turn it drove.

use crate::model::VehicleModel;
use crate::world::Odometry;
use serde::Serialize;

/// One turn: a stretch of constant belt commands with a commanded yaw rate.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TurnSummary {
    /// The stretch of the run (start, end), s; the achieved figures average its second half.
    pub window_s: [f64; 2],
    /// Commanded forward speed, m/s (the chassis tracks' mean belt command).
    pub commanded_speed_mps: f64,
    /// Commanded yaw rate, rad/s (belt commands over the tracks' geometric separation).
    pub commanded_yaw_rate_rad_s: f64,
    /// Commanded radius, m (speed / yaw rate, positive to the left; 0 for a turn on the spot).
    pub commanded_radius_m: f64,
    /// Mean forward speed achieved, m/s.
    pub achieved_speed_mps: f64,
    /// Mean yaw rate achieved, rad/s.
    pub achieved_yaw_rate_rad_s: f64,
    /// Achieved radius, m (mean speed / mean yaw rate; positive to the left).
    pub achieved_radius_m: f64,
    /// Mean longitudinal offset of the instantaneous centre of rotation from the chassis
    /// frame's origin, m (positive ahead).
    pub icr_x_m: f64,
}

/// The turns of a run of `v` recorded as `samples`: stretches of at least four samples with
/// constant belt commands and a commanded yaw rate of at least 0.01 rad/s.
pub fn turn_summaries(v: &VehicleModel, samples: &crate::run::SampleLog) -> Vec<TurnSummary> {
    let offsets = Odometry::counted_offsets(v);
    let kin = Odometry::new(
        &offsets,
        Odometry::geometric_separation(&offsets),
        0.0,
        0.0,
        0.0,
    );
    let mut turns = Vec::new();
    // The stretch being read: its first index, first sample's commands and time, its last
    // sample's time (one pass; a turn's second half is read again from its index).
    let mut open: Option<(usize, Vec<f64>, f64, f64)> = None;
    for (i, s) in samples.iter().enumerate() {
        if let Some((_, cmd, _, end)) = &mut open
            && *cmd == s.belt_cmd
        {
            *end = s.t;
            continue;
        }
        if let Some(stretch) = open.take() {
            turns.extend(turn(&kin, samples, stretch, i));
        }
        open = Some((i, s.belt_cmd.clone(), s.t, s.t));
    }
    if let Some(stretch) = open {
        turns.extend(turn(&kin, samples, stretch, samples.len()));
    }
    turns
}

/// The turn of one stretch of constant commands (samples `start..stop`: its first index,
/// commands, first and last times), if it is one.
fn turn(
    kin: &Odometry,
    samples: &crate::run::SampleLog,
    (start, belt_cmd, t0, end): (usize, Vec<f64>, f64, f64),
    stop: usize,
) -> Option<TurnSummary> {
    let (v, w) = kin.twist(&belt_cmd);
    let len = stop - start;
    if len < 4 || w.abs() < 0.01 {
        return None;
    }
    let half = || samples.iter_from(start + len / 2).take(len - len / 2);
    let n = (len - len / 2) as f64;
    let speed = half()
        .map(|s| s.linvel[0] * s.pose.yaw.cos() + s.linvel[1] * s.pose.yaw.sin())
        .sum::<f64>()
        / n;
    let rate = half().map(|s| s.angvel[2]).sum::<f64>() / n;
    let (icr_sum, icr_n) = half()
        .filter_map(|s| s.icr.map(|c| c[0]))
        .fold((-0.0, 0usize), |(sum, n), x| (sum + x, n + 1));
    let first_t = t0;
    Some(TurnSummary {
        window_s: [first_t, end],
        commanded_speed_mps: v,
        commanded_yaw_rate_rad_s: w,
        commanded_radius_m: v / w,
        achieved_speed_mps: speed,
        achieved_yaw_rate_rad_s: rate,
        achieved_radius_m: if rate.abs() > 1e-9 { speed / rate } else { 0.0 },
        icr_x_m: icr_sum / icr_n.max(1) as f64,
    })
}
