//! The floating origin on `Simulation`: the Rapier world shifted to stay near the robots, outputs
//! in world f64.

use super::Simulation;
use super::origin::shift_for;
use glam::DVec3;
use rapier3d::prelude::*;

impl Simulation {
    /// World position of the Rapier world's origin, m: world = origin + Rapier coordinates.
    /// Starts at the robots' start centre (on deformable soil: rounded to whole metres) and
    /// changes by whole metres in x and y as they drive, following their centre; z is 0.
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
