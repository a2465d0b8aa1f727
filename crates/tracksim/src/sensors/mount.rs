//! Where a sensor is at an update: its frame in the Rapier world (relative to the floating
//! origin, so nothing depends on where the robot is), the velocity of the point it sits on, the
//! angular velocity of its link, and the query filter that keeps the robot out of its rays.

use crate::model::{Mount, SensorModel};
use crate::world::Simulation;
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// A sensor's frame and motion at one instant (Rapier-world coordinates, f64).
#[derive(Clone, Copy, Debug)]
pub struct SensorFrame {
    /// Origin of the sensor frame, m (relative to `Simulation::origin`).
    pub position: DVec3,
    /// Orientation of the sensor frame in the world.
    pub rotation: DQuat,
    /// Velocity of the material point at the sensor's origin, m/s (world frame).
    pub velocity: DVec3,
    /// Angular velocity of the mount link, rad/s (world frame).
    pub angvel: DVec3,
}

fn d(v: Vector) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// The frame of sensor `m` now.
pub fn sensor_frame(sim: &Simulation, m: &SensorModel) -> SensorFrame {
    let h = match m.mount {
        Mount::Body => sim.body_handle(),
        Mount::Flipper(i) => sim.flipper_body(i),
    };
    let b = &sim.world.bodies[h];
    let p = b.position();
    let r = p.rotation;
    let link_rot = DQuat::from_xyzw(r.x as f64, r.y as f64, r.z as f64, r.w as f64).normalize();
    let position = d(p.translation) + link_rot * m.position;
    let point = Vector::new(position.x as f32, position.y as f32, position.z as f32);
    SensorFrame {
        position,
        rotation: (link_rot * m.rotation).normalize(),
        velocity: d(b.velocity_at_point(point)),
        angvel: d(b.angvel()),
    }
}

/// An f64 point or direction as Rapier's f32 vector.
pub fn v32(v: DVec3) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}
