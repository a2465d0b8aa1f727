//! Multiple wheels (paper Sec. II-A): `k` cylinders per track along the lower run, from the rear
//! pulley's centre to the front one's, on revolute joints with velocity motors at
//! belt speed / radius. No grousers: each wheel reaches the grouser tips of the real track
//! (radius = interpolated pulley radius + grouser height), filling its outer envelope as the
//! paper's 4 wheels "without spacing" do. The wheels share the belt's mass (no floor).

use super::common::{insert_wheel_body, set_motor_velocity, wheel_joint};
use super::track::{BuildContext, Track};
use crate::check::q;
use crate::error::{Error, Result};
use crate::geometry::Segment;
use crate::model::TrackModel;
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// One wheel of a multiple-wheel track.
#[derive(Debug)]
struct Wheel {
    body: RigidBodyHandle,
    joint: ImpulseJointHandle,
    /// Rolling radius, m.
    radius: f64,
    /// Axis in the parent frame.
    axis: DVec3,
}

/// A multiple-wheel track.
#[derive(Debug)]
pub struct Wheels {
    parent: RigidBodyHandle,
    wheels: Vec<Wheel>,
    position: f64,
    speed_cmd: f64,
    speed_measured: f64,
    /// The drive gives no force (an instructor's fault, issue 43): the wheels spin freely.
    unpowered: bool,
}

/// The lower run of a loop: the straight whose outward normal points most downwards, with the
/// arcs before and after it (their centres and radii), if it has arcs on both ends.
fn lower_run(track: &TrackModel) -> Option<(DVec3, f64, DVec3, f64)> {
    let segs = track.path.segments();
    let n = segs.len();
    let axis = track.path.axis();
    let (i, _) = segs
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match *s {
            Segment::Straight { direction, .. } => Some((i, direction.cross(axis).z)),
            _ => None,
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let before = &segs[(i + n - 1) % n];
    let after = &segs[(i + 1) % n];
    // The run goes backwards (rear arc after it, front arc before it).
    let (front_c, front_r) = (before.arc_centre()?, before.radius()?);
    let (rear_c, rear_r) = (after.arc_centre()?, after.radius()?);
    Some((rear_c, rear_r, front_c, front_r))
}

impl Wheels {
    /// Builds `k` wheels for `track` (whose grousers, if any, only set the wheels' reach).
    pub fn build(ctx: &mut BuildContext, track: &TrackModel, k: usize) -> Result<Self> {
        let (rear_c, rear_r, front_c, front_r) = lower_run(track).ok_or_else(|| {
            Error::Build(format!(
                "track {}: the multiple-wheel model needs a lower straight run between two arcs",
                track.name
            ))
        })?;
        let grouser = track.grousers.as_ref().map(|g| g.height).unwrap_or(0.0);
        let world = &mut *ctx.world;
        let axis = track.path.axis();
        let parent_pose = *world.bodies[ctx.parent].position();
        // The belt's mass shared evenly, without the link-mass floor: measured on the PackBot
        // (flat, 0.3 m/s, 5 s) wheels4 0.2976 m/s and 0.0896 m high unfloored against 0.2979
        // and 0.0898 floored, and a 0.5 kg floor would make 13 wheels outweigh the vehicle.
        let mass = track.belt_mass / k as f64;
        let mut wheels = Vec::with_capacity(k);
        for i in 0..k {
            let s = if k == 1 {
                0.5
            } else {
                i as f64 / (k - 1) as f64
            };
            let centre = rear_c.lerp(front_c, s);
            let radius = rear_r + (front_r - rear_r) * s + grouser;
            let h = insert_wheel_body(world, parent_pose, centre, axis, radius, track.width, mass);
            let c = ColliderBuilder::cylinder((track.width / 2.0) as f32, radius as f32)
                .rotation(q(DQuat::from_rotation_arc(DVec3::Y, axis)).to_scaled_axis())
                .density(0.0)
                .friction(track.friction as f32)
                .friction_combine_rule(track.combine)
                .collision_groups(ctx.groups);
            world.colliders.insert_with_parent(c, h, &mut world.bodies);
            let j =
                world
                    .impulse_joints
                    .insert(ctx.parent, h, wheel_joint(axis, centre, true), true);
            wheels.push(Wheel {
                body: h,
                joint: j,
                radius,
                axis,
            });
        }
        Ok(Wheels {
            parent: ctx.parent,
            wheels,
            position: 0.0,
            speed_cmd: 0.0,
            speed_measured: 0.0,
            unpowered: false,
        })
    }
}

impl Track for Wheels {
    fn set_belt_speed(&mut self, world: &mut PhysicsWorld, v: f64) {
        self.speed_cmd = v;
        for w in &self.wheels {
            set_motor_velocity(world, w.joint, JointAxis::AngX, (v / w.radius) as f32);
        }
    }

    fn commanded_belt_speed(&self) -> f64 {
        self.speed_cmd
    }

    fn holds_belt(&self) -> bool {
        !self.unpowered && self.speed_cmd == 0.0
    }

    fn set_unpowered(&mut self, world: &mut PhysicsWorld, unpowered: bool) -> bool {
        self.unpowered = unpowered;
        let cap = if unpowered { 0.0 } else { f32::MAX };
        for w in &self.wheels {
            if let Some(j) = world.impulse_joints.get_mut(w.joint, true) {
                j.data.set_motor_max_force(JointAxis::AngX, cap);
            }
        }
        true
    }

    fn after_step(&mut self, world: &mut PhysicsWorld, dt: f64) {
        if !self.unpowered {
            self.position += self.speed_cmd * dt;
        }
        let parent = &world.bodies[self.parent];
        let (rot, w_parent) = (parent.rotation(), parent.angvel());
        let sum: f64 = self
            .wheels
            .iter()
            .map(|w| {
                let axis = rot * Vector::new(w.axis.x as f32, w.axis.y as f32, w.axis.z as f32);
                (world.bodies[w.body].angvel() - w_parent).dot(axis) as f64 * w.radius
            })
            .sum();
        self.speed_measured = sum / self.wheels.len().max(1) as f64;
        if self.unpowered {
            self.position += self.speed_measured * dt;
        }
    }

    fn belt_position(&self) -> f64 {
        self.position
    }

    /// Wheels have no grouser pattern: the phase is 0.
    fn belt_phase(&self) -> f64 {
        0.0
    }

    fn measured_belt_speed(&self) -> f64 {
        self.speed_measured
    }

    fn bodies(&self) -> Vec<RigidBodyHandle> {
        self.wheels.iter().map(|w| w.body).collect()
    }
}
