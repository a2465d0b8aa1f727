//! The conveyor stage of [`Simulation::new`] and its state: every conveyor is a fixed body of
//! the world carrying a belt the track layer builds (`tracks::build_conveyor_belt`: a track whose
//! parent is the world, not a vehicle), its belt held at the file's speed; loose boxes are free
//! bodies. Their
//! colliders touch the vehicle and each other; the conveyor's do not touch the terrain.

use crate::check::{f, q};
use crate::error::Result;
use crate::model::Scenario;
use crate::tracks::{BuildContext, Track, build_conveyor_belt, conveyor_groups, loose_groups};
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

/// What the conveyor stage adds to the world.
#[derive(Debug, Default)]
pub(crate) struct Conveyors {
    /// Each conveyor's belt (segment links on its fixed frame body), running.
    pub(crate) belts: Vec<Box<dyn Track>>,
    /// The loose boxes' bodies, in file order.
    pub(crate) loose: Vec<RigidBodyHandle>,
}

/// Builds the conveyors and loose boxes of `sc` in `world`, whose origin is at `origin` m.
pub(crate) fn build_conveyors(
    world: &mut PhysicsWorld,
    sc: &Scenario,
    origin: DVec3,
) -> Result<Conveyors> {
    let mut out = Conveyors::default();
    for (i, cv) in sc.conveyors.iter().enumerate() {
        let frame = world.bodies.insert(
            RigidBodyBuilder::fixed()
                .pose(Pose::from_parts(f(cv.centre - origin), q(cv.rotation()))),
        );
        let mut ctx = BuildContext {
            world: &mut *world,
            parent: frame,
            index: sc.vehicle.tracks.len() + i,
            groups: conveyor_groups(),
            min_link_mass: sc.solver.min_link_mass,
        };
        let mut belt = build_conveyor_belt(&mut ctx, &cv.belt)?;
        belt.set_belt_speed(world, cv.speed);
        never_recycled(world, belt.as_ref());
        out.belts.push(belt);
    }
    for b in &sc.loose_boxes {
        let s = &b.solid;
        let rot = DQuat::from_rotation_z(s.yaw);
        let h = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(f(s.centre - origin), q(rot)))
                .can_sleep(false),
        );
        let c = ColliderBuilder::cuboid(s.half.x as f32, s.half.y as f32, s.half.z as f32)
            .mass(b.mass as f32)
            .friction(s.friction as f32)
            .collision_groups(loose_groups());
        world.colliders.insert_with_parent(c, h, &mut world.bodies);
        out.loose.push(h);
    }
    Ok(out)
}

/// Turns the contact hook on for every collider of a conveyor's belt, because Rapier never
/// recycles a pair with a hook (the hook changes nothing for them). A box riding a belt keeps
/// its relative pose to the belt's link for long stretches, so recycling froze the pair's
/// contact anchors and normal in world space while both moved at belt speed: the box rode
/// 2.9 % slower than the belt (1.5 % at dt 0.5 ms), or 1.5 % faster on the bundled scenario;
/// with fresh contacts every step it rides at the belt's speed (issue 23.6).
fn never_recycled(world: &mut PhysicsWorld, belt: &dyn Track) {
    for body in belt.bodies() {
        let colliders: Vec<ColliderHandle> = world.bodies[body].colliders().to_vec();
        for h in colliders {
            let c = &mut world.colliders[h];
            c.set_active_hooks(c.active_hooks() | ActiveHooks::MODIFY_SOLVER_CONTACTS);
        }
    }
}

impl Conveyors {
    /// The belts' work after a physics step (the paper's rollback).
    pub(crate) fn after_step(&mut self, world: &mut PhysicsWorld, dt: f64) {
        for b in &mut self.belts {
            b.after_step(world, dt);
        }
    }
}
