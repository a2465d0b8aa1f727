//! The floating origin: the Rapier world (single precision) is kept near the vehicle, and every
//! output is given in world coordinates in f64 as `origin + local`.
//!
//! Why: Rapier works in f32, whose spacing at 1000 m is 61 um; each step's displacement of a
//! body is rounded to it, which biased a PackBot at 0.3 m/s to 0.305 m/s at 100 m from the
//! origin, 0.244 m/s at 1000 m and a standstill at 3000 m. With the world shifted by whole
//! metres whenever the chassis is more than [`ORIGIN_SHIFT_M`] from the local origin, every body
//! stays within a few metres of it, where the spacing is below 0.5 um, wherever the robot
//! drives (docs/DESIGN.md has the measurements).
//!
//! A shift translates every body (the terrain's fixed bodies too) by the same whole number of
//! metres: for bodies within a factor of two of the shift the f32 subtraction is exact
//! (Sterbenz), contact manifolds and joints are held in body frames, so the physics does not
//! see it, with one exception: Rapier's contact recycling (`contact_recycling`, on by default)
//! keeps a pair whose *relative* pose barely moved with its solver contacts frozen in world
//! space (anchors and normal). A shift moves every body by the same amount, so every resting
//! pair would be recycled with contact points one shift away from the bodies: on a slope, mesh
//! or height field that was a kick of metres per second at the first step after the shift
//! (issue 23.1). The step after a shift therefore runs with recycling off, so every pair's
//! contacts are computed afresh at the new place.

use super::Simulation;
use glam::DVec3;
use rapier3d::prelude::*;

/// Distance (x or y) of the chassis from the local origin beyond which the world is shifted, m.
pub const ORIGIN_SHIFT_M: f64 = 2.0;

/// The shift, m (a whole number), that brings coordinate `v` m back near 0, or 0 if `v` is
/// within [`ORIGIN_SHIFT_M`].
pub(crate) fn shift_for(v: f64) -> f64 {
    if v.abs() > ORIGIN_SHIFT_M {
        v.round()
    } else {
        0.0
    }
}

impl Simulation {
    /// World position of the Rapier world's origin, m: world = origin + Rapier coordinates.
    /// Changes as the robots drive (whole metres in x and y; z is 0): it follows their centre.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The smallest and largest (x, y) of the robots' chassis in the Rapier world, m.
    pub(crate) fn chassis_extent_local(&self) -> ((f64, f64), (f64, f64)) {
        let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
        for r in &self.robots {
            let p = self.world.bodies[r.body].translation();
            let (x, y) = (p.x as f64, p.y as f64);
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        (lo, hi)
    }

    /// The centre of the robots' chassis in the Rapier world (x, y), m: the one robot's chassis
    /// in a one-robot world; what the origin and the ground tile follow.
    pub(crate) fn chassis_centre_local(&self) -> (f64, f64) {
        let (lo, hi) = self.chassis_extent_local();
        (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1))
    }

    /// Shifts the world when the robots' centre has left the neighbourhood of the local origin;
    /// returns whether it did (the next step must then not recycle contacts: module docs).
    pub(crate) fn follow_origin(&mut self) -> bool {
        let (x, y) = self.chassis_centre_local();
        let (dx, dy) = (shift_for(x), shift_for(y));
        if dx == 0.0 && dy == 0.0 {
            return false;
        }
        let d = Vector::new(dx as f32, dy as f32, 0.0);
        for (_, b) in self.world.bodies.iter_mut() {
            let mut pose = *b.position();
            pose.translation -= d;
            b.set_position(pose, false);
        }
        self.origin += DVec3::new(dx, dy, 0.0);
        true
    }
}
