//! Parts every track method shares: collision groups, velocity motors, wheel bodies, and the
//! tags that route a collider's contacts to the track that owns it.

use crate::check::{f, q};
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// Damping gain of the belt velocity motors (acceleration-based: constraint compliance
/// 1 / (dt * gain), i.e. 1e-3 at 1 ms: a hard velocity constraint).
pub const BELT_MOTOR_GAIN: f32 = 1.0e6;

/// Collision group of the terrain.
pub const WORLD_GROUP: Group = Group::GROUP_1;
/// Collision group of every collider of the vehicle.
pub const VEHICLE_GROUP: Group = Group::GROUP_2;

/// Collision group of every terrain collider but the flat-ground tile (on top of
/// [`WORLD_GROUP`]); what the exact grouser hulls of `okada2020_line_tips` see.
pub const RELIEF_GROUP: Group = Group::GROUP_5;
/// Collision group of the flat-ground tile (on top of [`WORLD_GROUP`]); what the grouser tip
/// capsules of `okada2020_line_tips` see.
pub const FLAT_GROUND_GROUP: Group = Group::GROUP_6;

/// Collision groups of a terrain collider: member of [`WORLD_GROUP`] and [`RELIEF_GROUP`],
/// sees everything.
pub fn world_groups() -> InteractionGroups {
    InteractionGroups::new(
        WORLD_GROUP.union(RELIEF_GROUP),
        Group::ALL,
        InteractionTestMode::And,
    )
}

/// Collision groups of the flat-ground tile: member of [`WORLD_GROUP`] and
/// [`FLAT_GROUND_GROUP`], sees everything. Every collider that sees the terrain sees it too
/// (all vehicle colliders but the line-tip grousers' hulls).
pub fn flat_ground_groups() -> InteractionGroups {
    InteractionGroups::new(
        WORLD_GROUP.union(FLAT_GROUND_GROUP),
        Group::ALL,
        InteractionTestMode::And,
    )
}

/// Collision groups of a vehicle collider: it never touches its own vehicle.
pub fn vehicle_groups() -> InteractionGroups {
    InteractionGroups::new(
        VEHICLE_GROUP,
        Group::ALL.difference(VEHICLE_GROUP),
        InteractionTestMode::And,
    )
}

/// Collision group of loose objects (free boxes a conveyor or a vehicle can move).
pub const LOOSE_GROUP: Group = Group::GROUP_3;

/// Collision groups of a conveyor's belt and cleats: part of the world (the terrain's group,
/// so height queries see it), touching the vehicle and loose objects but not the terrain (nor
/// the terrain's relief and flat-ground groups of `okada2020_line_tips`).
pub fn conveyor_groups() -> InteractionGroups {
    InteractionGroups::new(
        WORLD_GROUP,
        Group::ALL
            .difference(WORLD_GROUP)
            .difference(RELIEF_GROUP)
            .difference(FLAT_GROUND_GROUP),
        InteractionTestMode::And,
    )
}

/// Collision groups of a loose object: touches everything, other loose objects too.
pub fn loose_groups() -> InteractionGroups {
    InteractionGroups::new(LOOSE_GROUP, Group::ALL, InteractionTestMode::And)
}

/// `user_data` of a vehicle collider whose contacts only get the contact slop.
pub const SLOP_TAG: u128 = 0x534c_4f50 << 64; // "SLOP"
/// `user_data` high bits of a collider whose contacts go to its track (low 32 bits: the
/// track's index); see [`track_tag`].
pub const TRACK_TAG: u128 = 0x0054_5241_434b << 64; // "TRACK"

/// `user_data` high bits of a vehicle collider with a contact compliance (low 32 bits: the
/// index of its spring in the world's table); see [`compliance_tag`].
pub const COMPLIANCE_TAG: u128 = 0x434f_4d50 << 64; // "COMP"

/// The `user_data` of a collider whose contacts get spring `index` of the world's table.
pub fn compliance_tag(index: usize) -> u128 {
    COMPLIANCE_TAG | index as u128
}

/// The spring index a collider's `user_data` gives it, if any.
pub fn tagged_compliance(user_data: u128) -> Option<usize> {
    (user_data & !0xffff_ffff == COMPLIANCE_TAG).then_some((user_data & 0xffff_ffff) as usize)
}

/// The `user_data` routing a collider's contacts to track `index`.
pub fn track_tag(index: usize) -> u128 {
    TRACK_TAG | index as u128
}

/// The track index a collider's `user_data` routes its contacts to, if any.
pub fn tagged_track(user_data: u128) -> Option<usize> {
    (user_data & !0xffff_ffff == TRACK_TAG).then_some((user_data & 0xffff_ffff) as usize)
}

/// Sets the target velocity of a joint's velocity motor (m/s for a linear axis, rad/s for an
/// angular one), with [`BELT_MOTOR_GAIN`].
pub fn set_motor_velocity(
    world: &mut PhysicsWorld,
    joint: ImpulseJointHandle,
    axis: JointAxis,
    target: f32,
) {
    if let Some(j) = world.impulse_joints.get_mut(joint, true) {
        j.data.set_motor_velocity(axis, target, BELT_MOTOR_GAIN);
    }
}

/// Inserts a wheel body (a solid cylinder of `radius` m and `width` m about `axis`, mass `mass`
/// kg) centred at `centre` in the parent's frame, posed from `parent_pose`. Colliders are the
/// caller's.
pub fn insert_wheel_body(
    world: &mut PhysicsWorld,
    parent_pose: Pose,
    centre: DVec3,
    axis: DVec3,
    radius: f64,
    width: f64,
    mass: f64,
) -> RigidBodyHandle {
    let inertia_axial = 0.5 * mass * radius * radius;
    let inertia_across = mass * (3.0 * radius * radius + width * width) / 12.0;
    world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .pose(parent_pose * Pose::from_translation(f(centre)))
            .additional_mass_properties(MassProperties::with_principal_inertia_frame(
                Vector::ZERO,
                mass as f32,
                Vector::new(
                    inertia_across as f32,
                    inertia_axial as f32,
                    inertia_across as f32,
                ),
                q(DQuat::from_rotation_arc(DVec3::Y, axis)),
            ))
            .can_sleep(false),
    )
}

/// A revolute joint about `axis` (parent frame) through `centre`, at the child's origin, not
/// colliding with its parent; with a velocity motor at rest when `motor` is set.
pub fn wheel_joint(axis: DVec3, centre: DVec3, motor: bool) -> RevoluteJointBuilder {
    let joint = RevoluteJointBuilder::new(f(axis))
        .local_anchor1(f(centre))
        .local_anchor2(Vector::ZERO)
        .contacts_enabled(false);
    if motor {
        joint.motor_velocity(0.0, BELT_MOTOR_GAIN)
    } else {
        joint
    }
}
