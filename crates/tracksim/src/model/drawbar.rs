//! A drawbar load (`[drawbar]`, issue 14.5): the classic drawbar-pull test of a tracked
//! vehicle (Wong, *Theory of Ground Vehicles*, ch. 2 and 4): a horizontal pull on a hitch of
//! the chassis, backwards along the start heading, constant or from a tether on a spring.

use crate::check::{Checker, v3};
use crate::spec::DrawbarSpec;
use glam::DVec3;

/// How the drawbar's pull is made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DrawbarLoad {
    /// A constant pull, N (a dynamometer car, a weight over a pulley).
    Constant(f64),
    /// A tether on a spring of this rate, N/m, anchored where the hitch started: the pull is
    /// the rate times the distance the hitch moved forwards along the start heading (a slack
    /// tether pulls nothing).
    Spring(f64),
}

/// A compiled drawbar.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawbar {
    /// The load.
    pub load: DrawbarLoad,
    /// Hitch point in the chassis frame, m.
    pub hitch: DVec3,
    /// Time the pull starts, s.
    pub start: f64,
    /// Rise time of the pull from `start`, s (0: at once).
    pub ramp: f64,
}

impl Drawbar {
    /// The pull, N, at time `t` s with the hitch `forward` m ahead of where it started (along
    /// the start heading): the load times the ramp factor, never negative.
    pub fn pull(&self, t: f64, forward: f64) -> f64 {
        if t < self.start {
            return 0.0;
        }
        let ramp = if self.ramp > 0.0 {
            ((t - self.start) / self.ramp).min(1.0)
        } else {
            1.0
        };
        let full = match self.load {
            DrawbarLoad::Constant(p) => p,
            DrawbarLoad::Spring(k) => k * forward.max(0.0),
        };
        full * ramp
    }
}

/// Checks and compiles `[drawbar]`.
pub(crate) fn compile_drawbar(c: &mut Checker, d: &DrawbarSpec) -> Option<Drawbar> {
    let load = match (d.pull_n, d.stiffness_n_per_m) {
        (Some(p), None) => {
            c.non_negative("drawbar.pull_n", p, "N");
            DrawbarLoad::Constant(p)
        }
        (None, Some(k)) => {
            c.positive("drawbar.stiffness_n_per_m", k, "N/m");
            DrawbarLoad::Spring(k)
        }
        _ => {
            c.push(
                "drawbar",
                "give exactly one of `pull_n` (a constant pull, N) and `stiffness_n_per_m` \
                 (a tether on a spring, N/m)",
            );
            return None;
        }
    };
    c.finite("drawbar.hitch_m", &d.hitch_m);
    c.non_negative("drawbar.start_s", d.start_s, "s");
    c.non_negative("drawbar.ramp_s", d.ramp_s, "s");
    Some(Drawbar {
        load,
        hitch: v3(d.hitch_m),
        start: d.start_s,
        ramp: d.ramp_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pull_ramps_and_springs() {
        let d = Drawbar {
            load: DrawbarLoad::Constant(40.0),
            hitch: DVec3::ZERO,
            start: 1.0,
            ramp: 2.0,
        };
        assert_eq!(d.pull(0.5, 0.0), 0.0);
        assert!((d.pull(2.0, 0.0) - 20.0).abs() < 1e-12);
        assert!((d.pull(5.0, 0.0) - 40.0).abs() < 1e-12);
        let s = Drawbar {
            load: DrawbarLoad::Spring(100.0),
            ramp: 0.0,
            ..d
        };
        assert!((s.pull(1.0, 0.25) - 25.0).abs() < 1e-12);
        assert_eq!(s.pull(1.0, -0.25), 0.0, "a slack tether pulls nothing");
    }
}
