//! What the drive page's warnings need, computed where the physics is: each track's slip,
//! the stall ([`crate::run::events::StallDetector`], the rule a review's stall events use),
//! the tip-over limit, and the terrain's profile ahead of the robot (for the flipper gauge
//! against the step ahead).

use crate::run::RunView;
use crate::run::events::StallDetector;

/// Distances of the profile ahead, along the body's heading from its origin, m: from
/// [`AHEAD_FROM_M`] to [`AHEAD_TO_M`] every [`AHEAD_STEP_M`].
pub const AHEAD_FROM_M: f64 = -0.6;
/// See [`AHEAD_FROM_M`], m.
pub const AHEAD_TO_M: f64 = 1.5;
/// See [`AHEAD_FROM_M`], m.
pub const AHEAD_STEP_M: f64 = 0.05;
/// The step ahead is the largest rise of the profile within this distance ahead, m.
pub const STEP_AHEAD_WITHIN_M: f64 = 1.0;

/// The terrain's height along the body's horizontal heading: distances `d_m` and heights
/// `z_m` relative to the terrain under the body's origin (null where there is no terrain),
/// and `step_m`, the largest rise within [`STEP_AHEAD_WITHIN_M`] ahead (0 on level ground).
pub fn ahead_profile(run: &RunView) -> serde_json::Value {
    let sim = run.sim;
    let p = sim.body_pose();
    let n = ((AHEAD_TO_M - AHEAD_FROM_M) / AHEAD_STEP_M).round() as usize + 1;
    let d: Vec<f64> = (0..n)
        .map(|i| AHEAD_FROM_M + i as f64 * AHEAD_STEP_M)
        .collect();
    let (c, s) = (p.yaw.cos(), p.yaw.sin());
    let xs: Vec<f64> = d.iter().map(|d| p.x + d * c).collect();
    let ys: Vec<f64> = d.iter().map(|d| p.y + d * s).collect();
    let base = sim.terrain_below(p.x, p.y);
    let z: Vec<Option<f64>> = match (base, sim.terrain_heights(&xs, &ys)) {
        (Some(b), Ok(h)) => h.iter().map(|z| z.is_finite().then_some(z - b)).collect(),
        _ => vec![None; n],
    };
    let step = d
        .iter()
        .zip(&z)
        .filter(|(d, _)| **d > 0.0 && **d <= STEP_AHEAD_WITHIN_M + 1e-9)
        .filter_map(|(_, z)| *z)
        .fold(0.0, f64::max);
    serde_json::json!({ "d_m": d, "z_m": z, "step_m": step })
}

/// The warnings' data of successive states of one session.
#[derive(Debug, Default)]
pub struct HudFeed {
    stall: StallDetector,
    stalled_since: Option<f64>,
    seen: usize,
}

impl HudFeed {
    /// Starts again (a reset session).
    pub fn reset(&mut self) {
        *self = HudFeed::default();
    }

    /// `slip` (per track, the last sample's slip ratio), `stall` (bool) and `stall_since_s`
    /// (when it began, s), `tilt_limit_deg`, `ahead` ([`ahead_profile`]), as JSON fields.
    pub fn fields(&mut self, run: &RunView) -> serde_json::Map<String, serde_json::Value> {
        let samples = run.samples;
        if samples.len() < self.seen {
            self.reset();
        }
        for s in samples.iter_from(self.seen) {
            self.stalled_since = self.stall.update(&s);
        }
        self.seen = samples.len();
        let slip = samples.last().map(|s| s.slip.clone()).unwrap_or_default();
        let mut m = serde_json::Map::new();
        m.insert("slip".into(), serde_json::json!(slip));
        m.insert("stall".into(), self.stalled_since.is_some().into());
        m.insert(
            "stall_since_s".into(),
            serde_json::json!(self.stalled_since),
        );
        m.insert(
            "tilt_limit_deg".into(),
            run.scenario.outcome.max_tilt.to_degrees().into(),
        );
        m.insert("ahead".into(), ahead_profile(run));
        m
    }
}
