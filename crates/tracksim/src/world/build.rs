//! The build stages of [`Simulation::new`]: world settings, terrain, chassis, flippers, tracks
//! (by their method), contact compliance, contact slop, then placement on the terrain.

use super::origin::shift_for;
use super::robot::{Robot, RobotCollision};
use super::{Flipper, Odometry, START_CLEARANCE_M, Simulation};
use crate::check::{f, q};
use crate::error::{Error, Result};
use crate::model::{CollisionShape, Method, Parent, Scenario, SolverSettings, VehicleModel};
use crate::tracks::{
    BuildContext, SLOP_TAG, Track, flat_ground_groups, vehicle_groups, world_groups,
};
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;
use std::sync::Arc;

/// Builds a simulation of `sc`, stage by stage: the world, then every robot (one, or those of
/// `[[vehicles]]` in file order), then what needs them all.
pub(crate) fn build(sc: Arc<Scenario>) -> Result<Simulation> {
    let method = sc.method;
    let views: Vec<Arc<Scenario>> = match &sc.team {
        Some(t) => (0..t.robots.len())
            .map(|k| Arc::new(sc.robot_view(k)))
            .collect(),
        None => vec![sc.clone()],
    };
    for v in &views {
        check_method(v)?;
    }
    if views.len() > 1 && !sc.terrain.soils.is_empty() {
        return Err(Error::Build(
            "several robots on deformable soil are not supported yet (the soil's memory and \
             thrust are kept for one robot): give the scenario one robot, or rigid terrain"
                .into(),
        ));
    }
    let mut world = new_world(&sc.solver);
    crate::tracks::configure_world(method, &mut world.integration_parameters);
    if let Some(z) = sc.solver.terrain_contact_damping_ratio {
        world
            .integration_parameters
            .static_contact_softness
            .damping_ratio = z as f32;
    }
    let centre = start_centre(&views);
    let origin = start_origin(centre, !sc.terrain.soils.is_empty());
    insert_order_salt(&mut world, sc.solver.order_salt);
    let inserted = sc.terrain.insert_into(
        &mut world,
        world_groups(),
        Some((centre.0 - origin.x, centre.1 - origin.y)),
        origin,
    );
    let ground_tile = inserted.ground_tile;
    if let Some(tile) = ground_tile {
        for &c in world.bodies[tile].colliders().to_vec().iter() {
            world.colliders[c].set_collision_groups(flat_ground_groups());
        }
    }
    let order = build_order(&views);
    let mut springs = Vec::new();
    let mut built: Vec<Option<Robot>> = views.iter().map(|_| None).collect();
    let mut first_track = 0;
    for &k in &order {
        let mut r = build_robot(&mut world, &views[k], first_track, origin, &mut springs)?;
        r.name = sc.robot_names().swap_remove(k);
        first_track += r.tracks.len();
        built[k] = Some(r);
    }
    let robots: Vec<Robot> = built.into_iter().flatten().collect();
    if sc.solver.contact_slop > 0.0 {
        tag_slop(&mut world);
    }
    for &k in &order {
        RobotCollision::apply(&mut world, k, &robots[k].bodies());
    }
    let conveyors = super::conveyor::build_conveyors(&mut world, &sc, origin)?;
    let appearance = build_appearance(&world, &inserted.colors, &robots, &views, &conveyors, &sc);
    let mut sim = Simulation {
        world,
        origin,
        method,
        slop: sc.solver.contact_slop as f32,
        held_friction_in_bias_pass: sc.solver.held_friction_in_bias_pass,
        held_at_rest: false,
        friction_patch: None,
        patch_log: Vec::new(),
        ground_hooked: false,
        cull: super::speculative_cull::CullState::new(sc.solver.cull_speculative_contacts),
        fresh_pairs: Vec::new(),
        rest_positions: Vec::new(),
        springs,
        ground_tile,
        robots,
        focus: 0,
        order: order.clone(),
        dt: sc.solver.dt,
        time: 0.0,
        steps: 0,
        seed: sc.seed,
        scenario: sc.clone(),
        conveyors,
        soil: None,
        appearance,
    };
    start_load_windows(&mut sim, &sc);
    sim.soil = super::soil::build_soil(
        &sim.world,
        &sc.terrain.soils,
        &sc.vehicle.tracks,
        &sim.robots[0].tracks,
        &sim.vehicle_bodies(),
        sc.solver.dt,
    );
    for &k in &order {
        sim.focus = k;
        sim.conserve_mass(&views[k])?;
    }
    for &k in &order {
        sim.focus = k;
        place(&mut sim);
    }
    for k in 0..sim.robots.len() {
        sim.focus = k;
        sim.robots[k].odometry = start_odometry(&sim);
        sim.robots[k].drawbar = sim.start_drawbar();
    }
    sim.focus = 0;
    if sim.robots.len() > 1 {
        check_overlaps(&mut sim)?;
    }
    Ok(sim)
}

