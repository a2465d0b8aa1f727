//! The contact hook of the world (Rapier's `PhysicsHooks`): the contact compliance of grousers
//! and belts (`[tracks.compliance]`, `world/compliance.rs`), the contact slop
//! (`simulation.contact_slop_m`, ODE's `min_depth`), which applies to every track method, and
//! forwarding of contacts of colliders a track tagged for itself to that track.

use super::compliance::{SolverSpring, apply_compliance};
use super::soil::modify_soil_contacts;
use crate::terrain::tagged_soil;
use crate::tracks::{SLOP_TAG, Track, TrackContact, tagged_compliance, tagged_track};
use rapier3d::prelude::*;

/// The hook for one step: borrows the tracks.
pub(crate) struct ContactHooks<'a> {
    /// Uncorrected penetration, m: a solver contact shallower than this is reported as
    /// touching (not pushed out, further approach still stopped); a deeper one as depth - slop.
    pub slop: f32,
    /// The tracks, by index (the index in a collider's tag).
    pub tracks: &'a [Box<dyn Track>],
    /// The contact springs, by index (the index in a collider's compliance tag).
    pub springs: &'a [SolverSpring],
    /// Time step, s.
    pub dt: f32,
    /// Deformable soil, if the terrain has some.
    pub soil: Option<&'a super::soil::SoilState>,
    /// The floating origin (world position of the Rapier origin), m.
    pub origin: glam::DVec3,
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

impl PhysicsHooks for ContactHooks<'_> {
    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        let (u1, u2) = (
            ctx.colliders[ctx.collider1].user_data,
            ctx.colliders[ctx.collider2].user_data,
        );
        if let (Some(state), Some(i)) = (self.soil, tagged_soil(u1).or(tagged_soil(u2))) {
            modify_soil_contacts(ctx, state, i, self.origin);
            return;
        }
        let spring = tagged_compliance(u1)
            .or(tagged_compliance(u2))
            .and_then(|i| self.springs.get(i));
        if let Some(&s) = spring {
            apply_compliance(ctx, s, self.dt);
            apply_slop(ctx, self.slop);
            return;
        }
        if u1 == SLOP_TAG || u2 == SLOP_TAG {
            apply_slop(ctx, self.slop);
            return;
        }
        let (index, contact) = match (tagged_track(u1), tagged_track(u2)) {
            (Some(i), _) => (
                i,
                TrackContact {
                    collider: ctx.collider1,
                    sign: 1.0,
                },
            ),
            (None, Some(i)) => (
                i,
                TrackContact {
                    collider: ctx.collider2,
                    sign: -1.0,
                },
            ),
            _ => return,
        };
        let Some(track) = self.tracks.get(index) else {
            return;
        };
        track.modify_contacts(ctx, contact);
        apply_slop(ctx, self.slop);
    }
}
