//! The multiple-plate track (paper Sec. II-B): a closed chain of thin plates on hinge joints
//! wrapped around sprocket and idler wheels, driven by the sprocket. Slow, deformable reference.
//!
//! # What is built (per track)
//! - **Plates.** `N` plates: the track's grouser count if it still has grousers, else
//!   `round(L / DEFAULT_PLATE_PITCH_M)` (`L` the loop length; 40 on the PackBot, its real
//!   grouser count). The hinge line is the loop moved inwards by half the belt thickness (the
//!   plates' mid-thickness); the `N` hinge points lie on it with all chords equal to the pitch
//!   `p`, `p` solved so that the chain closes exactly (on arcs a chord is shorter than its arc, so
//!   `p` is slightly above `L_hinge / N`). Each plate is a cuboid between two hinge points
//!   (length `p - PLATE_GAP_M`, belt thickness, track width) with a cleat (grouser) cuboid in the
//!   middle of its outer face: the track's grouser height and box length when it has grousers,
//!   else [`DEFAULT_CLEAT_HEIGHT_M`] x [`DEFAULT_CLEAT_LENGTH_M`] (the PackBot's 8 x 5 mm;
//!   the other methods' builders drop the grousers, but this one keeps them).
//!   Consecutive plates are joined by revolute joints about the loop's lateral axis at their
//!   shared hinge points; the last joins the first.
//! - **Wheels.** One wheel per distinct arc centre of the loop, as a dynamic body jointed to the
//!   parent. The rearmost (smallest x in the track frame) is the **sprocket**: a revolute joint
//!   with a velocity motor at `v / r_eff`. The frontmost is the **idler** and tensioner: a joint
//!   that leaves it free to spin and to slide along the line from the sprocket to it, pushed
//!   outwards by a spring ([`TENSIONER_FORCE_N`] at the rest position, travel limited to
//!   [`TENSIONER_TRAVEL_M`]). Any other arc gets a free idler on a plain revolute joint. A
//!   wheel's radius is the distance from its centre to the inner faces of the plates wrapped on
//!   it, minus [`WHEEL_CLEARANCE_M`]; thin flanges on both sides, slightly larger than the wheel,
//!   keep the chain from sliding off sideways.
//! - **Drive.** By friction only: the sprocket's collider has friction [`SPROCKET_FRICTION`]
//!   with the `max` combine rule against the plates (the idlers [`IDLER_FRICTION`]); with the
//!   chain pre-tensioned by the idler's spring the capstan effect (`e^(mu * pi)`) keeps the chain
//!   from slipping. The chain speed for a sprocket turning at `w` without slip is `w * r_eff`
//!   with `r_eff = p / (2 asin(p / (2 R)))`, `R` the hinge circle of the chain lying on the
//!   sprocket (a polygon, not a circle): this is what the motor targets and what
//!   [`Plates::measured_belt_speed`] reports.
//! - **Masses.** Plates get the belt's mass split evenly (25 g on the PackBot); no floor was
//!   needed for stability. Wheels get `min_mass` each (the simulation's link-mass floor, 0.5 kg
//!   by default), as the multiple-wheel baseline's wheels do.
//! - **Collision groups.** Plates are members of the vehicle group and of [`PLATE_GROUP`] and
//!   filter out both: they touch the world but not their own vehicle or each other. Wheels are
//!   members of [`WHEEL_GROUP`] only and see only plates: no contact with the world or the body.
//! - **Contact stiffness (a world-wide side effect).** Rapier's soft contacts are springs of
//!   stiffness `m_eff * (2 pi f)^2`, so 25 g plates at the default 30 Hz sank 12 mm into the
//!   sprocket under the chain tension (body 11 mm low, speed 12 % low). Building a plate track
//!   raises the world's contact frequency to at least [`CONTACT_FREQUENCY_HZ`] (static contacts
//!   twice that), which affects every contact of the scenario. (A 0.1 kg plate floor alone did
//!   not fix it.)
//!
//! # What it achieves (PackBot 510, dt = 1 ms, 4 iterations; `tests/suite/plates.rs`)
//! Flat ground at 0.3 m/s: 0.304 m/s over seconds 2-6, body at 0.085-0.087 m; a 0.05 m step is
//! climbed. A 0.10 m step (`scenarios/packbot_step.toml`) is *not* climbed: the vehicle stays
//! stable but stalls nose-up against the edge (also with sprocket friction 5 and 80 N
//! tension): friction drive by a single sprocket is the likely limit. Release build: about
//! 1.3-1.4 x real time (the paper's method: about 8 x on the same machine).

