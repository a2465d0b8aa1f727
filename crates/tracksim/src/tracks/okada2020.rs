//! The paper's method (Okada et al., ICRA 2020, Sec. III): one rigid *segment link* per
//! straight or circular segment of the loop, joined to the parent by a prismatic or revolute
//! joint with a velocity motor at belt speed, carrying the belt shape and its grousers; after
//! every step each link is placed at `parent * shift(phase)`, which rolls it back by exactly one
//! grouser pitch when the phase wraps. Also its variant without grousers
//! (`okada2020_no_grousers`), whose links are restored every step.
//!
//! # How a track is built
//! Each included segment becomes one dynamic rigid body whose frame coincides with its parent's
//! frame at rest. A straight link carries a thin cuboid belt and is joined by a prismatic joint
//! along the segment; an arc link carries a cylinder of the loop radius and is joined by a
//! revolute joint on the pulley axis. Each link also carries, as separate colliders, the
//! grousers whose footprints lie on its segment at rest. Joint velocity motors (velocity-only,
//! effectively unlimited force) move every link at belt speed: `v` along straights, `v / r`
//! about arcs.
//!
//! # Rollback
//! The belt position `s` is integrated from the command and kept unwrapped (`f64`). With
//! grousers of pitch `p = L / N`, the phase is `phi = s - p * round(s / p)`, in `[-p/2, p/2)`.
//! After every physics step each link is put exactly at `parent * shift(phi)`, keeping the world
//! velocity the solver gave it. Between wraps that only removes the solver's joint error (a few
//! micrometres, reported as the link error); when `s` crosses a half pitch the phase wraps and
//! every link jumps back by exactly one pitch, which leaves the grouser pattern where it was, so
//! the track's shape is exact forever. Without grousers `phi = 0`: links are restored every step.
//! When a track has several grouser shapes in turn, the colliders' shapes are re-assigned on each
//! wrap so the pattern travels with the belt.
//!
//! # Choices (and why)
//! - Link mass: the belt's real mass split by segment length, but at least
//!   `simulation.min_link_mass_kg` ([`crate::model::MIN_LINK_MASS_KG`] by default): on the
//!   PackBot climbing a step the floor halves the per-step joint error (1.5 mm / 31 mrad ->
//!   0.8 mm / 14 mrad); on flat ground it makes no difference (docs/DESIGN.md).
//! - Belt and grousers are separate colliders (not one compound), with Rapier's contact
//!   clustering off by default: clustering merged grouser contacts and let them sink mm deep.
//! - Snapping keeps the solver's world velocities: also overwriting them with the joint
//!   kinematics injected momentum (5-13 mm/s^2 of drift on a frictionless ground).

use super::common::{BELT_MOTOR_GAIN, set_motor_velocity};
use super::track::{BuildContext, LinkError, Track};
use crate::check::{f, q};
use crate::error::{Error, Result};
use crate::geometry::Segment;
use crate::model::{DriveMotor, MotorCommand};
use crate::model::{GrouserShape, TrackModel};
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// How a link moves relative to its parent.
#[derive(Clone, Copy, Debug)]
enum LinkKind {
    /// Translation along a unit direction (parent frame).
    Slide { dir: DVec3 },
    /// Rotation about an axis through `centre`; `v / radius` rad/s per m/s of belt.
    Turn {
        centre: DVec3,
        axis: DVec3,
        radius: f64,
    },
}

impl LinkKind {
    /// Pose of the link relative to its parent when the belt has moved by `phi` m.
    fn shift(&self, phi: f64) -> Pose {
        match *self {
            LinkKind::Slide { dir } => Pose::from_translation(f(dir * phi)),
            LinkKind::Turn {
                centre,
                axis,
                radius,
            } => {
                let r = DQuat::from_axis_angle(axis, phi / radius);
                Pose::from_parts(f(centre - r * centre), q(r))
            }
        }
    }
    fn motor_axis(&self) -> JointAxis {
        match self {
            LinkKind::Slide { .. } => JointAxis::LinX,
            LinkKind::Turn { .. } => JointAxis::AngX,
        }
    }
    fn motor_target(&self, v: f64) -> f32 {
        match *self {
            LinkKind::Slide { .. } => v as f32,
            LinkKind::Turn { radius, .. } => (v / radius) as f32,
        }
    }
}

