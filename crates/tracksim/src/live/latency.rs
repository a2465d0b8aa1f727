//! Added command latency (an instructor's fault, issue 43): the trainee's controls reach the
//! robot `L` seconds of simulated time late ([`Delayed`]). The controls as applied (late) are
//! what the session records, so its `commands.toml` replays without any delay of its own.

use super::hub::DriveControl;
use std::collections::VecDeque;

/// The driver's controls on their way to the robot: each due at its simulated time, s.
#[derive(Debug, Default)]
pub(super) struct Delayed {
    queue: VecDeque<(f64, DriveControl)>,
}

impl Delayed {
    /// The driver gave `c`, due at simulated time `due` s. A control due no later than ones
    /// still queued replaces them (they were older: a latency just lowered never lets an old
    /// control overtake a newer one).
    pub(super) fn push(&mut self, due: f64, c: DriveControl) {
        self.queue.retain(|(d, _)| *d < due);
        self.queue.push_back((due, c));
    }

    /// The newest control due by simulated time `t` s, if any (the older ones due are
    /// superseded by it).
    pub(super) fn due(&mut self, t: f64) -> Option<DriveControl> {
        let mut out = None;
        while self.queue.front().is_some_and(|(d, _)| *d <= t + 1e-9) {
            out = self.queue.pop_front().map(|(_, c)| c);
        }
        out
    }

    /// Forgets every control on its way (a reset).
    pub(super) fn clear(&mut self) {
        self.queue.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fwd(v: f64) -> DriveControl {
        DriveControl {
            forward_mps: v,
            ..DriveControl::default()
        }
    }

    #[test]
    fn controls_arrive_late_in_order_and_never_overtaken() {
        let mut d = Delayed::default();
        d.push(0.5, fwd(0.1));
        assert_eq!(d.due(0.49), None, "not yet due");
        d.push(0.7, fwd(0.2));
        assert_eq!(d.due(0.5), Some(fwd(0.1)));
        assert_eq!(d.due(0.8), Some(fwd(0.2)));
        // The latency lowered: a newer control due earlier drops the older ones queued.
        d.push(2.0, fwd(0.3));
        d.push(1.0, fwd(0.4));
        assert_eq!(
            d.due(3.0),
            Some(fwd(0.4)),
            "the old control never applies after"
        );
        assert_eq!(d.due(4.0), None);
    }
}
