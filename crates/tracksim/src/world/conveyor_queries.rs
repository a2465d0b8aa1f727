//! Conveyors and loose boxes on `Simulation`: their belts' positions and the boxes' poses.

use super::{PoseRpy, Simulation};
use crate::tracks::Track;
use glam::DVec3;

impl Simulation {
    /// Poses of the loose boxes (`[[terrain.loose_boxes]]`, in file order) in world
    /// coordinates, m and rad.
    pub fn loose_box_poses(&self) -> Vec<PoseRpy> {
        self.conveyors
            .loose
            .iter()
            .map(|h| {
                let mut p = PoseRpy::from_pose(self.world.bodies[*h].position());
                p.x += self.origin.x;
                p.y += self.origin.y;
                p.z += self.origin.z;
                p
            })
            .collect()
    }

    /// Linear velocities of the loose boxes' centres of mass, m/s (world frame).
    pub fn loose_box_velocities(&self) -> Vec<DVec3> {
        self.conveyors
            .loose
            .iter()
            .map(|h| {
                let v = self.world.bodies[*h].linvel();
                DVec3::new(v.x as f64, v.y as f64, v.z as f64)
            })
            .collect()
    }

    /// The conveyors' belts at run time (belt position and phase, grouser colliders, link
    /// error), in file order.
    pub fn conveyor_tracks(&self) -> &[Box<dyn Track>] {
        &self.conveyors.belts
    }

    /// Forgets the largest link error every conveyor has seen so far.
    pub fn reset_conveyor_link_errors(&mut self) {
        for b in &mut self.conveyors.belts {
            b.reset_link_error();
        }
    }

    /// Each conveyor's unwrapped belt position, m, and measured belt speed, m/s.
    pub fn conveyor_belts(&self) -> Vec<(f64, f64)> {
        self.conveyors
            .belts
            .iter()
            .map(|b| (b.belt_position(), b.measured_belt_speed()))
            .collect()
    }
}
