//! The running state (MuJoCo's `mjData` idea): a Rapier world holding one vehicle built from a
//! [`VehicleModel`] by the chosen [`TrackMethod`] (the paper's by default; the baselines are in
//! `baselines.rs` and `plates.rs`), advanced by [`Simulation::step`].
//!
//! # How a track is built (paper Sec. III)
//! Each included segment of a track's loop becomes one dynamic rigid body (a *segment link*)
//! whose frame coincides with its parent's frame at rest. A straight link carries a thin cuboid
//! belt and is joined to the parent by a prismatic joint along the segment; an arc link carries
//! a cylinder of the loop radius and is joined by a revolute joint on the pulley axis. Each link
//! also carries, as separate colliders, the grousers whose footprints lie on its segment at rest.
//! Joint velocity motors (velocity-only, effectively unlimited force) move every link at belt
//! speed: `v` along straights, `v / r` about arcs.
//!
//! # Rollback
//! The belt position `s` is integrated from the command and kept unwrapped (`f64`). With
//! grousers of pitch `p = L / N`, the phase is `phi = s - p * round(s / p)`, in `[-p/2, p/2)`.
//! After every physics step each link is put exactly at `parent * shift(phi)`, keeping the world
//! velocity the solver gave it. Between wraps that only removes the solver's joint error (a few
//! micrometres, reported as `max_link_error_*`); when `s` crosses a half pitch the phase wraps and
//! every link jumps back by exactly one pitch, which leaves the grouser pattern where it was, so
//! the track's shape is exact forever. Without grousers `phi = 0`: links are restored every step.
//! When a track has several grouser shapes in turn, the colliders' shapes are re-assigned on each
//! wrap so the pattern travels with the belt.
//!
//! # Choices (and why)
//! - Link mass: the belt's real mass split by segment length, but at least
//!   [`MIN_LINK_MASS_KG`] by default (`simulation.min_link_mass_kg`): on the PackBot climbing a
//!   step the floor halves the per-step joint error (1.5 mm / 31 mrad -> 0.8 mm / 14 mrad);
//!   on flat ground it makes no difference (docs/DESIGN.md).
//! - Belt and grousers are separate colliders (not one compound), with Rapier's contact
//!   clustering off by default: clustering merged grouser contacts and let them sink mm deep.
//! - Belt links never collide with their own vehicle (collision groups); they collide with the
//!   world and other vehicles. Belt friction combines with `min` unless the file says otherwise.

use crate::error::{Error, Result};
use crate::model::*;
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// Default smallest mass given to a segment link, kg (see the module docs).
pub const MIN_LINK_MASS_KG: f64 = 0.5;
/// Damping gain of the belt velocity motors (acceleration-based: constraint compliance
/// 1 / (dt * gain), i.e. 1e-3 at 1 ms: a hard velocity constraint).
pub const BELT_MOTOR_GAIN: f32 = 1.0e6;
/// Clearance between the vehicle's lowest point and the ground at start, m.
pub const START_CLEARANCE_M: f64 = 0.001;
/// Linear speed above which a body is declared to have blown up, m/s.
pub const MAX_SPEED_MPS: f32 = 50.0;

const WORLD_GROUP: Group = Group::GROUP_1;
const VEHICLE_GROUP: Group = Group::GROUP_2;

use crate::check::{f, q};

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

#[derive(Debug)]
struct LinkRt {
    body: RigidBodyHandle,
    joint: ImpulseJointHandle,
    kind: LinkKind,
    local_com: Vector,
    /// Grouser colliders with their slot index k on the loop.
    grousers: Vec<(ColliderHandle, usize)>,
}

/// What a track is made of besides segment links (other track methods).
#[derive(Debug)]
enum Extra {
    /// Segment links only (the paper's method).
    None,
    /// Multiple wheels.
    Wheels(Vec<crate::baselines::WheelRt>),
    /// Constraint to ground: the outline is on the parent; belt speed goes to the hooks.
    Surface,
    /// Multiple plates.
    Plates(Box<crate::plates::PlateTrack>),
}

/// Friction of the constraint-to-ground track outline: Gazebo's TrackController example gives
/// the track mu2 = 150 along the belt ("set a very high mu for the track links" instead of
/// grousers); Rapier's friction is isotropic, and with the min rule the other surface decides.
pub const SURFACE_TRACK_FRICTION: f64 = 150.0;

