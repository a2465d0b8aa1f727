//! The contact hook of the world (Rapier's `PhysicsHooks`): every contact pair goes through four
//! stages in order, each acting on the pairs its collider tags name (issue 39; the hook used to
//! take the first match and return, so a track's own contact code never ran on soil):
//!
//! 1. soil (`world/soil.rs`): how deep the part may sink and the soil's shear limit;
//!    then a low-friction patch's friction on ground contacts inside it (`fault.patch`,
//!    `world/friction_patch.rs`), when the world has one;
//! 2. the track's own contacts (`Track::modify_contacts`: constraint-to-ground's belt speed);
//! 3. compliance of grousers and belts (`[tracks.compliance]`, `world/compliance.rs`);
//! 4. the contact slop (`simulation.contact_slop_m`, ODE's `min_depth`) on every track
//!    contact, whatever the method;
//! 5. a manifold with the ground that cannot act in this step is dropped
//!    (`world/speculative_cull.rs`, `simulation.cull_speculative_contacts`), on the contacts
//!    as the stages before left them.

use super::compliance::{SolverSpring, apply_compliance};
use super::friction_patch::apply_patch;
use super::soil::modify_soil_contacts;
use super::speculative_cull::{CullMode, cull_speculative};
use crate::model::FrictionPatch;
use crate::terrain::tagged_soil;
use crate::tracks::{SLOP_TAG, Track, TrackContact, tagged_compliance, tagged_track};
use rapier3d::prelude::*;

/// The hook for one step: borrows the tracks.
pub(crate) struct ContactHooks<'a> {
    /// Uncorrected penetration, m: a solver contact shallower than this is reported as
    /// touching (not pushed out, further approach still stopped); a deeper one as depth - slop.
    pub slop: f32,
    /// The robots, whose tracks are numbered in order (the index in a collider's tag).
    pub robots: &'a [super::robot::Robot],
    /// The contact springs, by index (the index in a collider's compliance tag).
    pub springs: &'a [SolverSpring],
    /// Time step, s.
    pub dt: f32,
    /// Deformable soil, if the terrain has some.
    pub soil: Option<&'a super::soil::SoilState>,
    /// The floating origin (world position of the Rapier origin), m.
    pub origin: glam::DVec3,
    /// The low-friction patch on the ground (`fault.patch`), if one is in force.
    pub patch: Option<&'a FrictionPatch>,
    /// What becomes of a manifold with the ground that cannot act in this step.
    pub cull: CullMode<'a>,
}

/// Applies the slop to every solver contact of the pair.
fn apply_slop(ctx: &mut ContactModificationContext, slop: f32) {
    if let Some(m) = ctx.rigid_mut() {
        for c in m.solver_contacts.iter_mut() {
            if c.dist < 0.0 {
                c.dist = (c.dist + slop).min(0.0);
            }
        }
    }
}

/// The track contact of a pair: the track's index and which collider is the track's (`None`:
/// neither collider carries a track's tag).
fn track_contact(
    ctx: &ContactModificationContext,
    u1: u128,
    u2: u128,
) -> Option<(usize, TrackContact)> {
    match (tagged_track(u1), tagged_track(u2)) {
        (Some(i), _) => Some((
            i,
            TrackContact {
                collider: ctx.collider1,
                sign: 1.0,
            },
        )),
        (None, Some(i)) => Some((
            i,
            TrackContact {
                collider: ctx.collider2,
                sign: -1.0,
            },
        )),
        _ => None,
    }
}

impl ContactHooks<'_> {
    /// The track whose tag index is `index` (robots number their tracks one after another).
    fn track(&self, index: usize) -> Option<&dyn Track> {
        self.robots.iter().find_map(|r| {
            let i = index.checked_sub(r.first_track)?;
            r.tracks.get(i).map(|t| &**t)
        })
    }

    /// Stage 1, soil: a vehicle part on a soil surface may sink as deep as the soil yields
    /// (`dist` raised) and slides at the soil's shear limit (the friction coefficient), see
    /// `world/soil.rs`.
    fn soil_stage(&self, ctx: &mut ContactModificationContext, u1: u128, u2: u128) {
        if let (Some(state), Some(i)) = (self.soil, tagged_soil(u1).or(tagged_soil(u2))) {
            modify_soil_contacts(ctx, state, i, self.origin);
        }
        if let Some(p) = self.patch {
            apply_patch(ctx, p, self.origin);
        }
    }

    /// Stage 2, the track's own contacts (e.g. constraint-to-ground's belt surface velocity).
    fn track_stage(&self, ctx: &mut ContactModificationContext, u1: u128, u2: u128) {
        if let Some((index, contact)) = track_contact(ctx, u1, u2)
            && let Some(track) = self.track(index)
        {
            track.modify_contacts(ctx, contact);
        }
    }

    /// Stage 3, compliance: the contact spring of grousers and belts (`[tracks.compliance]`).
    fn compliance_stage(&self, ctx: &mut ContactModificationContext, u1: u128, u2: u128) {
        let spring = tagged_compliance(u1)
            .or(tagged_compliance(u2))
            .and_then(|i| self.springs.get(i));
        if let Some(&s) = spring {
            apply_compliance(ctx, s, self.dt);
        }
    }

    /// Stage 4, slop: to the contacts of a track's colliders (tagged with the track, its
    /// compliance or the slop), `simulation.contact_slop_m`.
    fn slop_stage(&self, ctx: &mut ContactModificationContext, u1: u128, u2: u128) {
        let tracked =
            |u: u128| u == SLOP_TAG || tagged_track(u).is_some() || tagged_compliance(u).is_some();
        if tracked(u1) || tracked(u2) {
            apply_slop(ctx, self.slop);
        }
    }
}

impl PhysicsHooks for ContactHooks<'_> {
    /// Every pair goes through the stages in order: soil, the track's own contacts,
    /// compliance, slop (each acts only on the pairs its tags name), the cull of contacts that
    /// cannot act.
    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        let (u1, u2) = (
            ctx.colliders[ctx.collider1].user_data,
            ctx.colliders[ctx.collider2].user_data,
        );
        self.soil_stage(ctx, u1, u2);
        self.track_stage(ctx, u1, u2);
        self.compliance_stage(ctx, u1, u2);
        self.slop_stage(ctx, u1, u2);
        // Not on soil: its after-step update reads the manifolds it allowed to sink.
        if tagged_soil(u1).or(tagged_soil(u2)).is_none() {
            cull_speculative(ctx, &self.cull, self.dt);
        }
    }
}
