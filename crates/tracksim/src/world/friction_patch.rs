//! The contact hook's patch stage (issue 43, `fault.patch`): a contact between a moving body
//! and the fixed ground (terrain, ground tile, fixed boxes) whose contact point lies inside the
//! low-friction patch's rectangle takes the patch's friction coefficient. Rapier holds one
//! friction coefficient per manifold, so the manifold's contact point is the mean of its
//! solver contacts' points (world x, y: the floating origin plus Rapier's local point). No
//! patch, no change: the stage returns before reading the pair.
//!
//! The hook sees only the pairs of colliders that ask for it, and most vehicle and terrain
//! colliders do not (a pair with the hook is never recycled, so asking would change every
//! run). The first patch put on the ground makes every ground collider ask
//! ([`hook_the_ground`]) for the rest of the world's life: a patch removed later leaves no
//! friction behind in a recycled contact.

use crate::model::FrictionPatch;
use glam::DVec3;
use rapier3d::prelude::*;

/// A change of the world's low-friction patch: put (or replaced) or removed (`patch` `None`)
/// by a command applied at simulated time `t` s (the change acts from the step that starts
/// then). A run's changes in order are its patch timeline, which the replay draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchChange {
    /// Simulated time of the command, s.
    pub t: f64,
    /// The patch in force from then on (`None`: removed).
    pub patch: Option<FrictionPatch>,
}

/// Whether the body `b` of a pair (`None`: a collider without a body) is the fixed ground.
fn is_ground(ctx: &ContactModificationContext, b: Option<RigidBodyHandle>) -> bool {
    b.is_none_or(|b| ctx.bodies[b].is_fixed())
}

/// Sets the patch's friction on the pair of `ctx` if it is a contact with the ground whose
/// mean contact point (world, the Rapier origin at `origin` m) lies inside `patch`.
pub(crate) fn apply_patch(
    ctx: &mut ContactModificationContext,
    patch: &FrictionPatch,
    origin: DVec3,
) {
    if is_ground(ctx, ctx.rigid_body1) == is_ground(ctx, ctx.rigid_body2) {
        return;
    }
    let Some(m) = ctx.rigid_mut() else {
        return;
    };
    let n = m.solver_contacts.len();
    if n == 0 {
        return;
    }
    let sum = m.solver_contacts.iter().fold(DVec3::ZERO, |s, c| {
        s + (c.anchor1 + c.anchor2).as_dvec3() * 0.5
    });
    let p = origin + sum / n as f64;
    if patch.contains(p.x, p.y) {
        *m.friction = patch.friction as f32;
    }
}

/// Turns the contact hook on for every collider of the fixed ground (without a body, or on a
/// fixed one) that does not have it yet, so that its contacts reach the patch stage.
pub(crate) fn hook_the_ground(world: &mut PhysicsWorld) {
    let bodies = &world.bodies;
    for (_, c) in world.colliders.iter_mut() {
        let ground = c.parent().is_none_or(|b| bodies[b].is_fixed());
        if ground
            && !c
                .active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        {
            c.set_active_hooks(c.active_hooks() | ActiveHooks::MODIFY_SOLVER_CONTACTS);
        }
    }
}