/// Every robot's window of per-track loads, averaged over the output interval.
fn start_load_windows(sim: &mut Simulation, sc: &Scenario) {
    for k in 0..sim.robots.len() {
        sim.focus = k;
        sim.robots[k].load_window = super::track_loads::LoadWindow::new(
            sim.track_owners(),
            sc.output_interval,
            sc.solver.dt,
        );
    }
    sim.focus = 0;
}

/// The order the robots are built in: by start pose (x, y, yaw, pitch), whatever
/// their order in the file (issue 38: the order of a file's entries never changes the physics;
/// Rapier's handles and so its solver's order follow the build order). Two robots cannot start
/// at one pose (they would overlap), so the order is the same for every permutation.
fn build_order(views: &[Arc<Scenario>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..views.len()).collect();
    let key = |v: &Scenario| [v.start_xy.0, v.start_xy.1, v.start_yaw, v.start_pitch];
    order.sort_by(|&a, &b| {
        let (ka, kb) = (key(&views[a]), key(&views[b]));
        ka.iter()
            .zip(&kb)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    order
}

/// Where the floating origin starts (world x, y; z 0), m, for robots whose start positions
/// centre on `centre`: that centre itself, so the Rapier world holds the same f32 numbers
/// wherever a scenario is placed (translating a file's robots and terrain together, or starting
/// on a plane at another x, gives the same trajectory shifted; issue 38.3). With deformable
/// soil the origin stays on whole metres: the soil's cells are indexed from it
/// (`world/rut_grid.rs`), as before: rounded when the centre is more than
/// [`super::origin::ORIGIN_SHIFT_M`] out, else 0.
fn start_origin(centre: (f64, f64), soil: bool) -> DVec3 {
    if soil {
        DVec3::new(shift_for(centre.0), shift_for(centre.1), 0.0)
    } else {
        DVec3::new(centre.0, centre.1, 0.0)
    }
}

/// The centre of the robots' start positions (x, y), m: where the floating origin starts.
fn start_centre(views: &[Arc<Scenario>]) -> (f64, f64) {
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for v in views {
        for (i, c) in [v.start_xy.0, v.start_xy.1].into_iter().enumerate() {
            lo[i] = lo[i].min(c);
            hi[i] = hi[i].max(c);
        }
    }
    (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]))
}

/// A robot of the world (named by the caller): chassis, flippers, tracks (their tags numbered from `first_track`)
/// and their contact springs (appended to the world's `springs`), at its start pose.
fn build_robot(
    world: &mut PhysicsWorld,
    view: &Arc<Scenario>,
    first_track: usize,
    origin: DVec3,
    springs: &mut Vec<super::compliance::SolverSpring>,
) -> Result<Robot> {
    let start = start_pose(view, origin);
    let v = &view.vehicle;
    let body = insert_chassis(world, v, start)?;
    let flippers = insert_flippers(world, v, body, start)?;
    let tracks = build_tracks(world, view, view.method, body, &flippers, first_track)?;
    super::compliance::tag_compliance(world, &v.tracks, &tracks, view.solver.dt, springs);
    Ok(Robot {
        name: crate::model::DEFAULT_ROBOT_NAME.to_string(),
        body,
        tracks,
        first_track,
        flippers,
        track_names: v.tracks.iter().map(|t| t.name.clone()).collect(),
        flipper_names: v.flippers.iter().map(|f| f.name.clone()).collect(),
        has_motors: v.tracks.iter().any(|t| t.motor.is_some()),
        odometry: Odometry::new(&[], 0.0, 0.0, 0.0, 0.0),
        drawbar: None,
        load_window: Default::default(),
        momentum_before: Vector::ZERO,
        faults: super::fault_state::FaultState::new(
            v.tracks.len(),
            v.flippers.iter().map(|f| f.initial_angle).collect(),
        ),
        view: view.clone(),
    })
}

/// `simulation.order_salt`: `n` inert colliders on a fixed body of their own, inserted before
/// everything else. They collide with nothing (empty collision groups, and 1 km below the
/// world origin), so nothing physical changes; Rapier's handles and broad-phase tree do, and
/// with them the order its solver visits the contacts: the ensemble's perturbation of the
/// solver order (docs/ENSEMBLE.md).
fn insert_order_salt(world: &mut PhysicsWorld, n: usize) {
    if n == 0 {
        return;
    }
    let body = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -1000.0)));
    for i in 0..n {
        let c = ColliderBuilder::ball(0.01)
            .translation(Vector::new(0.1 * i as f32, 0.0, 0.0))
            .collision_groups(InteractionGroups::none());
        world
            .colliders
            .insert_with_parent(c, body, &mut world.bodies);
    }
}