/// How a track's grousers become colliders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrouserColliders {
    /// One collider per grouser (`okada2020`).
    Separate,
    /// Each grouser's hull for the relief and a tip capsule for the flat ground
    /// (`okada2020_line_tips`, [`super::line_tips`]).
    LineTips,
    /// The grousers of a link as one compound, with contact clustering
    /// (`okada2020_clustered`, [`super::clustered`]).
    Compound,
}

#[derive(Debug)]
struct Link {
    body: RigidBodyHandle,
    joint: ImpulseJointHandle,
    kind: LinkKind,
    local_com: Vector,
    /// Grouser colliders with their slot index k on the loop (a compound: once, with its first
    /// slot).
    grousers: Vec<(ColliderHandle, usize)>,
    /// Each compound collider of the link's grousers with its shape for every phase of the
    /// shape pattern ([`super::clustered::compounds`]; empty unless
    /// [`GrouserColliders::Compound`]).
    compounds: Vec<(ColliderHandle, Vec<SharedShape>)>,
}

/// A track of segment links (the paper's method).
#[derive(Debug)]
pub struct SegmentLinks {
    parent: RigidBodyHandle,
    links: Vec<Link>,
    /// Grouser pitch L / N, m (None without grousers).
    pitch: Option<f64>,
    /// One collider per grouser, posed on its footprint frame (not compounds, not line tips).
    per_grouser: bool,
    /// The grouser shapes in turn.
    shapes: Vec<SharedShape>,
    /// Unwrapped belt position, m.
    position: f64,
    /// Commanded belt speed, m/s.
    speed_cmd: f64,
    /// Belt speed measured from the links' joint velocities before the snap, m/s.
    speed_measured: f64,
    /// Wraps of the phase so far.
    wraps: i64,
    error: LinkError,
    /// Drive motor (None: the links' motors hold the commanded speed whatever the load).
    motor: Option<DriveMotor>,
    /// A duty or torque command in force (None: the speed set-point `speed_cmd`).
    motor_cmd: Option<MotorCommand>,
    /// The belt force the motor allowed in the last step, N.
    force_limit: f64,
    /// With a motor and a zero command, the belt position it holds, m (None: not held).
    hold: Option<f64>,
    /// The drive gives no force (an instructor's fault, issue 43): the belt free-wheels.
    unpowered: bool,
}

/// Time constant of a held motor's return to the belt position it holds, s: the driver's
/// position hold. Without it the solver's small velocity error at a zero command was
/// integrated into the belt position (the measured speed drives the phase) and a parked robot
/// crept 0.5-7 mm/s up a 20 deg slope on its held motors (issue 23.5).
const HOLD_TIME_S: f64 = 0.05;

/// Share of a track's belt force that every link may deliver whatever its contact load (it
/// has to move its own mass), of an even split.
const FREE_LINK_SHARE: f64 = 0.05;

/// Mass properties of a segment link: the belt's mass spread along the segment and across its
/// width (sampled: mass properties only, not geometry), kg and kg m^2.
fn link_mass_properties(
    track: &TrackModel,
    seg: usize,
    mass: f64,
    lateral: DVec3,
) -> MassProperties {
    let s = &track.path.segments()[seg];
    let n = 64;
    let len = s.length();
    let pts: Vec<DVec3> = (0..n)
        .map(|i| s.point_tangent(len * (i as f64 + 0.5) / n as f64).0)
        .collect();
    let com = pts.iter().sum::<DVec3>() / n as f64;
    let m = mass / n as f64;
    let mut inertia = glam::DMat3::ZERO;
    for p in &pts {
        let r = *p - com;
        inertia += (glam::DMat3::IDENTITY * r.length_squared()
            - glam::DMat3::from_cols(r * r.x, r * r.y, r * r.z))
            * m;
    }
    // Spread across the width and through the thickness (a thin plate, not a wire).
    let w2 = track.width * track.width / 12.0;
    let t2 = track.belt_thickness * track.belt_thickness / 12.0;
    inertia += (glam::DMat3::IDENTITY * (w2 + t2)
        - glam::DMat3::from_cols(
            lateral * lateral.x,
            lateral * lateral.y,
            lateral * lateral.z,
        ) * w2)
        * mass;
    let mat = glam::Mat3::from_cols(f(inertia.x_axis), f(inertia.y_axis), f(inertia.z_axis));
    MassProperties::with_inertia_matrix(f(com), mass as f32, mat)
}