#[derive(Debug)]
struct TrackRt {
    extra: Extra,
    parent: RigidBodyHandle,
    links: Vec<LinkRt>,
    pitch: Option<f64>,
    shapes: Vec<SharedShape>,
    /// Unwrapped belt position, m.
    position: f64,
    /// Commanded belt speed, m/s.
    speed_cmd: f64,
    /// Belt speed measured from the links' joint velocities before the snap, m/s.
    speed_measured: f64,
    wraps: i64,
}

impl TrackRt {
    fn phase(&self) -> (f64, i64) {
        match self.pitch {
            Some(p) => {
                let w = (self.position / p).round();
                (self.position - w * p, w as i64)
            }
            None => (0.0, 0),
        }
    }
}

#[derive(Debug)]
struct FlipperRt {
    body: RigidBodyHandle,
    joint: ImpulseJointHandle,
    axis: DVec3,
    target: f64,
    stiffness: f32,
    damping: f32,
}

/// Points of a shape (local frame) whose lowest one is the shape's lowest point, up to the
/// sampling of round shapes.
fn shape_points(shape: &dyn rapier3d::parry::shape::Shape) -> Vec<Vector> {
    if let Some(c) = shape.as_cuboid() {
        let h = c.half_extents;
        let mut v = Vec::with_capacity(8);
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    v.push(Vector::new(sx * h.x, sy * h.y, sz * h.z));
                }
            }
        }
        v
    } else if let Some(c) = shape.as_cylinder() {
        (0..64)
            .flat_map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 64.0;
                let (x, z) = (c.radius * a.cos(), c.radius * a.sin());
                [
                    Vector::new(x, c.half_height, z),
                    Vector::new(x, -c.half_height, z),
                ]
            })
            .collect()
    } else if let Some(c) = shape.as_convex_polyhedron() {
        c.points().to_vec()
    } else {
        let a = shape.compute_local_aabb();
        vec![a.mins, a.maxs, Vector::new(a.mins.x, a.maxs.y, a.mins.z)]
    }
}

/// Pose of a body as REP 103 position and roll/pitch/yaw (Z-Y-X), m and rad.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PoseRpy {
    /// m.
    pub x: f64,
    /// m.
    pub y: f64,
    /// m.
    pub z: f64,
    /// rad, about x.
    pub roll: f64,
    /// rad, about y.
    pub pitch: f64,
    /// rad, about z.
    pub yaw: f64,
}

impl PoseRpy {
    /// Converts a Rapier pose.
    pub fn from_pose(p: &Pose) -> Self {
        let r = p.rotation;
        let (w, x, y, z) = (r.w as f64, r.x as f64, r.y as f64, r.z as f64);
        PoseRpy {
            x: p.translation.x as f64,
            y: p.translation.y as f64,
            z: p.translation.z as f64,
            roll: (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y)),
            pitch: (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin(),
            yaw: (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
        }
    }
}

/// One recorded instant of the vehicle's state.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Simulated time, s.
    pub t: f64,
    /// Body pose.
    pub pose: PoseRpy,
    /// Body linear velocity (world), m/s.
    pub linvel: [f64; 3],
    /// Body angular velocity (world), rad/s.
    pub angvel: [f64; 3],
    /// Measured belt speed per track, m/s.
    pub belt_speed: Vec<f64>,
    /// Belt phase per track, m.
    pub belt_phase: Vec<f64>,
    /// Flipper angle per flipper, rad.
    pub flipper_angle: Vec<f64>,
    /// Active contact points in the world.
    pub contacts: usize,
    /// Deepest geometric penetration among the world's contact points (0 if none), m.
    pub penetration: f64,
}

/// A vehicle on a terrain in a Rapier world, advanced one step at a time.
pub struct Simulation {
    /// The Rapier world; public for inspection (and for advanced users).
    pub world: PhysicsWorld,
    hooks: crate::baselines::SurfaceHooks,
    /// The flat-ground tile kept under the vehicle (`terrain::GROUND_TILE_HALF_M`).
    ground_tile: Option<RigidBodyHandle>,
    body: RigidBodyHandle,
    tracks: Vec<TrackRt>,
    flippers: Vec<FlipperRt>,
    commands: Vec<Command>,
    next_command: usize,
    dt: f64,
    time: f64,
    steps: u64,
    max_link_error_m: f64,
    max_link_error_rad: f64,
    track_names: Vec<String>,
    flipper_names: Vec<String>,
}

