//! Moments of a run worth jumping to in a review: stalls (belts commanded, the robot not
//! moving), the largest tilt, the outcome. Found from the samples after the run (written to
//! `summary.json` as `events`), and the stall also live ([`StallDetector`], on the drive
//! page's HUD), by the same rule.

use crate::world::Sample;

/// A belt commanded faster than this counts as driven, m/s.
pub const STALL_BELT_MPS: f64 = 0.05;
/// A body slower than this (speed of its origin) counts as not moving, m/s.
pub const STALL_SPEED_MPS: f64 = 0.02;
/// A body turning slower than this (|yaw rate|) counts as not turning, rad/s.
pub const STALL_YAW_RATE_RAD_S: f64 = 0.05;
/// How long belts must be driven with the body still before it counts as a stall, s.
pub const STALL_HOLD_S: f64 = 1.0;

/// One moment of a run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunEvent {
    /// When, s (a stall: when it began).
    pub t_s: f64,
    /// "stall", "largest_tilt" or "outcome".
    pub kind: &'static str,
    /// What happened, in words with units.
    pub detail: String,
}

/// Whether a sample is driven but still: some belt commanded faster than
/// [`STALL_BELT_MPS`], the body slower than [`STALL_SPEED_MPS`] and turning slower than
/// [`STALL_YAW_RATE_RAD_S`].
pub fn driven_but_still(s: &Sample) -> bool {
    let driven = s.belt_cmd.iter().any(|c| c.abs() > STALL_BELT_MPS);
    let [vx, vy, vz] = s.linvel;
    let speed = (vx * vx + vy * vy + vz * vz).sqrt();
    driven && speed < STALL_SPEED_MPS && s.angvel[2].abs() < STALL_YAW_RATE_RAD_S
}

/// A stall found sample by sample: driven but still for [`STALL_HOLD_S`].
#[derive(Clone, Debug, Default)]
pub struct StallDetector {
    since: Option<f64>,
}

impl StallDetector {
    /// Takes the next sample; returns the time the stall began while the robot is stalled.
    pub fn update(&mut self, s: &Sample) -> Option<f64> {
        if driven_but_still(s) {
            let since = *self.since.get_or_insert(s.t);
            (s.t - since >= STALL_HOLD_S - 1e-9).then_some(since)
        } else {
            self.since = None;
            None
        }
    }
}

/// The stall episodes of `samples`: (begin, end) times, s (an episode still open at the last
/// sample ends there).
pub fn stalls(samples: &[Sample]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut det = StallDetector::default();
    let mut open: Option<f64> = None;
    for s in samples {
        match (det.update(s), open) {
            (Some(b), None) => open = Some(b),
            (None, Some(b)) => {
                out.push((b, s.t));
                open = None;
            }
            _ => {}
        }
    }
    if let (Some(b), Some(last)) = (open, samples.last()) {
        out.push((b, last.t));
    }
    out
}

/// The review events of a run: each stall, the sample of the largest tilt (max of |roll| and
/// |pitch|, against `max_tilt` rad, the scenario's tip-over limit) and the outcome at its
/// time, in time order.
pub fn run_events(
    samples: &[Sample],
    max_tilt: f64,
    outcome: (&super::Outcome, f64),
) -> Vec<RunEvent> {
    let mut events: Vec<RunEvent> = stalls(samples)
        .into_iter()
        .map(|(b, e)| RunEvent {
            t_s: b,
            kind: "stall",
            detail: format!(
                "belts driven (> {STALL_BELT_MPS} m/s), body still (< {STALL_SPEED_MPS} m/s) for {:.2} s",
                e - b
            ),
        })
        .collect();
    let tilt = |s: &Sample| s.pose.roll.abs().max(s.pose.pitch.abs());
    if let Some(s) = samples.iter().max_by(|a, b| tilt(a).total_cmp(&tilt(b))) {
        events.push(RunEvent {
            t_s: s.t,
            kind: "largest_tilt",
            detail: format!(
                "roll {:.1} deg, pitch {:.1} deg ({:.0} % of the {:.1} deg limit)",
                s.pose.roll.to_degrees(),
                s.pose.pitch.to_degrees(),
                100.0 * tilt(s) / max_tilt,
                max_tilt.to_degrees()
            ),
        });
    }
    events.push(RunEvent {
        t_s: outcome.1,
        kind: "outcome",
        detail: format!("{}: {}", outcome.0.name(), outcome.0.reason()),
    });
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    events
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64, cmd: f64, v: f64) -> Sample {
        Sample {
            t,
            belt_cmd: vec![cmd, cmd],
            linvel: [v, 0.0, 0.0],
            ..Sample::default()
        }
    }

    #[test]
    fn a_stall_needs_driven_belts_and_a_still_body_for_the_hold_time() {
        // 0.01 s samples: driven and still from 1.0 s to 2.5 s, then moving.
        let samples: Vec<Sample> = (0..400)
            .map(|i| {
                let t = i as f64 * 0.01;
                let still = (1.0..2.5).contains(&t);
                sample(
                    t,
                    if t >= 1.0 { 0.3 } else { 0.0 },
                    if still { 0.0 } else { 0.3 },
                )
            })
            .collect();
        let st = stalls(&samples);
        assert_eq!(st.len(), 1, "{st:?}");
        assert!(
            (st[0].0 - 1.0).abs() < 1e-9 && (st[0].1 - 2.5).abs() < 1e-9,
            "{st:?}"
        );
        // Still but not driven, or driven and moving: no stall.
        let idle: Vec<Sample> = (0..300)
            .map(|i| sample(i as f64 * 0.01, 0.0, 0.0))
            .collect();
        assert!(stalls(&idle).is_empty());
        // Still for less than the hold time: none.
        let short: Vec<Sample> = (0..300)
            .map(|i| {
                let t = i as f64 * 0.01;
                sample(t, 0.3, if (1.0..1.9).contains(&t) { 0.0 } else { 0.3 })
            })
            .collect();
        assert!(stalls(&short).is_empty());
    }
}