use super::common::{insert_wheel_body, set_motor_velocity, wheel_joint};
use super::track::{BuildContext, Track};
use crate::error::{Error, Result};
use crate::model::TrackModel;
use glam::{DMat3, DQuat, DVec3};
use rapier3d::prelude::*;

/// Collision group of every plate (on top of the vehicle group).
pub const PLATE_GROUP: Group = Group::GROUP_3;
/// Collision group of sprockets and idlers: they only see plates.
pub const WHEEL_GROUP: Group = Group::GROUP_4;
/// Plate pitch used when the track has no grousers, m (the PackBot's 40 grousers give 38 mm).
pub const DEFAULT_PLATE_PITCH_M: f64 = 0.038;
/// Cleat height when the track has no grousers, m.
pub const DEFAULT_CLEAT_HEIGHT_M: f64 = 0.008;
/// Cleat length along the belt when the track has no box grousers, m.
pub const DEFAULT_CLEAT_LENGTH_M: f64 = 0.005;
/// Gap between consecutive plates along the belt, m.
pub const PLATE_GAP_M: f64 = 0.002;
/// Radial clearance between a wheel and the plates wrapped on it at rest, m.
pub const WHEEL_CLEARANCE_M: f64 = 0.0005;
/// Friction of the sprocket against the plates (combine rule `max`).
pub const SPROCKET_FRICTION: f64 = 2.0;
/// Friction of the idlers against the plates (combine rule `max`).
pub const IDLER_FRICTION: f64 = 1.0;
/// Force of the tensioner spring at the idler's rest position, N.
pub const TENSIONER_FORCE_N: f64 = 30.0;
/// Stiffness of the tensioner spring, N/m.
pub const TENSIONER_STIFFNESS_N_PER_M: f64 = 5000.0;
/// Damping of the tensioner, N s/m.
pub const TENSIONER_DAMPING_N_S_PER_M: f64 = 100.0;
/// Travel of the tensioner from its rest position, m: [back, forward].
pub const TENSIONER_TRAVEL_M: [f64; 2] = [-0.003, 0.010];
/// Natural frequency of dynamic contacts in a world with plate tracks, Hz (static contacts:
/// twice this). Rapier's default is 30 Hz (60 Hz static).
pub const CONTACT_FREQUENCY_HZ: f64 = 120.0;
/// Radial height of the wheel flanges above the wheel, m.
pub const FLANGE_HEIGHT_M: f64 = 0.004;
/// Flange thickness, m.
pub const FLANGE_THICKNESS_M: f64 = 0.002;

use crate::check::{f, q};

/// A plate-chain track at run time.
#[derive(Debug)]
pub struct Plates {
    /// Every body this track added (plates and wheels).
    bodies: Vec<RigidBodyHandle>,
    /// The parent (body or flipper).
    parent: RigidBodyHandle,
    /// The sprocket.
    sprocket: RigidBodyHandle,
    /// The sprocket's motorised joint.
    sprocket_joint: ImpulseJointHandle,
    /// The loop's lateral axis in the parent frame.
    axis: DVec3,
    /// Chain speed per sprocket angular speed, m/rad.
    r_eff: f64,
    /// Grouser pitch of the track description, m, for the reported phase.
    pitch: Option<f64>,
    position: f64,
    speed_cmd: f64,
    speed_measured: f64,
    /// The sprocket's drive let go (an instructor's fault): the chain free-wheels.
    unpowered: bool,
}

/// A point of the hinge line (the loop moved inwards by `inset`) at loop arc length `s`.
fn hinge_point(track: &TrackModel, inset: f64, s: f64) -> DVec3 {
    let fr = track.path.frame_at(s);
    fr.origin - fr.normal * inset
}