fn groups(g: Group) -> InteractionGroups {
    InteractionGroups::new(g, Group::ALL, InteractionTestMode::And)
}

fn vehicle_groups() -> InteractionGroups {
    InteractionGroups::new(
        VEHICLE_GROUP,
        Group::ALL.difference(VEHICLE_GROUP),
        InteractionTestMode::And,
    )
}

fn shape_collider(shape: &CollisionShape) -> Result<ColliderBuilder> {
    match shape {
        CollisionShape::Box { half, centre } => {
            Ok(
                ColliderBuilder::cuboid(half.x as f32, half.y as f32, half.z as f32)
                    .translation(f(*centre)),
            )
        }
        CollisionShape::Convex(pts) => {
            let p: Vec<Vector> = pts.iter().map(|p| f(*p)).collect();
            ColliderBuilder::convex_hull(&p).ok_or_else(|| {
                Error::Build(
                    "a convex shape's hull could not be computed (are its points coplanar?)".into(),
                )
            })
        }
    }
}

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

impl Simulation {
    /// Builds the world for a scenario: terrain, then the vehicle at its start pose.
    pub fn new(sc: &Scenario) -> Result<Self> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        let ip = &mut world.integration_parameters;
        ip.dt = sc.solver.dt as f32;
        ip.num_solver_iterations = sc.solver.iterations;
        ip.contact_clustering = sc.solver.contact_clustering;
        ip.normalized_prediction_distance = sc.solver.prediction_distance as f32;

        // Terrain.
        let ground_z = sc.terrain.ground.map(|g| g.0).unwrap_or(0.0);
        let ground_tile =
            sc.terrain
                .insert_into(&mut world, groups(WORLD_GROUP), Some(sc.start_xy));