/// Refuses what the scenario's method cannot model ([`crate::model::method_problems`]: checked
/// when the file is compiled, again here for a scenario whose method was changed after).
fn check_method(sc: &Scenario) -> Result<()> {
    let issues = crate::model::method_problems(sc.method, &sc.vehicle);
    if issues.is_empty() {
        Ok(())
    } else {
        Err(Error::Invalid {
            path: sc.source.clone().unwrap_or_default(),
            issues,
        })
    }
}

/// Odometry at the placed start pose over every track (REP 105: the odom frame coincides
/// with the world at the start).
fn start_odometry(sim: &Simulation) -> Odometry {
    let p = sim.body_pose();
    Odometry::of_vehicle(&sim.rb().view.vehicle, p.x, p.y, p.yaw)
}

/// An empty world with the scenario's solver settings, z up.
fn new_world(solver: &SolverSettings) -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    let ip = &mut world.integration_parameters;
    ip.dt = solver.dt as f32;
    ip.num_solver_iterations = solver.iterations;
    ip.num_internal_stabilization_iterations = solver.stabilization_iterations;
    ip.warmstart_coefficient = solver.warmstart as f32;
    ip.contact_clustering = solver.contact_clustering;
    ip.contact_recycling = solver.contact_recycling;
    ip.normalized_prediction_distance = solver.prediction_distance as f32;
    world
}

/// The start pose at z = 0 (placement lifts it onto the terrain), relative to `origin`.
fn start_pose(sc: &Scenario, origin: DVec3) -> Pose {
    let start_rot = DQuat::from_rotation_z(sc.start_yaw) * DQuat::from_rotation_y(sc.start_pitch);
    Pose::from_parts(
        Vector::new(
            (sc.start_xy.0 - origin.x) as f32,
            (sc.start_xy.1 - origin.y) as f32,
            0.0,
        ),
        q(start_rot),
    )
}

/// The colliders of a vehicle collision shape (body frame): one, or one per part of a
/// compound.
fn shape_colliders(shape: &CollisionShape) -> Result<Vec<ColliderBuilder>> {
    Ok(match shape {
        CollisionShape::Box { half, centre } => {
            vec![
                ColliderBuilder::cuboid(half.x as f32, half.y as f32, half.z as f32)
                    .translation(f(*centre)),
            ]
        }
        CollisionShape::Convex(pts) => {
            let p: Vec<Vector> = pts.iter().map(|p| f(*p)).collect();
            vec![ColliderBuilder::convex_hull(&p).ok_or_else(|| {
                Error::Build(
                    "a convex shape's hull could not be computed (are its points coplanar?)".into(),
                )
            })?]
        }
        CollisionShape::Sphere { radius, centre } => {
            vec![ColliderBuilder::ball(*radius as f32).translation(f(*centre))]
        }
        // Rapier's cylinder runs along y; URDF's along z: turn y onto z.
        CollisionShape::Cylinder {
            radius,
            half_length,
            centre,
            rotation,
        } => vec![
            ColliderBuilder::cylinder(*half_length as f32, *radius as f32).position(
                Pose::from_parts(
                    f(*centre),
                    q(*rotation * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)),
                ),
            ),
        ],
        CollisionShape::Compound(parts) => {
            let mut out = Vec::new();
            for p in parts {
                out.extend(shape_colliders(p)?);
            }
            out
        }
    })
}

/// Mass properties of a part: principal moments along the body axes, or (with products of
/// inertia, from a URDF) the full tensor, diagonalised by Rapier.
fn mass_properties(com: DVec3, mass: f64, inertia: DVec3, products: DVec3) -> MassProperties {
    if products == DVec3::ZERO {
        return MassProperties::new(f(com), mass as f32, f(inertia));
    }
    let m = glam::Mat3::from_cols(
        glam::Vec3::new(inertia.x as f32, products.x as f32, products.y as f32),
        glam::Vec3::new(products.x as f32, inertia.y as f32, products.z as f32),
        glam::Vec3::new(products.y as f32, products.z as f32, inertia.z as f32),
    );
    MassProperties::with_inertia_matrix(f(com), mass as f32, m)
}

