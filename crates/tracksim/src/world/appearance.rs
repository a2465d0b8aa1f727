//! What the world's colliders look like in camera images ([`Appearance`]): a colour per
//! collider, set when the world is built (the terrain's per entry, each robot's per part:
//! chassis, flippers, tracks; loose boxes and conveyors) and read by the colour cameras.
//! Looks never touch the physics.

use crate::render::{Rgb, palette};
use rapier3d::prelude::*;
use rustc_hash::FxHashMap;

/// The colour of every collider of a world.
#[derive(Clone, Debug, Default)]
pub struct Appearance {
    colors: FxHashMap<ColliderHandle, Rgb>,
}

impl Appearance {
    /// The colour of collider `h` ([`palette::OTHER`] for one of no known part).
    pub fn color(&self, h: ColliderHandle) -> Rgb {
        self.colors.get(&h).copied().unwrap_or(palette::OTHER)
    }

    /// Gives collider `h` colour `c`.
    pub(crate) fn set(&mut self, h: ColliderHandle, c: Rgb) {
        self.colors.insert(h, c);
    }

    /// Gives every collider of `bodies` colour `c`.
    pub(crate) fn paint(&mut self, world: &PhysicsWorld, bodies: &[RigidBodyHandle], c: Rgb) {
        for &b in bodies {
            for &h in world.bodies[b].colliders() {
                self.set(h, c);
            }
        }
    }
}

/// Builds the appearance of a world: `terrain` (its colliders and colours), each robot's
/// parts (`(chassis, flippers, track bodies, colours)`), the conveyors' bodies and the loose
/// boxes' bodies with their colours.
pub(crate) fn appearance(
    world: &PhysicsWorld,
    terrain: &[(ColliderHandle, Rgb)],
    robots: &[(
        RigidBodyHandle,
        Vec<RigidBodyHandle>,
        Vec<RigidBodyHandle>,
        crate::model::VehicleColors,
    )],
    conveyors: &[RigidBodyHandle],
    loose: &[(RigidBodyHandle, Rgb)],
) -> Appearance {
    let mut a = Appearance::default();
    for &(h, c) in terrain {
        a.set(h, c);
    }
    for (body, flippers, tracks, colors) in robots {
        a.paint(world, tracks, colors.tracks);
        a.paint(world, flippers, colors.flippers);
        a.paint(world, &[*body], colors.body);
    }
    a.paint(world, conveyors, palette::CONVEYOR);
    for &(b, c) in loose {
        a.paint(world, &[b], c);
    }
    a
}
