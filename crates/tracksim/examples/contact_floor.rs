//! The contact floor of the Table II case: what Rapier alone charges per step for the grouser
//! contacts of a PackBot, without any track machinery (no segment links, no joints, no
//! placement). Two 7.5 kg boxes (left and right track, not joined) each carry `n / 2`
//! separate 5 x 75 x 8 mm grouser colliders 38 mm apart and slide at 0.3 m/s over a
//! frictionless ground plane, dt 1 ms, 4 solver iterations (the defaults `tracksim bench`
//! uses).
//!
//! `cargo run --release -p tracksim --example contact_floor [-- N]` (default N = 36: the
//! grousers within the 2 cm prediction distance of the ground in the bench case).
use rapier3d::prelude::*;
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(36);
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters.dt = 0.001;
    world.integration_parameters.num_solver_iterations = 4;
    world
        .colliders
        .insert(ColliderBuilder::new(SharedShape::halfspace(Vector::Z)).friction(0.0));
    let mut bodies = Vec::new();
    for y in [0.16f32, -0.16] {
        let body = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, y, 0.004))
                .linvel(Vector::new(0.3, 0.0, 0.0))
                .can_sleep(false),
        );
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.25, 0.03, 0.03)
                .translation(Vector::new(0.0, 0.0, 0.05))
                .mass(7.5),
            body,
            &mut world.bodies,
        );
        bodies.push(body);
    }
    for k in 0..n {
        let (row, i) = (k % 2, k / 2);
        let body = bodies[row];
        let x = -0.3 + 0.0384 * i as f32;
        let y = 0.0;
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.0025, 0.0375, 0.004)
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
        "{n} grousers: {us:.1} us/step (real-time factor {:.0}), {contacts} contacts, body z {z:.4} m",
        1e3 / us
    );
}