/// The Rapier shapes of a track's grousers, in turn.
fn grouser_shapes(t: &TrackModel) -> Result<Vec<SharedShape>> {
    let Some(g) = &t.grousers else {
        return Ok(Vec::new());
    };
    g.shapes
        .iter()
        .map(|s| match s {
            GrouserShape::Box { half, .. } => Some(SharedShape::cuboid(
                half.x as f32,
                half.y as f32,
                half.z as f32,
            )),
            GrouserShape::Convex(pts) => {
                SharedShape::convex_hull(&pts.iter().map(|p| f(*p)).collect::<Vec<_>>())
            }
        })
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| {
            Error::Build(format!(
                "track {}: a grouser shape's convex hull could not be computed",
                t.name
            ))
        })
}

/// The belt collider of segment `seg` (parent frame) and how its link moves.
fn belt_collider(t: &TrackModel, seg: &Segment, lateral: DVec3) -> (LinkKind, ColliderBuilder) {
    match *seg {
        Segment::Straight {
            start,
            direction,
            length,
        } => {
            let normal = direction.cross(lateral);
            let centre = start + direction * (length / 2.0) - normal * (t.belt_thickness / 2.0);
            let rot = DQuat::from_mat3(&glam::DMat3::from_cols(direction, lateral, normal));
            (
                LinkKind::Slide { dir: direction },
                ColliderBuilder::cuboid(
                    (length / 2.0) as f32,
                    (t.width / 2.0) as f32,
                    (t.belt_thickness / 2.0) as f32,
                )
                .position(Pose::from_parts(f(centre), q(rot))),
            )
        }
        Segment::Arc { axis, angle, .. } => {
            let centre = seg.arc_centre().unwrap_or_default();
            let radius = seg.radius().unwrap_or_default();
            let rot = DQuat::from_rotation_arc(DVec3::Y, lateral);
            (
                LinkKind::Turn {
                    centre,
                    axis: axis * angle.signum(),
                    radius,
                },
                ColliderBuilder::cylinder((t.width / 2.0) as f32, (radius - t.rim_inset) as f32)
                    .position(Pose::from_parts(f(centre), q(rot))),
            )
        }
    }
}

/// The joint of a link to its parent: prismatic along a straight, revolute about an arc's
/// axis, each with a velocity motor at rest.
fn link_joint(kind: LinkKind, seg: &Segment) -> GenericJoint {
    match kind {
        LinkKind::Slide { dir } => PrismaticJointBuilder::new(f(dir))
            .local_anchor1(f(seg.start()))
            .local_anchor2(f(seg.start()))
            .contacts_enabled(false)
            .motor_velocity(0.0, BELT_MOTOR_GAIN)
            .into(),
        LinkKind::Turn { centre, axis, .. } => RevoluteJointBuilder::new(f(axis))
            .local_anchor1(f(centre))
            .local_anchor2(f(centre))
            .contacts_enabled(false)
            .motor_velocity(0.0, BELT_MOTOR_GAIN)
            .into(),
    }
}

impl SegmentLinks {
    /// Builds the segment links of `t` on `ctx.parent` (with `t`'s grousers, if it has any).
    pub fn build(ctx: &mut BuildContext, t: &TrackModel) -> Result<Self> {
        Self::build_with(ctx, t, GrouserColliders::Separate)
    }