/// The chassis body and its collider.
fn insert_chassis(
    world: &mut PhysicsWorld,
    v: &VehicleModel,
    start: Pose,
) -> Result<RigidBodyHandle> {
    let body = world.bodies.insert(
        RigidBodyBuilder::dynamic()
            .pose(start)
            .additional_mass_properties(mass_properties(
                v.body.com,
                v.body.mass,
                v.body.inertia,
                v.body.inertia_products,
            ))
            .can_sleep(false),
    );
    for c in shape_colliders(&v.body.shape)? {
        let c = c
            .density(0.0)
            .friction(v.body.friction as f32)
            .collision_groups(vehicle_groups());
        world
            .colliders
            .insert_with_parent(c, body, &mut world.bodies);
    }
    Ok(body)
}

/// The flipper arms on position-controlled revolute joints with a torque limit.
fn insert_flippers(
    world: &mut PhysicsWorld,
    v: &VehicleModel,
    body: RigidBodyHandle,
    start: Pose,
) -> Result<Vec<Flipper>> {
    let mut flippers = Vec::new();
    for fl in &v.flippers {
        let rot = DQuat::from_axis_angle(fl.axis, fl.initial_angle);
        let rel = Pose::from_parts(f(fl.pivot - rot * fl.pivot), q(rot));
        let h = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(start * rel)
                .additional_mass_properties(mass_properties(
                    fl.com,
                    fl.mass,
                    fl.inertia,
                    fl.inertia_products,
                ))
                .can_sleep(false),
        );
        if let Some(s) = &fl.shape {
            for c in shape_colliders(s)? {
                let c = c
                    .density(0.0)
                    .friction(v.body.friction as f32)
                    .collision_groups(vehicle_groups());
                world.colliders.insert_with_parent(c, h, &mut world.bodies);
            }
        }
        let mut joint = RevoluteJointBuilder::new(f(fl.axis))
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
        if let Some([lo, hi]) = fl.limits {
            joint = joint.limits([lo as f32, hi as f32]);
        }
        let j = world.impulse_joints.insert(body, h, joint, true);
        flippers.push(Flipper {
            body: h,
            joint: j,
            axis: fl.axis,
            target: fl.initial_angle,
            stiffness: fl.stiffness as f32,
            damping: fl.damping as f32,
            limits: fl.limits,
        });
    }
    Ok(flippers)
}

/// Every track of the vehicle, built by `method` on its parent.
fn build_tracks(
    world: &mut PhysicsWorld,
    sc: &Scenario,
    method: Method,
    body: RigidBodyHandle,
    flippers: &[Flipper],
    first_track: usize,
) -> Result<Vec<Box<dyn Track>>> {
    let mut tracks = Vec::new();
    for (ti, t) in sc.vehicle.tracks.iter().enumerate() {
        let parent = match t.parent {
            Parent::Body => body,
            Parent::Flipper(i) => flippers[i].body,
        };
        let mut ctx = BuildContext {
            world: &mut *world,
            parent,
            index: first_track + ti,
            groups: vehicle_groups(),
            min_link_mass: sc.solver.min_link_mass,
        };
        tracks.push(crate::tracks::build_track(method, &mut ctx, t)?);
    }
    Ok(tracks)
}

/// Contact slop: every collider on the vehicle's (dynamic) bodies, whatever the track method,
/// gets the contact hook; colliders a track tagged for itself get it in the same hook.
fn tag_slop(world: &mut PhysicsWorld) {
    for (_, c) in world.colliders.iter_mut() {
        let on_vehicle = c
            .parent()
            .is_some_and(|b| world.bodies[b].body_type().is_dynamic());
        if on_vehicle && c.user_data == 0 {
            c.set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
            c.user_data = SLOP_TAG;
        }
    }
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
    } else if let Some(c) = shape.as_compound() {
        // The grouser groups of `okada2020_clustered`: their parts, each in its pose.
        c.shapes()
            .iter()
            .flat_map(|(pose, part)| {
                shape_points(&**part)
                    .into_iter()
                    .map(move |p| pose.transform_point(p))
            })
            .collect()
    } else {
        let a = shape.compute_local_aabb();
        vec![a.mins, a.maxs, Vector::new(a.mins.x, a.maxs.y, a.mins.z)]
    }
}

/// Updates collider poses and the scene-query structures without advancing time.
pub(crate) fn refresh_queries(world: &mut PhysicsWorld) {
    let dt = world.integration_parameters.dt;
    world.integration_parameters.dt = 0.0;
    world.step();
    world.integration_parameters.dt = dt;
}