        // Vehicle, first at z = 0, then lifted to rest on the ground.
        let v = &sc.vehicle;
        let start_rot =
            DQuat::from_rotation_z(sc.start_yaw) * DQuat::from_rotation_y(sc.start_pitch);
        let start = Pose::from_parts(
            Vector::new(sc.start_xy.0 as f32, sc.start_xy.1 as f32, 0.0),
            q(start_rot),
        );
        let body = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(start)
                .additional_mass_properties(MassProperties::new(
                    f(v.body.com),
                    v.body.mass as f32,
                    f(v.body.inertia),
                ))
                .can_sleep(false),
        );
        let c = shape_collider(&v.body.shape)?
            .density(0.0)
            .friction(v.body.friction as f32)
            .collision_groups(vehicle_groups());
        world
            .colliders
            .insert_with_parent(c, body, &mut world.bodies);

        // Flippers.
        let mut flippers = Vec::new();
        for fl in &v.flippers {
            let rot = DQuat::from_axis_angle(fl.axis, fl.initial_angle);
            let rel = Pose::from_parts(f(fl.pivot - rot * fl.pivot), q(rot));
            let h = world.bodies.insert(
                RigidBodyBuilder::dynamic()
                    .pose(start * rel)
                    .additional_mass_properties(MassProperties::new(
                        f(fl.com),
                        fl.mass as f32,
                        f(fl.inertia),
                    ))
                    .can_sleep(false),
            );
            if let Some(s) = &fl.shape {
                let c = shape_collider(s)?
                    .density(0.0)
                    .friction(v.body.friction as f32)
                    .collision_groups(vehicle_groups());
                world.colliders.insert_with_parent(c, h, &mut world.bodies);
            }
            let joint = RevoluteJointBuilder::new(f(fl.axis))
                .local_anchor1(f(fl.pivot))
                .local_anchor2(f(fl.pivot))
                .contacts_enabled(false)
                .motor_model(MotorModel::ForceBased)
                .motor_position(
                    fl.initial_angle as f32,
                    fl.stiffness as f32,
                    fl.damping as f32,
                )
                .motor_max_force(fl.max_torque as f32);
            let j = world.impulse_joints.insert(body, h, joint, true);
            flippers.push(FlipperRt {
                body: h,
                joint: j,
                axis: fl.axis,
                target: fl.initial_angle,
                stiffness: fl.stiffness as f32,
                damping: fl.damping as f32,
            });
        }

        // Tracks.
        let mut tracks = Vec::new();
        let mut hooks = crate::baselines::SurfaceHooks {
            slop: sc.solver.contact_slop as f32,
            ..Default::default()
        };
        let method = sc.method;
        let segments_method = matches!(
            method,
            TrackMethod::Okada2020 | TrackMethod::Okada2020NoGrousers
        );
        for (ti, t) in v.tracks.iter().enumerate() {
            let grouser_height = t.grousers.as_ref().map(|g| g.height).unwrap_or(0.0);
            let stripped;
            let t = if matches!(method, TrackMethod::Okada2020 | TrackMethod::Plates) {
                t
            } else {
                // Only the paper's method and the plate chain (cleats) carry grousers.
                stripped = TrackModel {
                    grousers: None,
                    ..t.clone()
                };
                &stripped
            };
            hooks.tracks.push((0.0, t.path.axis()));
            let parent = match t.parent {
                Parent::Body => body,
                Parent::Flipper(i) => flippers[i].body,
            };
            let parent_pose = *world.bodies[parent].position();
            let path = &t.path;
            let lateral = path.axis();
            let shapes: Vec<SharedShape> = match &t.grousers {
                None => Vec::new(),
                Some(g) => g
                    .shapes
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
                    })?,
            };
            let footprints = t
                .grousers
                .as_ref()
                .map(|g| g.layout.footprints(path))
                .unwrap_or_default();
            let mut links = Vec::new();
            for (si, seg) in path.segments().iter().enumerate() {
                if !t.included[si] || !segments_method {
                    continue;
                }
                let mass =
                    (t.belt_mass * seg.length() / path.length()).max(sc.solver.min_link_mass);
                let mprops = link_mass_properties(t, si, mass, lateral);
                let h = world.bodies.insert(
                    RigidBodyBuilder::dynamic()
                        .pose(parent_pose)
                        .additional_mass_properties(mprops)
                        .can_sleep(false),
                );
                let base = |b: ColliderBuilder| {
                    b.density(0.0)
                        .friction(t.friction as f32)
                        .friction_combine_rule(t.combine)
                        .collision_groups(vehicle_groups())
                };
                // Belt shape.
                let (kind, belt) = match *seg {
                    crate::geometry::Segment::Straight {
                        start,
                        direction,
                        length,
                    } => {
                        let normal = direction.cross(lateral);
                        let centre =
                            start + direction * (length / 2.0) - normal * (t.belt_thickness / 2.0);
                        let rot =
                            DQuat::from_mat3(&glam::DMat3::from_cols(direction, lateral, normal));
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
                    crate::geometry::Segment::Arc { axis, angle, .. } => {
                        let centre = seg.arc_centre().unwrap_or_default();
                        let radius = seg.radius().unwrap_or_default();
                        let rot = DQuat::from_rotation_arc(DVec3::Y, lateral);
                        (
                            LinkKind::Turn {
                                centre,
                                axis: axis * angle.signum(),
                                radius,
                            },
                            ColliderBuilder::cylinder((t.width / 2.0) as f32, radius as f32)
                                .position(Pose::from_parts(f(centre), q(rot))),
                        )
                    }
                };
                world
                    .colliders
                    .insert_with_parent(base(belt), h, &mut world.bodies);
                // Grousers whose footprint lies on this segment at rest.
                let mut grousers = Vec::new();
                if let Some(g) = &t.grousers {
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
                        let c = base(ColliderBuilder::new(shapes[shape_i].clone()).position(pose));
                        let ch = world.colliders.insert_with_parent(c, h, &mut world.bodies);
                        grousers.push((ch, k));
                    }
                }
                let joint: GenericJoint = match kind {
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
                };
                let j = world.impulse_joints.insert(parent, h, joint, true);
                links.push(LinkRt {
                    body: h,
                    joint: j,
                    kind,
                    local_com: mprops.local_com,
                    grousers,
                });
            }
            let extra = match method {
                TrackMethod::Okada2020 | TrackMethod::Okada2020NoGrousers => Extra::None,
                TrackMethod::Wheels(k) => Extra::Wheels(
                    crate::baselines::build_wheels(
                        &mut world,
                        t,
                        grouser_height,
                        k,
                        parent,
                        vehicle_groups(),
                        sc.solver.min_link_mass,
                        BELT_MOTOR_GAIN,
                    )
                    .map_err(Error::Build)?,
                ),
                TrackMethod::ConstraintToGround => {
                    crate::baselines::build_surface(
                        &mut world,
                        t,
                        ti,
                        parent,
                        vehicle_groups(),
                        SURFACE_TRACK_FRICTION,
                    )
                    .map_err(Error::Build)?;
                    Extra::Surface
                }
                TrackMethod::Plates => Extra::Plates(Box::new(
                    crate::plates::build_plates(
                        &mut world,
                        t,
                        parent,
                        vehicle_groups(),
                        sc.solver.min_link_mass,
                    )
                    .map_err(Error::Build)?,
                )),
            };
            tracks.push(TrackRt {
                extra,
                parent,
                links,
                pitch: t.grousers.as_ref().map(|g| g.layout.pitch(path)),
                shapes,
                position: 0.0,
                speed_cmd: 0.0,
                speed_measured: 0.0,
                wraps: 0,
            });
        }

        // Contact slop: every collider on the vehicle's (dynamic) bodies, whatever the track
        // method, gets the hook; the constraint-to-ground outlines have it already and apply
        // the slop in the same hook.
        if sc.solver.contact_slop > 0.0 {
            for (_, c) in world.colliders.iter_mut() {
                let on_vehicle = c
                    .parent()
                    .is_some_and(|b| world.bodies[b].body_type().is_dynamic());
                if on_vehicle && c.user_data == 0 {
                    c.set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
                    c.user_data = crate::baselines::SLOP_TAG;
                }
            }
        }

        let mut sim = Simulation {
            world,
            hooks,
            ground_tile,
            body,
            tracks,
            flippers,
            commands: sc.commands.clone(),
            next_command: 0,
            dt: sc.solver.dt,
            time: 0.0,
            steps: 0,
            max_link_error_m: 0.0,
            max_link_error_rad: 0.0,
            track_names: v.tracks.iter().map(|t| t.name.clone()).collect(),
            flipper_names: v.flippers.iter().map(|f| f.name.clone()).collect(),
        };
        // Lift the vehicle so that every point of it is just above the terrain below it
        // (exact for boxes, hulls and grousers; cylinders sampled every 360/64 deg).
        let dz = match sc.start_z {
            Some(z) => z,
            None => {
                sim.refresh_queries();
                let mut dz = f64::MIN;
                let colliders: Vec<ColliderHandle> = sim
                    .vehicle_bodies()
                    .flat_map(|h| sim.world.bodies[h].colliders().to_vec())
                    .collect();
                for c in colliders {
                    let col = &sim.world.colliders[c];
                    let pose = *col.position();
                    for p in shape_points(col.shape()) {
                        let w = pose.transform_point(p);
                        let below = sim
                            .terrain_below(w.x as f64, w.y as f64)
                            .unwrap_or(ground_z);
                        dz = dz.max(below + START_CLEARANCE_M - w.z as f64);
                    }
                }
                dz
            }
        };
        let handles: Vec<_> = sim.vehicle_bodies().collect();
        for h in handles {
            let b = &mut sim.world.bodies[h];
            let mut p = *b.position();
            p.translation.z += dz as f32;
            b.set_position(p, true);
        }
        sim.apply_commands();
        Ok(sim)
    }

    /// Updates collider poses and the scene-query structures without advancing time.
    fn refresh_queries(&mut self) {
        let dt = self.world.integration_parameters.dt;
        self.world.integration_parameters.dt = 0.0;
        self.world.step();
        self.world.integration_parameters.dt = dt;
    }

    fn vehicle_bodies(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        std::iter::once(self.body)
            .chain(self.flippers.iter().map(|f| f.body))
            .chain(self.tracks.iter().flat_map(|t| {
                let extra: Vec<RigidBodyHandle> = match &t.extra {
                    Extra::Wheels(w) => w.iter().map(|w| w.body).collect(),
                    Extra::Plates(p) => p.bodies.clone(),
                    Extra::None | Extra::Surface => Vec::new(),
                };
                t.links.iter().map(|l| l.body).chain(extra)
            }))
    }

    /// Applies every command whose time has come.
    fn apply_commands(&mut self) {
        while self.next_command < self.commands.len()
            && self.commands[self.next_command].t <= self.time + 1e-9
        {
            let cmd = self.commands[self.next_command].clone();
            for (i, v) in cmd.belt_speed.iter().enumerate() {
                if let Some(v) = v {
                    self.set_belt_speed(i, *v);
                }
            }
            for (i, a) in cmd.flipper_angle.iter().enumerate() {
                if let Some(a) = a {
                    self.set_flipper_angle(i, *a);
                }
            }
            self.next_command += 1;
        }
    }

    /// Sets the belt speed of track `i`, m/s (positive drives forwards).
    pub fn set_belt_speed(&mut self, i: usize, v: f64) {
        let t = &mut self.tracks[i];
        t.speed_cmd = v;
        self.hooks.tracks[i].0 = v;
        match &mut t.extra {
            Extra::Wheels(wheels) => {
                for w in wheels.iter() {
                    if let Some(j) = self.world.impulse_joints.get_mut(w.joint, true) {
                        j.data.set_motor_velocity(
                            JointAxis::AngX,
                            (v / w.radius) as f32,
                            BELT_MOTOR_GAIN,
                        );
                    }
                }
            }
            Extra::Plates(p) => p.set_speed(&mut self.world, v),
            Extra::None | Extra::Surface => {}
        }
        for l in &t.links {
            if let Some(j) = self.world.impulse_joints.get_mut(l.joint, true) {
                j.data.set_motor_velocity(
                    l.kind.motor_axis(),
                    l.kind.motor_target(v),
                    BELT_MOTOR_GAIN,
                );
            }
        }
    }

    /// Sets the target angle of flipper `i`, rad.
    pub fn set_flipper_angle(&mut self, i: usize, a: f64) {
        let fl = &mut self.flippers[i];
        fl.target = a;
        if let Some(j) = self.world.impulse_joints.get_mut(fl.joint, true) {
            j.data
                .set_motor_position(JointAxis::AngX, a as f32, fl.stiffness, fl.damping);
        }
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Track names in output order.
    pub fn track_names(&self) -> &[String] {
        &self.track_names
    }

    /// Flipper names in output order.
    pub fn flipper_names(&self) -> &[String] {
        &self.flipper_names
    }

    /// Largest distance, m, and angle, rad, seen between a link's pose after a physics step and
    /// its exact pose `parent * shift(phase)`, over all links and steps so far.
    pub fn max_link_error(&self) -> (f64, f64) {
        (self.max_link_error_m, self.max_link_error_rad)
    }

    /// Forgets the largest link error seen so far (e.g. after the landing transient).
    pub fn reset_max_link_error(&mut self) {
        self.max_link_error_m = 0.0;
        self.max_link_error_rad = 0.0;
    }

    /// Handle of the chassis body.
    pub fn body_handle(&self) -> RigidBodyHandle {
        self.body
    }

    /// Unwrapped belt position of track `i`, m.
    pub fn belt_position(&self, i: usize) -> f64 {
        self.tracks[i].position
    }

    /// For track `i`: each link's pose relative to its parent and the pose it must have
    /// (`shift(phase)`). After a step both are equal up to float rounding.
    pub fn link_relative_poses(&self, i: usize) -> Vec<(Pose, Pose)> {
        let t = &self.tracks[i];
        let (phi, _) = t.phase();
        let parent = *self.world.bodies[t.parent].position();
        t.links
            .iter()
            .map(|l| {
                let rel = parent.inv_mul(self.world.bodies[l.body].position());
                (rel, l.kind.shift(phi))
            })
            .collect()
    }

    /// Advances the simulation by one time step.
    pub fn step(&mut self) -> Result<()> {
        self.apply_commands();
        if let Some(tile) = self.ground_tile {
            let p = self.world.bodies[self.body].translation();
            crate::terrain::TerrainModel::recentre_ground_tile(
                &mut self.world,
                tile,
                p.x as f64,
                p.y as f64,
            );
        }
        self.world.step_with_events(&self.hooks, &());
        let dt = self.dt;
        self.steps += 1;
        self.time = self.steps as f64 * dt;
        for ti in 0..self.tracks.len() {
            self.update_track(ti, dt);
        }
        self.check_stability()
    }

    /// Integrates the belt position, measures, rolls back and snaps the links of track `ti`.
    fn update_track(&mut self, ti: usize, dt: f64) {
        let t = &mut self.tracks[ti];
        t.position += t.speed_cmd * dt;
        match &mut t.extra {
            Extra::None => {}
            Extra::Surface => t.speed_measured = t.speed_cmd,
            Extra::Plates(p) => {
                p.after_step(&mut self.world, dt);
                t.speed_measured = p.measured_speed(&self.world);
            }
            Extra::Wheels(wheels) => {
                let parent = &self.world.bodies[t.parent];
                let (rot, w_parent) = (parent.rotation(), parent.angvel());
                let sum: f64 = wheels
                    .iter()
                    .map(|w| {
                        let axis =
                            rot * Vector::new(w.axis.x as f32, w.axis.y as f32, w.axis.z as f32);
                        (self.world.bodies[w.body].angvel() - w_parent).dot(axis) as f64 * w.radius
                    })
                    .sum();
                t.speed_measured = sum / wheels.len().max(1) as f64;
            }
        }
        let (phi, wraps) = t.phase();
        // Where the links should be before any wrap: the old wrap count's phase.
        let phi_unwrapped = phi + (wraps - t.wraps) as f64 * t.pitch.unwrap_or(0.0);
        let bodies = &mut self.world.bodies;
        let parent = &bodies[t.parent];
        let parent_pose = *parent.position();
        let parent_linvel = parent.linvel();
        let parent_angvel = parent.angvel();
        let parent_com = parent.center_of_mass();
        let mut measured = 0.0;
        for l in &t.links {
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
            self.max_link_error_m = self.max_link_error_m.max(com_err);
            self.max_link_error_rad = self.max_link_error_rad.max(rot_err);
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
            // Snap to the exact pose, keeping the world velocity the solver gave. (Overwriting
            // velocities with the joint kinematics would discard the solver's impulses and
            // inject momentum: measured 5-13 mm/s^2 of drift on a frictionless ground.)
            bodies[l.body].set_position(expected, false);
        }
        if !t.links.is_empty() {
            t.speed_measured = measured / t.links.len() as f64;
        }
        // Several grouser shapes in turn: re-assign them so the pattern moves with the belt.
        if wraps != t.wraps && t.shapes.len() > 1 {
            let m = t.shapes.len() as i64;
            for l in &t.links {
                for &(ch, k) in &l.grousers {
                    let idx = (k as i64 - wraps).rem_euclid(m) as usize;
                    if let Some(c) = self.world.colliders.get_mut(ch) {
                        c.set_shape(t.shapes[idx].clone());
                    }
                }
            }
        }
        t.wraps = wraps;
    }

    fn check_stability(&self) -> Result<()> {
        // Names are only formatted when something is wrong: this runs every step.
        let handles = std::iter::once(self.body).chain(self.flippers.iter().map(|f| f.body));
        for (i, h) in handles.enumerate() {
            let b = &self.world.bodies[h];
            let p = b.position();
            let v = b.linvel();
            let bad = if !p.is_finite() || !v.is_finite() || !b.angvel().is_finite() {
                Some("has a non-finite position or velocity (NaN)".to_string())
            } else if v.length() > MAX_SPEED_MPS {
                Some(format!(
                    "moves at {:.1} m/s (limit {MAX_SPEED_MPS} m/s): it was flung off",
                    v.length()
                ))
            } else if p.translation.z < -100.0 {
                Some("fell below z = -100 m: it left the world".to_string())
            } else {
                None
            };
            if let Some(what) = bad {
                return Err(Error::Unstable {
                    time_s: self.time,
                    body: match i {
                        0 => "body".to_string(),
                        _ => format!("flipper {}", self.flipper_names[i - 1]),
                    },
                    what,
                });
            }
        }
        Ok(())
    }

    /// Height of the terrain surface below (x, y), m, by a downward ray that sees only the
    /// terrain; `None` if there is no terrain there (off the edge).
    pub fn terrain_below(&self, x: f64, y: f64) -> Option<f64> {
        let top = 1000.0f32;
        let ray = Ray::new(Vector::new(x as f32, y as f32, top), Vector::NEG_Z);
        let filter = QueryFilter::default().groups(InteractionGroups::new(
            Group::ALL,
            WORLD_GROUP,
            InteractionTestMode::And,
        ));
        self.world
            .cast_ray(&ray, 2.0 * top, true, filter)
            .map(|(_, toi)| (top - toi) as f64)
    }

    /// Pose of the chassis.
    pub fn body_pose(&self) -> PoseRpy {
        PoseRpy::from_pose(self.world.bodies[self.body].position())
    }

    /// Number of active solver contact points in the world.
    pub fn contact_count(&self) -> usize {
        self.world
            .narrow_phase
            .contact_pairs()
            .flat_map(|p| p.manifolds())
            .map(|m| m.data.solver_contacts.len())
            .sum()
    }

    /// Number of active solver contact points in the world and the deepest penetration (m, 0 if
    /// none) of any touching collider pair, measured from the colliders' current poses (the
    /// narrow phase's stored distances can be frames old for recycled pairs, and the contact
    /// slop hook rewrites the solver's).
    pub fn contact_stats(&self) -> (usize, f64) {
        let mut n = 0;
        let mut deepest = 0.0f32;
        let cs = &self.world.colliders;
        for p in self.world.narrow_phase.contact_pairs() {
            let active: usize = p
                .manifolds()
                .iter()
                .map(|m| m.data.solver_contacts.len())
                .sum();
            if active == 0 {
                continue;
            }
            n += active;
            let (Some(c1), Some(c2)) = (cs.get(p.collider1), cs.get(p.collider2)) else {
                continue;
            };
            if let Ok(Some(c)) = rapier3d::parry::query::contact(
                c1.position(),
                c1.shape(),
                c2.position(),
                c2.shape(),
                0.0,
            ) {
                deepest = deepest.max(-c.dist);
            }
        }
        (n, deepest as f64)
    }

    /// Angle of flipper `i` relative to the body, rad.
    pub fn flipper_angle(&self, i: usize) -> f64 {
        let fl = &self.flippers[i];
        let pb = self.world.bodies[self.body].position();
        let pf = self.world.bodies[fl.body].position();
        let r = (pb.rotation.inverse() * pf.rotation).normalize();
        let v = DVec3::new(r.x as f64, r.y as f64, r.z as f64);
        2.0 * v.dot(fl.axis).atan2(r.w as f64)
    }

    /// Current state as a sample.
    pub fn sample(&self) -> Sample {
        let b = &self.world.bodies[self.body];
        let lv = b.linvel();
        let av = b.angvel();
        // Before the first step the narrow phase still holds the placement's trial contacts.
        let (contacts, penetration) = if self.steps() == 0 {
            (0, 0.0)
        } else {
            self.contact_stats()
        };
        Sample {
            t: self.time,
            pose: self.body_pose(),
            linvel: [lv.x as f64, lv.y as f64, lv.z as f64],
            angvel: [av.x as f64, av.y as f64, av.z as f64],
            belt_speed: self.tracks.iter().map(|t| t.speed_measured).collect(),
            belt_phase: self.tracks.iter().map(|t| t.phase().0).collect(),
            flipper_angle: (0..self.flippers.len())
                .map(|i| self.flipper_angle(i))
                .collect(),
            contacts,
            penetration,
        }
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
        let mut sim = Simulation::new(&sc).unwrap();
        let tall_slots = |sim: &Simulation| -> Vec<usize> {
            let mut v: Vec<usize> = sim.tracks[0]
                .links
                .iter()
                .flat_map(|l| l.grousers.iter())
                .filter(|(h, _)| {
                    sim.world.colliders[*h]
                        .shape()
                        .as_cuboid()
                        .unwrap()
                        .half_extents
                        .z
                        > 0.006
                })
                .map(|(_, k)| *k)
                .collect();
            v.sort();
            v
        };
        assert!(tall_slots(&sim).iter().all(|k| k % 2 == 1));
        let pitch = sim.tracks[0].pitch.unwrap();
        // Drive until the belt has wrapped once (moved by about one pitch).
        while sim.tracks[0].wraps == 0 {
            sim.step().unwrap();
        }
        assert!((sim.belt_position(0) - pitch / 2.0).abs() < 0.001);
        assert!(
            tall_slots(&sim).iter().all(|k| k % 2 == 0),
            "{:?}",
            tall_slots(&sim)
        );
        assert_eq!(tall_slots(&sim).len(), 20);
    }
}
