//! Segment links as a reduced-coordinate articulation (`okada2020_multibody`, issue 16.3): the
//! paper's links of [`super::okada2020`], each a prismatic or revolute child of its parent in a
//! Rapier multibody instead of a body held by an impulse joint.
//!
//! # How it differs from `okada2020`
//! - Each link's pose is its parent's pose times its joint coordinate (m along a straight, rad
//!   about an arc's axis): the joint has no error to correct, the solver has no joint rows, and
//!   every contact on the articulation is a generic (non-SIMD) multibody contact constraint.
//! - The chassis becomes the multibody's root, with a free joint. Flippers stay on their
//!   impulse joints and a flipper's tracks keep impulse joints too: with the flipper as the root
//!   of its own articulation of its tracks' links, joined by its impulse joint to the chassis's
//!   articulation, the flippers were flung off within 15 ms (88-235 m/s, PackBot with flippers
//!   and Quince).
//! - The per-step placement at `parent * shift(phase)` sets every link's joint coordinate to
//!   the belt phase (`phase` m, or `phase / radius` rad) and runs the forward kinematics; the
//!   joint velocities the solver gave are kept (as `okada2020` keeps the world velocities).
//!   What the placement removes is the velocity motor's error integrated over a step, reported
//!   as the link error.

use crate::error::{Error, Result};
use rapier3d::prelude::*;

/// Inserts `joint` between `parent` and `child` as a multibody joint (the parent becomes, or
/// stays, its articulation's root).
pub fn insert(
    world: &mut PhysicsWorld,
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    joint: GenericJoint,
) -> Result<MultibodyJointHandle> {
    world
        .multibody_joints
        .insert(parent, child, joint, true)
        .ok_or_else(|| {
            Error::Build(
                "okada2020_multibody: a segment link could not join its parent's articulation"
                    .into(),
            )
        })
}

/// Sets the velocity motor of a link's joint on `axis` to `target` (m/s or rad/s) with
/// [`super::common::BELT_MOTOR_GAIN`], and its largest force (N, or torque N m) if given.
pub fn set_motor(
    world: &mut PhysicsWorld,
    joint: MultibodyJointHandle,
    axis: JointAxis,
    target: f32,
    max_force: Option<f32>,
) {
    if let Some((mb, id)) = world.multibody_joints.get_mut(joint)
        && let Some(link) = mb.link_mut(id)
    {
        let data = &mut link.joint.data;
        data.set_motor_velocity(axis, target, super::common::BELT_MOTOR_GAIN);
        if let Some(f) = max_force {
            data.set_motor_max_force(axis, f);
        }
    }
}

/// Sets the one free coordinate of a link's joint on `axis` to `value` (m for a prismatic
/// joint, rad for a revolute one), keeping its velocity. The link's pose follows at the next
/// [`forward_kinematics`].
pub fn set_coordinate(
    world: &mut PhysicsWorld,
    joint: MultibodyJointHandle,
    axis: JointAxis,
    value: f32,
) {
    if let Some((mb, id)) = world.multibody_joints.get_mut(joint)
        && let Some(link) = mb.link_mut(id)
    {
        let now = link.joint.coords()[axis as usize];
        link.joint.apply_displacement(&[value - now]);
    }
}

/// Runs the forward kinematics of the articulation `joint` belongs to and puts its bodies (and
/// their world mass properties) where its coordinates say.
pub fn forward_kinematics(world: &mut PhysicsWorld, joint: MultibodyJointHandle) {
    if let Some((mb, _)) = world.multibody_joints.get_mut(joint) {
        mb.forward_kinematics(&world.bodies, false);
        mb.update_rigid_bodies(&mut world.bodies, true);
    }
}