    /// [`Self::build`] with the grousers made colliders as `how` says.
    pub fn build_with(
        ctx: &mut BuildContext,
        t: &TrackModel,
        how: GrouserColliders,
    ) -> Result<Self> {
        let shapes = grouser_shapes(t)?;
        let tips = if how == GrouserColliders::LineTips {
            super::line_tips::tip_shapes(t)?
        } else {
            Vec::new()
        };
        let path = &t.path;
        let footprints = t
            .grousers
            .as_ref()
            .map(|g| g.layout.footprints(path))
            .unwrap_or_default();
        let mut links = Vec::new();
        for si in 0..path.segments().len() {
            if t.included[si] {
                links.push(Self::build_link(
                    ctx,
                    t,
                    si,
                    (&shapes, &tips, how),
                    &footprints,
                ));
            }
        }
        let mut s = SegmentLinks {
            parent: ctx.parent,
            links,
            pitch: t.grousers.as_ref().map(|g| g.layout.pitch(path)),
            per_grouser: how == GrouserColliders::Separate,
            shapes,
            position: 0.0,
            speed_cmd: 0.0,
            speed_measured: 0.0,
            wraps: 0,
            error: LinkError::default(),
            motor: t.motor.clone(),
            motor_cmd: None,
            force_limit: 0.0,
            hold: None,
            unpowered: false,
        };
        if let Some(m) = &s.motor {
            let loads = vec![0.0; s.links.len()];
            s.force_limit = m.max_belt_force(0.0, 0.0);
            s.limit_link_forces(ctx.world, s.force_limit, &loads, 0.0);
        }
        Ok(s)
    }