/// Lifts the vehicle so that every point of it is just above the terrain below it (exact for
/// boxes, hulls and grousers; cylinders sampled every 360/64 deg), or to the file's `z_m`.
fn place(sim: &mut Simulation) {
    let ground_z = sim.scenario.terrain.ground.map(|g| g.0).unwrap_or(0.0);
    let dz = match sim.rb().view.start_z {
        Some(z) => z,
        None => {
            refresh_queries(&mut sim.world);
            let mut dz = f64::MIN;
            let colliders: Vec<ColliderHandle> = sim
                .vehicle_bodies()
                .into_iter()
                .flat_map(|h| sim.world.bodies[h].colliders().to_vec())
                .collect();
            for c in colliders {
                let col = &sim.world.colliders[c];
                let pose = *col.position();
                for p in shape_points(col.shape()) {
                    let w = pose.transform_point(p);
                    let below = sim
                        .terrain_below_local(w.x as f64, w.y as f64)
                        .unwrap_or(ground_z);
                    dz = dz.max(below + START_CLEARANCE_M - w.z as f64);
                }
            }
            dz
        }
    };
    for h in sim.vehicle_bodies() {
        let b = &mut sim.world.bodies[h];
        let mut p = *b.position();
        p.translation.z += dz as f32;
        b.set_position(p, true);
    }
}

/// Refuses robots placed overlapping each other: any collider of one intersecting any of
/// another's at the placed start poses, every such pair named at once.
fn check_overlaps(sim: &mut Simulation) -> crate::error::Result<()> {
    refresh_queries(&mut sim.world);
    let colliders: Vec<Vec<ColliderHandle>> = sim
        .robots
        .iter()
        .map(|r| {
            r.bodies()
                .iter()
                .flat_map(|&b| sim.world.bodies[b].colliders().to_vec())
                .collect()
        })
        .collect();
    let cs = &sim.world.colliders;
    let touch = |a: ColliderHandle, b: ColliderHandle| {
        let (a, b) = (&cs[a], &cs[b]);
        a.compute_aabb().intersects(&b.compute_aabb())
            && rapier3d::parry::query::intersection_test(
                a.position(),
                a.shape(),
                b.position(),
                b.shape(),
            )
            .is_ok_and(|i| i.intersecting)
    };
    let mut issues = Vec::new();
    for k in 0..colliders.len() {
        for j in 0..k {
            let hit = colliders[k]
                .iter()
                .any(|&a| colliders[j].iter().any(|&b| touch(a, b)));
            if hit {
                issues.push(crate::error::SpecIssue::new(
                    format!("vehicles[{k}].vehicle.x_m"),
                    format!(
                        "`{}` overlaps `{}` (vehicles[{j}]) where they start: move one of them \
                         (x_m, y_m, yaw_deg){}",
                        sim.robots[k].name,
                        sim.robots[j].name,
                        drawn_from(&sim.scenario)
                    ),
                ));
            }
        }
    }
    if issues.is_empty() {
        Ok(())
    } else {
        Err(crate::error::Error::Invalid {
            path: sim.scenario.source.clone().unwrap_or_default(),
            issues,
        })
    }
}

/// For a start drawn by `[randomize]`: the values and the seed that placed the robots so, and
/// the fix (empty for a fixed file).
fn drawn_from(sc: &Scenario) -> String {
    if sc.randomized.is_empty() {
        return String::new();
    }
    format!(
        ", with the [randomize] values of seed {}: {}; narrow the ranges so that no draw \
         places them overlapping",
        sc.seed,
        crate::model::sampled_text(&sc.randomized)
    )
}

/// The colour of every collider: the terrain's, each robot's parts by its own vehicle's
/// colours, the conveyors' and the loose boxes'.
fn build_appearance(
    world: &PhysicsWorld,
    terrain: &[(ColliderHandle, crate::render::Rgb)],
    robots: &[Robot],
    views: &[Arc<Scenario>],
    conveyors: &super::conveyor::Conveyors,
    sc: &Scenario,
) -> super::Appearance {
    let parts: Vec<_> = robots
        .iter()
        .zip(views)
        .map(|(r, v)| {
            (
                r.body,
                r.flippers.iter().map(|f| f.body).collect(),
                r.tracks.iter().flat_map(|t| t.bodies()).collect(),
                v.vehicle.colors,
            )
        })
        .collect();
    let belts: Vec<_> = conveyors.belts.iter().flat_map(|t| t.bodies()).collect();
    let loose: Vec<_> = conveyors
        .loose
        .iter()
        .zip(&sc.loose_boxes)
        .map(|(&b, m)| (b, m.solid.color))
        .collect();
    super::appearance::appearance(world, terrain, &parts, &belts, &loose)
}
