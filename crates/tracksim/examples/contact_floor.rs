//! The contact floor of the Table II case: what Rapier alone charges per step for the grouser
//! contacts of a PackBot, without any track machinery (no segment links, no joints, no
//! placement). `b` boxes (15 kg in all, not joined; default 6, as the bench case's lower
//! straight and the two arcs of each track) carry `n` separate 5 x 75 x 8 mm grouser colliders
//! 38 mm apart, dealt out in turn, and slide at 0.3 m/s over a frictionless ground plane, dt
//! 1 ms, 4 solver iterations (the defaults `tracksim bench` uses).
//!
//! `cargo run --release -p tracksim --example contact_floor [-- N [B [ITERATIONS [SHAPE]]]]`
//! (default N = 36: about the grousers within the 2 cm prediction distance of the ground in the
//! bench case, whose 150 contact points include ~20 of the belts'). SHAPE `box` (default) is the
//! grouser cuboid (4 contact points per grouser); `capsule` the tip capsule of
//! `okada2020_line_tips` (radius 2.5 mm across the belt at the tip: 2 points); `roundbox` a
//! round cuboid of zero length along the belt with a 2.5 mm border (the grouser's envelope with
//! a half-cylinder tip: still 4 points, its support feature is a degenerate face); `triangle`
//! a rounded triangle across the belt, tip edge outwards (3 points).
use rapier3d::prelude::*;
use std::time::Instant;

fn main() {
    let arg = |i: usize, name: &str, default: usize| -> usize {
        match std::env::args().nth(i) {
            None => default,
            Some(a) => a.parse().unwrap_or_else(|_| {
                eprintln!(
                    "contact_floor: {name} must be a whole number, got {a:?}\n\
                     usage: contact_floor [GROUSERS [BODIES [ITERATIONS]]] (defaults 36 6 4)"
                );
                std::process::exit(2)
            }),
        }
    };
    let n = arg(1, "GROUSERS", 36);
    let nb = arg(2, "BODIES", 6).max(1);
    let iterations = arg(3, "ITERATIONS", 4).max(1);
    let shape = match std::env::args().nth(4).as_deref() {
        None | Some("box") => SharedShape::cuboid(0.0025, 0.0375, 0.004),
        Some("roundbox") => SharedShape::round_cuboid(0.0, 0.035, 0.0015, 0.0025),
        Some("capsule") => SharedShape::capsule(
            Vector::new(0.0, -0.035, -0.0015),
            Vector::new(0.0, 0.035, -0.0015),
            0.0025,
        ),
        // a cylinder across the belt (parry's cylinder axis is local y) of the grouser's
        // thickness, at the tip
        Some("cylinder") => SharedShape::cylinder(0.0375, 0.0025),
        Some("segment") => SharedShape::segment(
            Vector::new(0.0, -0.0375, -0.004),
            Vector::new(0.0, 0.0375, -0.004),
        ),
        Some("triangle") => SharedShape::round_triangle(
            Vector::new(0.0, -0.035, -0.0015),
            Vector::new(0.0, 0.035, -0.0015),
            Vector::new(0.0, 0.0, 0.0015),
            0.0025,
        ),
        Some(other) => {
            eprintln!(
                "contact_floor: SHAPE must be `box`, `capsule`, `cylinder`, `segment`, `roundbox` or `triangle`, got {other:?}"
            );
            std::process::exit(2)
        }
    };
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters.dt = 0.001;
    world.integration_parameters.num_solver_iterations = iterations;
    let ground = match std::env::args().nth(5).as_deref() {
        None | Some("plane") => ColliderBuilder::new(SharedShape::halfspace(Vector::Z)),
        // the simulations' 20 m flat-ground tile (40 m x 40 m x 1 m box, top at z = 0)
        Some("tile") => {
            ColliderBuilder::cuboid(20.0, 20.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5))
        }
        Some(other) => {
            eprintln!("contact_floor: GROUND must be `plane` or `tile`, got {other:?}");
            std::process::exit(2)
        }
    };
    world.colliders.insert(ground.friction(0.0));
    let mut bodies = Vec::new();
    for i in 0..nb {
        let y = -0.5 + i as f32 * 0.2;
        let body = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, y, 0.004))
                .linvel(Vector::new(0.3, 0.0, 0.0))
                .can_sleep(false),
        );
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.25, 0.03, 0.03)
                .translation(Vector::new(0.0, 0.0, 0.05))
                .mass(15.0 / nb as f32),
            body,
            &mut world.bodies,
        );
        bodies.push(body);
    }
    for k in 0..n {
        let (row, i) = (k % nb, k / nb);
        let body = bodies[row];
        let x = -0.3 + 0.0384 * i as f32;
        let y = 0.0;
        world.colliders.insert_with_parent(
            ColliderBuilder::new(shape.clone())
                .translation(Vector::new(x, y, 0.0))
                .density(0.0)
                .friction(0.0),
            body,
            &mut world.bodies,
        );
    }
    for _ in 0..500 {
        world.step();
    }
    let steps = 5000;
    let t0 = Instant::now();
    for _ in 0..steps {
        world.step();
    }
    let us = t0.elapsed().as_secs_f64() * 1e6 / steps as f64;
    let contacts: usize = world
        .narrow_phase
        .contact_pairs()
        .flat_map(|p| p.manifolds())
        .map(|m| m.data.solver_contacts.len())
        .sum();
    let z = world.bodies[bodies[0]].translation().z;
    println!(
        "{n} grousers on {nb} bodies, {iterations} iterations: {us:.1} us/step (real-time factor {:.0}), {contacts} contacts, body z {z:.4} m",
        1e3 / us
    );
}