    /// Builds the link of segment `si`: body, belt collider, grousers, joint.
    fn build_link(
        ctx: &mut BuildContext,
        t: &TrackModel,
        si: usize,
        (shapes, tips, how): (&[SharedShape], &[SharedShape], GrouserColliders),
        footprints: &[(usize, crate::geometry::Frame)],
    ) -> Link {
        let world = &mut *ctx.world;
        let path = &t.path;
        let seg = &path.segments()[si];
        // A spatial loop's lateral axis changes along it: the frame's at the segment's start.
        let lateral = if path.is_planar() {
            path.axis()
        } else {
            path.frame_at(path.segment_start(si)).lateral
        };
        let parent_pose = *world.bodies[ctx.parent].position();
        let mass = (t.belt_mass * seg.length() / path.length()).max(ctx.min_link_mass);
        let mprops = link_mass_properties(t, si, mass, lateral);
        let h = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(parent_pose)
                .additional_mass_properties(mprops)
                .can_sleep(false),
        );
        let groups = ctx.groups;
        let base = |b: ColliderBuilder| {
            b.density(0.0)
                .friction(t.friction as f32)
                .friction_combine_rule(t.combine)
                .collision_groups(groups)
        };
        let (kind, belt) = belt_collider(t, seg, lateral);
        // A segment without contact keeps its body, joint and motor (the belt's momentum) and
        // carries nothing to collide with.
        let touching = t.touching[si];
        // A spatial loop has no belt surface: it carries its grousers (objects) only.
        if path.is_planar() && touching {
            world
                .colliders
                .insert_with_parent(base(belt), h, &mut world.bodies);
        }
        // Grousers whose footprint lies on this segment at rest.
        let mut grousers = Vec::new();
        let mut parts = Vec::new();
        if let Some(g) = t.grousers.as_ref().filter(|_| touching) {
            for (k, (gs, frame)) in footprints.iter().enumerate() {
                if *gs != si {
                    continue;
                }
                let shape_i = k % g.shapes.len();
                let centre = match &g.shapes[shape_i] {
                    GrouserShape::Box { centre, .. } => *centre,
                    GrouserShape::Convex(_) => DVec3::ZERO,
                };
                let pose = Pose::from_parts(f(frame.to_track(centre)), q(frame.rotation()));
                if how == GrouserColliders::Compound {
                    parts.push((pose, k));
                    continue;
                }
                let c = base(ColliderBuilder::new(shapes[shape_i].clone()).position(pose));
                let ch = world.colliders.insert_with_parent(c, h, &mut world.bodies);
                grousers.push((ch, k));
                if let Some(tip) = tips.get(shape_i) {
                    world.colliders[ch].set_collision_groups(super::line_tips::hull_groups());
                    let c = base(ColliderBuilder::new(tip.clone()).position(pose))
                        .collision_groups(super::line_tips::tip_groups());
                    let ch = world.colliders.insert_with_parent(c, h, &mut world.bodies);
                    grousers.push((ch, k));
                }
            }
        }
        super::clustered::order_along_segment(&mut parts, footprints.len());
        let mut compounds = Vec::new();
        for group in parts.chunks(super::clustered::GROUSERS_PER_COMPOUND) {
            let phases = super::clustered::compounds(group, shapes);
            let c = base(ColliderBuilder::new(phases[0].clone()));
            let ch = world.colliders.insert_with_parent(c, h, &mut world.bodies);
            grousers.push((ch, group[0].1));
            compounds.push((ch, phases));
        }
        let joint = link_joint(kind, seg);
        let j = world.impulse_joints.insert(ctx.parent, h, joint, true);
        Link {
            body: h,
            joint: j,
            kind,
            local_com: mprops.local_com,
            grousers,
            compounds,
        }
    }

    /// Phase in `[-p/2, p/2)`, m, and the number of wraps it implies.
    fn phase(&self) -> (f64, i64) {
        super::phase_and_wraps(self.position, self.pitch)
    }

    /// Several grouser shapes in turn: re-assigns them so the pattern moves with the belt.
    fn reassign_shapes(&self, world: &mut PhysicsWorld, wraps: i64) {
        let m = self.shapes.len() as i64;
        for l in &self.links {
            if !l.compounds.is_empty() {
                for (ch, phases) in &l.compounds {
                    if let Some(c) = world.colliders.get_mut(*ch) {
                        c.set_shape(phases[wraps.rem_euclid(m) as usize].clone());
                    }
                }
                continue;
            }
            for &(ch, k) in &l.grousers {
                let idx = (k as i64 - wraps).rem_euclid(m) as usize;
                if let Some(c) = world.colliders.get_mut(ch) {
                    c.set_shape(self.shapes[idx].clone());
                }
            }
        }
    }

    /// Grouser slot indices `k` whose collider currently has a shape for which `pick` holds.
    pub fn grouser_slots(
        &self,
        world: &PhysicsWorld,
        pick: impl Fn(&dyn rapier3d::parry::shape::Shape) -> bool,
    ) -> Vec<usize> {
        let mut v: Vec<usize> = self
            .links
            .iter()
            .flat_map(|l| l.grousers.iter())
            .filter(|(h, _)| pick(world.colliders[*h].shape()))
            .map(|(_, k)| *k)
            .collect();
        v.sort();
        v
    }
}

impl SegmentLinks {
    /// Each link's speed along its segment relative to the parent, m/s (as `after_step`
    /// measures it).
    fn link_speeds(&self, world: &PhysicsWorld) -> Vec<f64> {
        let parent = &world.bodies[self.parent];
        let rot = parent.rotation();
        self.links
            .iter()
            .map(|l| {
                let link = &world.bodies[l.body];
                let com = link.position().transform_point(l.local_com);
                match l.kind {
                    LinkKind::Slide { dir } => {
                        ((link.linvel() - parent.velocity_at_point(com)).dot(rot * f(dir))) as f64
                    }
                    LinkKind::Turn { axis, radius, .. } => {
                        ((link.angvel() - parent.angvel()).dot(rot * f(axis))) as f64 * radius
                    }
                }
            })
            .collect()
    }

    /// The belt's speed with a motor, m/s: the links' speeds weighted by their terrain loads
    /// (the belt moves as fast as where it meets the ground), their plain mean off the ground.
    fn loaded_belt_speed(speeds: &[f64], loads: &[f64]) -> f64 {
        let sum: f64 = loads.iter().sum();
        if sum > 0.0 {
            speeds.iter().zip(loads).map(|(v, w)| v * w).sum::<f64>() / sum
        } else {
            speeds.iter().sum::<f64>() / speeds.len().max(1) as f64
        }
    }