/// The arc length `s' > s` whose hinge point is at distance `p` from the one at `s`.
fn next_hinge(track: &TrackModel, inset: f64, s: f64, p: f64) -> f64 {
    let a = hinge_point(track, inset, s);
    let (mut lo, mut hi) = (s, s + 3.0 * p);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (hinge_point(track, inset, mid) - a).length() < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Arc lengths of `n` hinge points starting at 0 with chords `p`; the last entry is where the
/// `n`-th chord ends (the loop closes when it equals the loop length).
fn walk(track: &TrackModel, inset: f64, n: usize, p: f64) -> Vec<f64> {
    let mut s = vec![0.0];
    for i in 0..n {
        let next = next_hinge(track, inset, s[i], p);
        s.push(next);
    }
    s
}

/// Hinge arc lengths (n + 1 entries, the last = L) and the pitch of a closed chain of `n`
/// plates.
fn chain_layout(track: &TrackModel, inset: f64, n: usize) -> Result<(Vec<f64>, f64), String> {
    let l = track.path.length();
    let (mut lo, mut hi) = (0.5 * l / n as f64, 1.2 * l / n as f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if *walk(track, inset, n, mid).last().unwrap_or(&0.0) < l {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let s = walk(track, inset, n, p);
    let closure = (hinge_point(track, inset, s[n]) - hinge_point(track, inset, 0.0)).length();
    if closure > 1e-6 {
        return Err(format!(
            "track {}: could not close a chain of {n} plates on its loop (gap {closure:.2e} m)",
            track.name
        ));
    }
    Ok((s, p))
}

/// Distinct arc centres of the loop with the arc's radius (the first arc's, for repeats).
fn wheel_sites(track: &TrackModel) -> Vec<(DVec3, f64)> {
    let mut sites: Vec<(DVec3, f64)> = Vec::new();
    for seg in track.path.segments() {
        if let (Some(c), Some(r)) = (seg.arc_centre(), seg.radius())
            && !sites.iter().any(|(c2, _)| (*c2 - c).length() < 1e-6)
        {
            sites.push((c, r));
        }
    }
    sites
}

/// Rotation whose columns are `x`, `y`, `x` cross `y`.
fn frame_rot(x: DVec3, y: DVec3) -> DQuat {
    DQuat::from_mat3(&DMat3::from_cols(x, y, x.cross(y)))
}

/// The chain's layout: plate count, cleat size and hinge positions.
struct Layout {
    /// Loop arc length of every hinge point (n + 1 values, the last closing the loop), m.
    s: Vec<f64>,
    /// Chord between hinge points, m.
    p: f64,
    /// Cleat height and length, m.
    cleat: (f64, f64),
    /// Wheel centres and loop radii (parent frame), m.
    sites: Vec<(DVec3, f64)>,
}

/// Plate count, cleats, hinge points and wheel sites of `track`, checked.
fn layout(track: &TrackModel) -> Result<Layout, String> {
    let inset = track.belt_thickness / 2.0;
    let l = track.path.length();
    let n = match &track.grousers {
        Some(g) => g.layout.count,
        None => (l / DEFAULT_PLATE_PITCH_M).round() as usize,
    }
    .max(8);
    let cleat = match &track.grousers {
        Some(g) => (
            g.height,
            g.shapes
                .iter()
                .find_map(|s| match s {
                    crate::model::GrouserShape::Box { half, .. } => Some(2.0 * half.x),
                    _ => None,
                })
                .unwrap_or(DEFAULT_CLEAT_LENGTH_M),
        ),
        None => (DEFAULT_CLEAT_HEIGHT_M, DEFAULT_CLEAT_LENGTH_M),
    };
    let (s, p) = chain_layout(track, inset, n)?;
    if p <= PLATE_GAP_M * 2.0 {
        return Err(format!(
            "track {}: plates of pitch {p:.4} m are too short",
            track.name
        ));
    }
    let sites = wheel_sites(track);
    if sites.len() < 2 {
        return Err(format!(
            "track {}: the multiple-plate model needs at least two arcs (sprocket and idler)",
            track.name
        ));
    }
    Ok(Layout { s, p, cleat, sites })
}

/// Raises the world's contact stiffness for light plates. Rapier's soft contacts are springs
/// of stiffness m_eff * (2 pi f)^2: with 25 g plates the default 30 Hz lets the chain sink
/// 12 mm into the sprocket under its own tension.
fn stiffen_contacts(world: &mut PhysicsWorld) {
    let ip = &mut world.integration_parameters;
    ip.contact_softness.natural_frequency = ip
        .contact_softness
        .natural_frequency
        .max(CONTACT_FREQUENCY_HZ as f32);
    ip.static_contact_softness.natural_frequency = ip
        .static_contact_softness
        .natural_frequency
        .max(2.0 * CONTACT_FREQUENCY_HZ as f32);
}

/// Inserts the plates (with their cleats) and the hinges between them; returns the plates.
fn insert_plates(
    world: &mut PhysicsWorld,
    track: &TrackModel,
    parent: RigidBodyHandle,
    lay: &Layout,
    plate_groups: InteractionGroups,
) -> Vec<RigidBodyHandle> {
    let lateral = track.path.axis();
    let t = track.belt_thickness;
    let inset = t / 2.0;
    let (s, p, (cleat_h, cleat_l)) = (&lay.s, lay.p, lay.cleat);
    let n = s.len() - 1;
    let parent_pose = *world.bodies[parent].position();
    let mass = track.belt_mass / n as f64;
    let len = p - PLATE_GAP_M;
    let w = track.width;
    let inertia = Vector::new(
        (mass * (w * w + t * t) / 12.0) as f32,
        (mass * (len * len + t * t) / 12.0) as f32,
        (mass * (len * len + w * w) / 12.0) as f32,
    );
    let mut plates = Vec::with_capacity(n);
    for i in 0..n {
        let a = hinge_point(track, inset, s[i]);
        let b = hinge_point(track, inset, s[i + 1]);
        let x = (b - a).normalize();
        let rot = frame_rot(x, lateral);
        let pose = parent_pose * Pose::from_parts(f(0.5 * (a + b)), q(rot));
        let h = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(pose)
                .additional_mass_properties(MassProperties::new(Vector::ZERO, mass as f32, inertia))
                .can_sleep(false),
        );
        let base = |c: ColliderBuilder| {
            c.density(0.0)
                .friction(track.friction as f32)
                .friction_combine_rule(track.combine)
                .collision_groups(plate_groups)
        };
        let plate = ColliderBuilder::cuboid((len / 2.0) as f32, (w / 2.0) as f32, (t / 2.0) as f32);
        world
            .colliders
            .insert_with_parent(base(plate), h, &mut world.bodies);
        if cleat_h > 0.0 {
            let cleat = ColliderBuilder::cuboid(
                (cleat_l / 2.0) as f32,
                (w / 2.0) as f32,
                (cleat_h / 2.0) as f32,
            )
            .translation(Vector::new(
                ((len - cleat_l) / 2.0) as f32,
                0.0,
                (t / 2.0 + cleat_h / 2.0) as f32,
            ));
            world
                .colliders
                .insert_with_parent(base(cleat), h, &mut world.bodies);
        }
        plates.push(h);
    }
    let half = (p / 2.0) as f32;
    for i in 0..n {
        let joint = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(Vector::new(half, 0.0, 0.0))
            .local_anchor2(Vector::new(-half, 0.0, 0.0))
            .contacts_enabled(false);
        world
            .impulse_joints
            .insert(plates[i], plates[(i + 1) % n], joint, true);
    }
    plates
}

/// Inserts a wheel's cylinder and its two flanges on body `h`.
fn insert_wheel_colliders(
    world: &mut PhysicsWorld,
    h: RigidBodyHandle,
    lateral: DVec3,
    radius: f64,
    w: f64,
    friction: f64,
    wheel_groups: InteractionGroups,
) {
    let wheel_rot = q(DQuat::from_rotation_arc(DVec3::Y, lateral));
    let wheel = ColliderBuilder::cylinder((w / 2.0) as f32, radius as f32)
        .rotation(wheel_rot.to_scaled_axis())
        .density(0.0)
        .friction(friction as f32)
        .friction_combine_rule(CoefficientCombineRule::Max)
        .collision_groups(wheel_groups);
    world
        .colliders
        .insert_with_parent(wheel, h, &mut world.bodies);
    for side in [-1.0, 1.0] {
        let y = side * (w / 2.0 + FLANGE_THICKNESS_M / 2.0 + 0.001);
        let flange = ColliderBuilder::cylinder(
            (FLANGE_THICKNESS_M / 2.0) as f32,
            (radius + FLANGE_HEIGHT_M) as f32,
        )
        .position(Pose::from_parts(f(lateral * y), wheel_rot))
        .density(0.0)
        .friction(0.0)
        .friction_combine_rule(CoefficientCombineRule::Min)
        .collision_groups(wheel_groups);
        world
            .colliders
            .insert_with_parent(flange, h, &mut world.bodies);
    }
}

/// The idler's tensioner joint: free spin about the lateral axis (joint x) and a spring along
/// the line from the sprocket at `rear` (joint y).
fn tensioner_joint(lateral: DVec3, centre: DVec3, rear: DVec3) -> GenericJointBuilder {
    let dir = (centre - rear).normalize();
    let frame_rot = q(frame_rot(lateral, dir));
    let k_spring = TENSIONER_STIFFNESS_N_PER_M;
    GenericJointBuilder::new(
        JointAxesMask::LIN_X | JointAxesMask::LIN_Z | JointAxesMask::ANG_Y | JointAxesMask::ANG_Z,
    )
    .local_frame1(Pose::from_parts(f(centre), frame_rot))
    .local_frame2(Pose::from_parts(Vector::ZERO, frame_rot))
    .contacts_enabled(false)
    .limits(
        JointAxis::LinY,
        [TENSIONER_TRAVEL_M[0] as f32, TENSIONER_TRAVEL_M[1] as f32],
    )
    .motor_model(JointAxis::LinY, MotorModel::ForceBased)
    .motor_position(
        JointAxis::LinY,
        (TENSIONER_FORCE_N / k_spring) as f32,
        k_spring as f32,
        TENSIONER_DAMPING_N_S_PER_M as f32,
    )
}

/// The sprocket: its body, motorised joint and effective radius, m.
type Sprocket = (RigidBodyHandle, ImpulseJointHandle, f64);

/// Inserts the sprocket (rearmost arc), the tensioned idler (frontmost) and free idlers;
/// returns their bodies and the sprocket.
fn insert_wheels(
    world: &mut PhysicsWorld,
    track: &TrackModel,
    parent: RigidBodyHandle,
    lay: &Layout,
    min_mass: f64,
) -> Result<(Vec<RigidBodyHandle>, Sprocket), String> {
    let lateral = track.path.axis();
    let inset = track.belt_thickness / 2.0;
    let (sites, p, w) = (&lay.sites, lay.p, track.width);
    let parent_pose = *world.bodies[parent].position();
    let wheel_groups = InteractionGroups::new(WHEEL_GROUP, PLATE_GROUP, InteractionTestMode::And);
    let rear = (0..sites.len())
        .min_by(|&a, &b| sites[a].0.x.total_cmp(&sites[b].0.x))
        .unwrap_or(0);
    let front = (0..sites.len())
        .max_by(|&a, &b| sites[a].0.x.total_cmp(&sites[b].0.x))
        .unwrap_or(1);
    let mut bodies = Vec::new();
    let mut sprocket = None;
    for (k, &(centre, r)) in sites.iter().enumerate() {
        let r_hinge = r - inset;
        let half_p = p / 2.0;
        if r_hinge <= half_p + inset {
            return Err(format!(
                "track {}: an arc of radius {r:.3} m is too tight for plates of pitch {p:.3} m",
                track.name
            ));
        }
        let radius = (r_hinge * r_hinge - half_p * half_p).sqrt() - inset - WHEEL_CLEARANCE_M;
        let m = min_mass.max(1e-3);
        let h = insert_wheel_body(world, parent_pose, centre, lateral, radius, w, m);
        let friction = if k == rear {
            SPROCKET_FRICTION
        } else {
            IDLER_FRICTION
        };
        insert_wheel_colliders(world, h, lateral, radius, w, friction, wheel_groups);
        if k == front && k != rear {
            let joint = tensioner_joint(lateral, centre, sites[rear].0);
            world.impulse_joints.insert(parent, h, joint, true);
        } else {
            let joint = wheel_joint(lateral, centre, k == rear);
            let j = world.impulse_joints.insert(parent, h, joint, true);
            if k == rear {
                // Hinge circle of the chain lying on the sprocket.
                let apothem = radius + inset;
                let r_h = (apothem * apothem + half_p * half_p).sqrt();
                let r_eff = p / (2.0 * (p / (2.0 * r_h)).asin());
                sprocket = Some((h, j, r_eff));
            }
        }
        bodies.push(h);
    }
    let sprocket = sprocket.ok_or_else(|| format!("track {}: no sprocket", track.name))?;
    Ok((bodies, sprocket))
}

impl Plates {
    /// Builds the chain for `track` on `ctx.parent` (keeping its grousers as cleats).
    pub fn build(ctx: &mut BuildContext, track: &TrackModel) -> Result<Self> {
        let lay = layout(track).map_err(Error::Build)?;
        let world = &mut *ctx.world;
        let groups = ctx.groups;
        let plate_groups = InteractionGroups::new(
            groups.memberships | PLATE_GROUP,
            groups.filter.difference(PLATE_GROUP),
            InteractionTestMode::And,
        );
        stiffen_contacts(world);
        let mut bodies = insert_plates(world, track, ctx.parent, &lay, plate_groups);
        let (wheels, (sprocket, sprocket_joint, r_eff)) =
            insert_wheels(world, track, ctx.parent, &lay, ctx.min_link_mass)
                .map_err(Error::Build)?;
        bodies.extend(wheels);
        Ok(Plates {
            bodies,
            parent: ctx.parent,
            sprocket,
            sprocket_joint,
            axis: track.path.axis(),
            r_eff,
            pitch: track.grousers.as_ref().map(|g| g.layout.pitch(&track.path)),
            position: 0.0,
            speed_cmd: 0.0,
            speed_measured: 0.0,
            unpowered: false,
        })
    }
}

impl Track for Plates {
    fn set_belt_speed(&mut self, world: &mut PhysicsWorld, v: f64) {
        self.speed_cmd = v;
        set_motor_velocity(
            world,
            self.sprocket_joint,
            JointAxis::AngX,
            (v / self.r_eff) as f32,
        );
    }

    fn commanded_belt_speed(&self) -> f64 {
        self.speed_cmd
    }

    fn holds_belt(&self) -> bool {
        !self.unpowered && self.speed_cmd == 0.0
    }

    /// Unpowered: the sprocket's motor gives no torque (its force limit 0), so the sprocket,
    /// the idlers and the chain turn freely, as the ground and the vehicle move them.
    fn set_unpowered(&mut self, world: &mut PhysicsWorld, unpowered: bool) -> bool {
        self.unpowered = unpowered;
        let cap = if unpowered { 0.0 } else { f32::MAX };
        if let Some(j) = world.impulse_joints.get_mut(self.sprocket_joint, true) {
            j.data.set_motor_max_force(JointAxis::AngX, cap);
        }
        true
    }

    /// The chain is free: only the belt position is integrated (the commanded speed; the
    /// measured one while unpowered) and the speed measured.
    fn after_step(&mut self, world: &mut PhysicsWorld, dt: f64) {
        if !self.unpowered {
            self.position += self.speed_cmd * dt;
        }
        self.speed_measured = self.measured_belt_speed_now(world);
        if self.unpowered {
            self.position += self.speed_measured * dt;
        }
    }

    fn belt_position(&self) -> f64 {
        self.position
    }

    fn belt_phase(&self) -> f64 {
        super::phase(self.position, self.pitch)
    }

    /// The sprocket's angular speed relative to the parent times its effective radius.
    fn measured_belt_speed(&self) -> f64 {
        self.speed_measured
    }

    fn bodies(&self) -> Vec<RigidBodyHandle> {
        self.bodies.clone()
    }
}

impl Plates {
    /// Belt speed from the chain now, m/s.
    fn measured_belt_speed_now(&self, world: &PhysicsWorld) -> f64 {
        let parent = &world.bodies[self.parent];
        let axis = parent.rotation() * f(self.axis);
        (world.bodies[self.sprocket].angvel() - parent.angvel()).dot(axis) as f64 * self.r_eff
    }
}
