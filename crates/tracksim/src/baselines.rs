//! The track models the paper compares against (Sec. II), built from the same vehicle
//! description: multiple wheels, and constraint to ground (Pecka et al., IROS 2017; Gazebo's
//! TrackController). The multiple-plate chain lives in [`crate::plates`].

use crate::geometry::Segment;
use crate::model::TrackModel;
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

use crate::check::{f, q};

/// One wheel of a multiple-wheel track.
#[derive(Debug)]
pub(crate) struct WheelRt {
    pub body: RigidBodyHandle,
    pub joint: ImpulseJointHandle,
    /// Rolling radius, m.
    pub radius: f64,
    /// Axis in the parent frame.
    pub axis: DVec3,
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

/// Builds `k` wheels along the lower run of a track, from the rear pulley's centre to the front
/// one's, each reaching the grouser tips (radius = interpolated pulley radius + `grouser`, the
/// grouser height of the real track, so the wheels fill its outer envelope as in the paper),
/// on revolute joints with velocity motors at belt speed / radius.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_wheels(
    world: &mut PhysicsWorld,
    track: &TrackModel,
    grouser: f64,
    k: usize,
    parent: RigidBodyHandle,
    groups: InteractionGroups,
    min_mass: f64,
    motor_gain: f32,
) -> Result<Vec<WheelRt>, String> {
    let (rear_c, rear_r, front_c, front_r) = lower_run(track).ok_or_else(|| {
        format!(
            "track {}: the multiple-wheel model needs a lower straight run between two arcs",
            track.name
        )
    })?;
    let axis = track.path.axis();
    let parent_pose = *world.bodies[parent].position();
    let mass = (track.belt_mass / k as f64).max(min_mass);
    let mut wheels = Vec::with_capacity(k);
    for i in 0..k {
        let s = if k == 1 {
            0.5
        } else {
            i as f64 / (k - 1) as f64
        };
        let centre = rear_c.lerp(front_c, s);
        let radius = rear_r + (front_r - rear_r) * s + grouser;
        let inertia_axial = 0.5 * mass * radius * radius;
        let inertia_across = mass * (3.0 * radius * radius + track.width * track.width) / 12.0;
        let h = world.bodies.insert(
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
        );
        let c = ColliderBuilder::cylinder((track.width / 2.0) as f32, radius as f32)
            .rotation(q(DQuat::from_rotation_arc(DVec3::Y, axis)).to_scaled_axis())
            .density(0.0)
            .friction(track.friction as f32)
            .friction_combine_rule(track.combine)
            .collision_groups(groups);
        world.colliders.insert_with_parent(c, h, &mut world.bodies);
        let joint = RevoluteJointBuilder::new(f(axis))
            .local_anchor1(f(centre))
            .local_anchor2(Vector::ZERO)
            .contacts_enabled(false)
            .motor_velocity(0.0, motor_gain);
        let j = world.impulse_joints.insert(parent, h, joint, true);
        wheels.push(WheelRt {
            body: h,
            joint: j,
            radius,
            axis,
        });
    }
    Ok(wheels)
}

/// Marks track colliders of the constraint-to-ground model: `user_data` = this tag | index.
pub(crate) const SURFACE_TAG: u128 = 0x0054_5241_434b << 64; // "TRACK"

/// Builds the constraint-to-ground track: one rigid outline (the convex hull of the loop swept
/// across the belt width) fixed to the parent, whose contacts get the belt's surface velocity in
/// [`SurfaceHooks`]. No grousers. Friction: the track colliders get `friction` (Gazebo's
/// example gives the track a very high friction along the belt, so that the other surface's
/// friction decides through the min rule).
pub(crate) fn build_surface(
    world: &mut PhysicsWorld,
    track: &TrackModel,
    index: usize,
    parent: RigidBodyHandle,
    groups: InteractionGroups,
    friction: f64,
) -> Result<Vec<ColliderHandle>, String> {
    let axis = track.path.axis();
    let mut pts = Vec::new();
    for s in track.path.segments() {
        let n = if s.is_straight() { 1 } else { 48 };
        for i in 0..=n {
            let p = s.point_tangent(s.length() * i as f64 / n as f64).0;
            pts.push(f(p + axis * (track.width / 2.0)));
            pts.push(f(p - axis * (track.width / 2.0)));
        }
    }
    let c = ColliderBuilder::convex_hull(&pts)
        .ok_or_else(|| format!("track {}: could not build its outline", track.name))?
        .density(0.0)
        .friction(friction as f32)
        .friction_combine_rule(track.combine)
        .collision_groups(groups)
        .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        .user_data(SURFACE_TAG | index as u128);
    Ok(vec![world.colliders.insert_with_parent(
        c,
        parent,
        &mut world.bodies,
    )])
}

/// Contact modification for the constraint-to-ground model: every contact of a track outline
/// gets a target sliding velocity equal to the belt velocity there, along the belt's tangent
/// (lateral axis x outward normal), so the rounded ends push along their curve.
///
/// The same hooks apply the contact slop (`simulation.contact_slop_m`) to the colliders tagged
/// [`SLOP_TAG`] (every other collider on the vehicle when the slop is set) and to the outlines:
/// a penetration shallower than the slop is reported to the solver as zero, so it is not
/// pushed out but the contact still stops any further approach (ODE's `min_depth`).
#[derive(Debug, Default)]
pub(crate) struct SurfaceHooks {
    /// Per track index: (belt speed m/s, lateral axis in the parent frame).
    pub tracks: Vec<(f64, DVec3)>,
    /// Uncorrected penetration for [`SLOP_TAG`] colliders, m.
    pub slop: f32,
}

/// Marks track colliders whose contacts get the contact slop.
pub(crate) const SLOP_TAG: u128 = 0x534c_4f50 << 64; // "SLOP"

impl PhysicsHooks for SurfaceHooks {
    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        if ctx.colliders[ctx.collider1].user_data == SLOP_TAG
            || ctx.colliders[ctx.collider2].user_data == SLOP_TAG
        {
            let slop = self.slop;
            if let Some(m) = ctx.rigid_mut() {
                for c in m.solver_contacts.iter_mut() {
                    if c.dist < 0.0 {
                        c.dist = (c.dist + slop).min(0.0);
                    }
                }
            }
            return;
        }
        let tag = |h: ColliderHandle| {
            let u = ctx.colliders[h].user_data;
            (u & !0xffff_ffff == SURFACE_TAG).then_some((u & 0xffff_ffff) as usize)
        };
        let (index, sign, track_collider) = match (tag(ctx.collider1), tag(ctx.collider2)) {
            (Some(i), _) => (i, 1.0f32, ctx.collider1),
            (None, Some(i)) => (i, -1.0f32, ctx.collider2),
            _ => return,
        };
        let Some(&(speed, lateral)) = self.tracks.get(index) else {
            return;
        };
        let Some(body) = ctx.colliders[track_collider].parent() else {
            return;
        };
        let lateral_w = ctx.bodies[body].rotation() * f(lateral);
        let Some(m) = ctx.rigid_mut() else {
            return;
        };
        // The manifold normal points from collider 1 to collider 2: outward for the track when
        // it is collider 1.
        let n_out = *m.normal * sign;
        let t = lateral_w.cross(n_out).normalize_or_zero();
        // The solver drives (v1 - v2).t to -tangent_velocity.t; the track surface must move at
        // the belt velocity relative to its body.
        let u = t * (speed as f32) * sign;
        for c in m.solver_contacts.iter_mut() {
            c.tangent_velocity = u;
            if c.dist < 0.0 {
                c.dist = (c.dist + self.slop).min(0.0);
            }
        }
    }
}