    /// Caps the link motors so that together they deliver at most `total` N to the terrain,
    /// shared by the links' contact loads `loads` of the last step (plus [`FREE_LINK_SHARE`]
    /// each): the belt force goes where the belt meets the ground. A link off the ground is
    /// held at the belt's speed `belt` m/s with, on top, its own weight: in a real belt its
    /// tension holds it, and the weight of a closed belt adds no net load on the motor.
    fn limit_link_forces(&self, world: &mut PhysicsWorld, total: f64, loads: &[f64], belt: f64) {
        let n = self.links.len().max(1) as f64;
        let sum: f64 = loads.iter().sum();
        for (l, load) in self.links.iter().zip(loads) {
            let share = if sum > 0.0 {
                (1.0 - FREE_LINK_SHARE) * load / sum + FREE_LINK_SHARE / n
            } else {
                1.0 / n
            };
            let mut force = total * share;
            if *load <= 0.0 {
                force += world.bodies[l.body].mass() as f64 * 9.81;
            }
            // Loaded links run at the command, or held, back to the held belt position
            // ([`Self::hold_target`]); unloaded ones follow the belt. A belt with no link on
            // the ground has nothing to follow but its speed controller: every link then runs
            // at the command (within the motor's force). Following its own measured speed
            // there left it without a set-point, and the solver's small per-step velocity
            // deficit accumulated: a raised flipper's belt slowed by 0.3-0.6 m/s per second
            // until a grouser touched again, by how much depending on where the grousers lie
            // on the loop, i.e. on the pulley order (issue 38).
            // Unpowered, every link follows the belt (the loaded ones with no force at all).
            let target = if self.unpowered {
                belt
            } else if *load > 0.0 || sum <= 0.0 {
                self.hold_target()
            } else {
                belt
            };
            let cap = match l.kind {
                LinkKind::Slide { .. } => force,
                LinkKind::Turn { radius, .. } => force * radius,
            };
            set_motor_velocity(
                world,
                l.joint,
                l.kind.motor_axis(),
                l.kind.motor_target(target),
            );
            if let Some(j) = world.impulse_joints.get_mut(l.joint, false) {
                j.data.set_motor_max_force(l.kind.motor_axis(), cap as f32);
            }
        }
    }

    /// The loaded links' target speed, m/s: the command, or held, the return to the held
    /// position over [`HOLD_TIME_S`].
    fn hold_target(&self) -> f64 {
        match self.hold {
            Some(h) => (h - self.position) / HOLD_TIME_S,
            None => self.speed_cmd,
        }
    }

    /// Link terrain loads of the last step (ratios only).
    fn link_loads(&self, world: &PhysicsWorld) -> Vec<f64> {
        self.links
            .iter()
            .map(|l| link_contact_load(world, l.body))
            .collect()
    }
}

/// Sum of the normal impulses on `body`'s colliders from the terrain in the last step (any
/// unit: only ratios are used).
fn link_contact_load(world: &PhysicsWorld, body: RigidBodyHandle) -> f64 {
    let Some(b) = world.bodies.get(body) else {
        return 0.0;
    };
    let mut load = 0.0;
    for &ch in b.colliders() {
        for p in world.narrow_phase.contact_pairs_with(ch) {
            for m in p.solver_manifolds() {
                load += m
                    .points
                    .iter()
                    .map(|pt| pt.data.impulse as f64)
                    .sum::<f64>();
            }
        }
    }
    load
}

impl Track for SegmentLinks {
    fn set_belt_speed(&mut self, world: &mut PhysicsWorld, v: f64) {
        self.speed_cmd = v;
        self.motor_cmd = None;
        for l in &self.links {
            set_motor_velocity(world, l.joint, l.kind.motor_axis(), l.kind.motor_target(v));
        }
    }

    fn commanded_belt_speed(&self) -> f64 {
        self.speed_cmd
    }

    fn set_motor_command(&mut self, world: &mut PhysicsWorld, cmd: MotorCommand) {
        let Some(m) = &self.motor else { return };
        let v = m.command_target(cmd);
        self.set_belt_speed(world, v);
        self.motor_cmd = Some(cmd);
    }

