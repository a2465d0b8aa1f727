//! Moments of a run worth jumping to in a review: stalls (belts commanded, the robot not
//! moving), the largest tilt, the outcome. Found from the samples after the run (written to
//! `summary.json` as `events`), and the stall also live ([`StallDetector`], on the drive
//! page's HUD), by the same rule.

use crate::world::Sample;

/// A belt commanded faster than this counts as driven, m/s.
pub const STALL_BELT_MPS: f64 = 0.05;
/// A body whose origin moved less than this mean speed over the hold time counts as not
/// moving, m/s (the displacement over the window, not the instantaneous speed: a robot
/// pushing against a wall vibrates at a few cm/s without going anywhere).
pub const STALL_SPEED_MPS: f64 = 0.02;
/// A body whose heading turned less than this mean rate over the hold time counts as not
/// turning, rad/s.
pub const STALL_YAW_RATE_RAD_S: f64 = 0.05;
/// How long belts must be driven with the body still before it counts as a stall, s.
pub const STALL_HOLD_S: f64 = 1.0;

/// One moment of a run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunEvent {
    /// When, s (a stall: when it began).
    pub t_s: f64,
    /// When it ended, s (a stall only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_end_s: Option<f64>,
    /// "stall", "largest_tilt" or "outcome".
    pub kind: &'static str,
    /// What happened, in words with units.
    pub detail: String,
}

/// Whether a sample's belts are driven: some belt commanded faster than [`STALL_BELT_MPS`].
pub fn driven(s: &Sample) -> bool {
    s.belt_cmd.iter().any(|c| c.abs() > STALL_BELT_MPS)
}

/// A stall found sample by sample: belts driven throughout the last [`STALL_HOLD_S`] while
/// the body's origin moved less than [`STALL_SPEED_MPS`] and its heading turned less than
/// [`STALL_YAW_RATE_RAD_S`] on average over that window.
#[derive(Clone, Debug, Default)]
pub struct StallDetector {
    /// (t s, position m, yaw rad) of the driven samples of the window.
    window: std::collections::VecDeque<(f64, [f64; 3], f64)>,
    since: Option<f64>,
}

impl StallDetector {
    /// Takes the next sample; returns the time the stall began while the robot is stalled.
    pub fn update(&mut self, s: &Sample) -> Option<f64> {
        if !driven(s) {
            self.window.clear();
            self.since = None;
            return None;
        }
        let p = [s.pose.x, s.pose.y, s.pose.z];
        self.window.push_back((s.t, p, s.pose.yaw));
        // Keep the latest sample at least the hold time back as the window's start.
        while self.window.len() >= 2 && s.t - self.window[1].0 >= STALL_HOLD_S - 1e-9 {
            self.window.pop_front();
        }
        let (t0, p0, yaw0) = self.window[0];
        let span = s.t - t0;
        let moved =
            ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
        let turned = (s.pose.yaw - yaw0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        let still = span >= STALL_HOLD_S - 1e-9
            && moved < STALL_SPEED_MPS * span
            && turned.abs() < STALL_YAW_RATE_RAD_S * span;
        if still {
            Some(*self.since.get_or_insert(t0))
        } else {
            self.since = None;
            None
        }
    }
}

/// The stall episodes of `samples`: (begin, end) times, s (an episode still open at the last
/// sample ends there).
pub fn stalls<S: std::borrow::Borrow<Sample>>(
    samples: impl IntoIterator<Item = S>,
) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut det = StallDetector::default();
    let mut open: Option<f64> = None;
    let mut last = None;
    for s in samples {
        let s = s.borrow();
        last = Some(s.t);
        match (det.update(s), open) {
            (Some(b), None) => open = Some(b),
            (None, Some(b)) => {
                out.push((b, s.t));
                open = None;
            }
            _ => {}
        }
    }
    if let (Some(b), Some(last)) = (open, last) {
        out.push((b, last));
    }
    out
}

/// The review events of a run: each stall, the sample of the largest tilt (max of |roll| and
/// |pitch|, against `max_tilt` rad, the scenario's tip-over limit) and the outcome at its
/// time, in time order.
pub fn run_events(
    samples: &super::SampleLog,
    max_tilt: f64,
    outcome: (&super::Outcome, f64),
) -> Vec<RunEvent> {
    let mut events: Vec<RunEvent> = stalls(samples.iter())
        .into_iter()
        .map(|(b, e)| RunEvent {
            t_s: b,
            t_end_s: Some(e),
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
            t_end_s: None,
            kind: "largest_tilt",
            detail: format!(
                "roll {:.1} deg, pitch {:.1} deg ({:.0} % of the {:.1} deg limit)",
                s.pose.roll.to_degrees(),
                s.pose.pitch.to_degrees(),
                100.0 * tilt(&s) / max_tilt,
                max_tilt.to_degrees()
            ),
        });
    }
    events.push(RunEvent {
        t_s: outcome.1,
        t_end_s: None,
        kind: "outcome",
        detail: format!("{}: {}", outcome.0.name(), outcome.0.reason()),
    });
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    events
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sample at `t` s with both belts commanded `cmd` m/s and the body at `x` m.
    fn sample(t: f64, cmd: f64, x: f64) -> Sample {
        Sample {
            t,
            belt_cmd: vec![cmd, cmd],
            pose: crate::world::PoseRpy {
                x,
                ..Default::default()
            },
            ..Sample::default()
        }
    }

    /// Samples every 0.01 s for `n`, the body moving at `v(t)` m/s plus a +-5 mm vibration
    /// (a robot banging against a wall), belts at `cmd(t)` m/s.
    fn run(n: usize, cmd: impl Fn(f64) -> f64, v: impl Fn(f64) -> f64) -> Vec<Sample> {
        let mut x = 0.0;
        (0..n)
            .map(|i| {
                let t = i as f64 * 0.01;
                x += 0.01 * v(t);
                let jitter = 0.005 * if i % 2 == 0 { 1.0 } else { -1.0 };
                sample(t, cmd(t), x + jitter)
            })
            .collect()
    }

    #[test]
    fn a_stall_needs_driven_belts_and_a_still_body_for_the_hold_time() {
        // Driven from 1.0 s; still (vibrating in place) from 1.0 s to 2.5 s, then moving.
        let samples = run(
            400,
            |t| if t >= 1.0 { 0.3 } else { 0.0 },
            |t| if (1.0..2.5).contains(&t) { 0.0 } else { 0.3 },
        );
        let st = stalls(&samples);
        assert_eq!(st.len(), 1, "{st:?}");
        // Flagged once the window spans the hold time; it began at 1.0 s, ends when the body
        // has moved 2 cm in the last second (at 0.3 m/s, within 0.1 s of 2.5 s).
        assert!((st[0].0 - 1.0).abs() < 0.011, "{st:?}");
        assert!((st[0].1 - 2.5).abs() < 0.1, "{st:?}");
        // Still but not driven: no stall.
        assert!(stalls(run(300, |_| 0.0, |_| 0.0)).is_empty());
        // Driven and creeping at 0.03 m/s (a slow climb): no stall.
        assert!(stalls(run(300, |_| 0.3, |_| 0.03)).is_empty());
        // Still for less than the hold time: none.
        let short = run(
            300,
            |_| 0.3,
            |t| if (1.0..1.9).contains(&t) { 0.0 } else { 0.3 },
        );
        assert!(stalls(&short).is_empty());
    }
}