    fn holds_belt(&self) -> bool {
        !self.unpowered && self.motor_cmd.is_none() && self.speed_cmd == 0.0
    }

    fn set_unpowered(&mut self, world: &mut PhysicsWorld, unpowered: bool) -> bool {
        if unpowered == self.unpowered {
            return true;
        }
        self.unpowered = unpowered;
        self.hold = None;
        // Unpowered: no link motor gives any force until `after_step` shares out the links'
        // own weights. Powered again without a motor model: no limit, as built; with one,
        // the next `after_step` sets the limits.
        let cap = if unpowered { 0.0 } else { f32::MAX };
        for l in &self.links {
            if let Some(j) = world.impulse_joints.get_mut(l.joint, true) {
                j.data.set_motor_max_force(l.kind.motor_axis(), cap);
            }
        }
        self.force_limit = 0.0;
        true
    }

    fn belt_force_limit(&self) -> Option<f64> {
        self.motor.as_ref().map(|_| {
            if self.unpowered {
                0.0
            } else {
                self.force_limit
            }
        })
    }

    fn after_step(&mut self, world: &mut PhysicsWorld, dt: f64) {
        // With a motor the belt moves as fast as its links did (it slows when the motor cannot
        // hold the command); without, exactly at the command.
        // Unpowered (a fault), the belt moves as its links do, as with a motor.
        let loaded = (self.motor.is_some() || self.unpowered).then(|| {
            let loads = self.link_loads(world);
            let v = Self::loaded_belt_speed(&self.link_speeds(world), &loads);
            (loads, v)
        });
        let speed = match &loaded {
            Some((_, v)) => *v,
            None => self.speed_cmd,
        };
        self.position += speed * dt;
        let (phi, wraps) = self.phase();
        // Where the links should be before any wrap: the old wrap count's phase.
        let phi_unwrapped = phi + (wraps - self.wraps) as f64 * self.pitch.unwrap_or(0.0);
        let bodies = &mut world.bodies;
        let parent = &bodies[self.parent];
        let parent_pose = *parent.position();
        let parent_linvel = parent.linvel();
        let parent_angvel = parent.angvel();
        let parent_com = parent.center_of_mass();
        let mut measured = 0.0;
        for l in &self.links {
            let expected = parent_pose * l.kind.shift(phi);
            let link = &bodies[l.body];
            let actual = *link.position();
            let before = parent_pose * l.kind.shift(phi_unwrapped);
            // Joint error before the snap.
            let com_err = (actual.transform_point(l.local_com)
                - before.transform_point(l.local_com))
            .length() as f64;
            let rot_err = (before.rotation.inverse() * actual.rotation)
                .normalize()
                .to_axis_angle()
                .1
                .abs() as f64;
            let rot_err = rot_err.min(std::f64::consts::TAU - rot_err);
            self.error.distance = self.error.distance.max(com_err);
            self.error.angle = self.error.angle.max(rot_err);
            // Relative velocity along the joint, as belt speed.
            let com_w = actual.transform_point(l.local_com);
            let carried = parent_linvel + parent_angvel.cross(com_w - parent_com);
            measured += match l.kind {
                LinkKind::Slide { dir } => {
                    ((link.linvel() - carried).dot(parent_pose.rotation * f(dir))) as f64
                }
                LinkKind::Turn { axis, radius, .. } => {
                    ((link.angvel() - parent_angvel).dot(parent_pose.rotation * f(axis))) as f64
                        * radius
                }
            };
            // Snap to the exact pose, keeping the world velocity the solver gave (which
            // keeps the momentum: carrying the relative twist over to the new pose instead
            // gives the belt a net impulse every pitch, paid by the chassis through the joint).
            bodies[l.body].set_position(expected, false);
        }
        if !self.links.is_empty() {
            self.speed_measured = measured / self.links.len() as f64;
        }
        if wraps != self.wraps && self.shapes.len() > 1 {
            self.reassign_shapes(world, wraps);
        }
        self.wraps = wraps;
        if self.unpowered {
            if let Some((loads, v)) = loaded {
                // No drive force: each link carries only its own weight along the belt.
                self.speed_measured = v;
                self.limit_link_forces(world, 0.0, &loads, v);
            }
        } else if let (Some(m), Some((loads, v))) = (self.motor.clone(), loaded) {
            self.speed_measured = v;
            self.hold = (self.speed_cmd == 0.0 && self.motor_cmd.is_none())
                .then(|| self.hold.unwrap_or(self.position));
            self.force_limit = match self.motor_cmd {
                None => m.max_belt_force(v, self.speed_cmd),
                Some(cmd) => m.commanded_belt_force(cmd, v),
            };
            self.limit_link_forces(world, self.force_limit, &loads, v);
        }
    }

    fn belt_position(&self) -> f64 {
        self.position
    }

    fn belt_phase(&self) -> f64 {
        self.phase().0
    }

    fn measured_belt_speed(&self) -> f64 {
        self.speed_measured
    }

    fn bodies(&self) -> Vec<RigidBodyHandle> {
        self.links.iter().map(|l| l.body).collect()
    }

    fn grousers_on_footprints(&self) -> bool {
        self.per_grouser
    }

    fn grouser_colliders(&self) -> Vec<ColliderHandle> {
        self.links
            .iter()
            .flat_map(|l| l.grousers.iter().map(|&(h, _)| h))
            .collect()
    }

    fn link_error(&self) -> LinkError {
        self.error
    }

    fn reset_link_error(&mut self) {
        self.error = LinkError::default();
    }

    fn link_relative_poses(&self, world: &PhysicsWorld) -> Vec<(Pose, Pose)> {
        let (phi, _) = self.phase();
        let parent = *world.bodies[self.parent].position();
        self.links
            .iter()
            .map(|l| {
                let rel = parent.inv_mul(world.bodies[l.body].position());
                (rel, l.kind.shift(phi))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{compile_scenario, load_vehicle, read_toml};
    use std::path::Path;

    /// With two grouser shapes in turn, the shape found at a given place on the loop follows
    /// the belt: after the belt has moved by `w` pitches, slot `k` shows shape `(k - w) mod 2`.
    #[test]
    fn alternating_grouser_shapes_travel_with_the_belt() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let spec: crate::spec::ScenarioSpec =
            read_toml(&root.join("scenarios/packbot_flat.toml")).unwrap();
        let mut v = load_vehicle(&root.join("vehicles/packbot510.toml")).unwrap();
        for t in &mut v.tracks {
            let g = t.grousers.as_mut().unwrap();
            let tall = GrouserShape::Box {
                half: DVec3::new(0.0025, 0.0375, 0.008),
                centre: DVec3::new(0.0, 0.0, 0.008),
            };
            g.shapes.push(tall);
        }
        let sc = compile_scenario(&spec, v, &root).unwrap();
        let mut world = PhysicsWorld::new();
        let parent = world.bodies.insert(RigidBodyBuilder::fixed());
        let mut ctx = BuildContext {
            world: &mut world,
            parent,
            index: 0,
            groups: crate::tracks::vehicle_groups(),
            min_link_mass: sc.solver.min_link_mass,
        };
        let mut track = SegmentLinks::build(&mut ctx, &sc.vehicle.tracks[0]).unwrap();
        let tall =
            |s: &dyn rapier3d::parry::shape::Shape| s.as_cuboid().unwrap().half_extents.z > 0.006;
        assert!(track.grouser_slots(&world, tall).iter().all(|k| k % 2 == 1));
        let pitch = track.pitch.unwrap();
        track.set_belt_speed(&mut world, 0.3);
        // Move the belt until it has wrapped once (moved by about one pitch).
        while track.wraps == 0 {
            track.after_step(&mut world, 0.001);
        }
        assert!((track.belt_position() - pitch / 2.0).abs() < 0.001);
        let slots = track.grouser_slots(&world, tall);
        assert!(slots.iter().all(|k| k % 2 == 0), "{slots:?}");
        assert_eq!(slots.len(), 20);
    }
}
