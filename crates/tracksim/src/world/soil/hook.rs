//! The contact hook's soil stage: a manifold between a vehicle part and a soil surface told how
//! deep the part may sink and how much the soil can shear (`modify_soil_contacts`), a parked track
//! held at its anchor (`hold_parked`).

use super::patch::{Load, origin_cells, patch_of};
use super::state::SoilState;
use super::{ANCHOR_MAX_MPS, ANCHOR_TIME_S, MU_CAP};
use glam::DVec3;
use rapier3d::prelude::*;

/// The contact hook's work on a manifold between a vehicle part and soil `soil` (see the
/// module docs). `sign` is +1 when the part is the manifold's collider 1.
pub(crate) fn modify_soil_contacts(
    ctx: &mut ContactModificationContext,
    state: &SoilState,
    soil_index: usize,
    origin: DVec3,
) {
    let (part_h, ground_h, sign) = if crate::terrain::tagged_soil(
        ctx.colliders[ctx.collider1].user_data,
    ) == Some(soil_index)
    {
        (ctx.collider2, ctx.collider1, -1.0f32)
    } else {
        (ctx.collider1, ctx.collider2, 1.0f32)
    };
    let Some(part) = state.parts.get(&part_h).copied() else {
        return; // not the vehicle's (a loose box): rigid contact
    };
    let Some(soil) = state.soils.get(soil_index) else {
        return;
    };
    let collider = &ctx.colliders[part_h];
    let Some(body) = collider.parent() else {
        return;
    };
    let patch = patch_of(&part, collider);
    // A parked track's anchor: the motion that takes its parent back to where it was parked.
    let back = part
        .track
        .and_then(|t| state.anchors.get(t).copied().flatten())
        .filter(|a| a.origin == origin)
        .map(|a| a.pose * ctx.bodies[a.parent].position().inverse());
    let Some(m) = ctx.rigid_mut() else {
        return;
    };
    if part.drop {
        m.solver_contacts.clear();
        return;
    }
    // A manifold of shapes that only come near (within the prediction distance, or whose
    // bounding boxes overlap on a tilted plate) loads no ground.
    if m.solver_contacts.iter().all(|c| c.dist > 0.0) {
        return;
    }
    // The patch's memory: mean largest sinkage and mean mobilised shear of its cells.
    let oc = origin_cells(soil, origin);
    let (mut n, mut z_hist, mut mob) = (0usize, 0.0f64, 0.0f64);
    let mut cells = state.grid.reader(soil_index);
    patch.cells(soil.cells_per_m(), oc, |ix, iy| {
        n += 1;
        if let Some(c) = cells.cell(ix, iy) {
            z_hist += c.z_max as f64;
            mob += soil.mobilised(c.j as f64);
        }
    });
    let n = n.max(1) as f64;
    let (z_hist, mob) = (z_hist / n, mob / n);
    // The body's pressure over the last step (filtered in the after-step update).
    // Bekker's b: the track's width for a grouser's patch (the footprint's smaller side).
    let area = patch.area();
    let b = match part.grouser {
        Some((_, half_width)) => 2.0 * half_width,
        None => patch.b(),
    };
    let (force_body, area_body, p_rut) = state
        .bodies
        .get(&part.footprint(body))
        .copied()
        .unwrap_or((0.0, area, 0.0));
    let p = force_body / area_body.max(1e-9);
    let force = p * area;
    // Grousers: until their tips have sunk their height the tips alone bear the load (Bekker
    // at the tip pressure, b = the tip's thickness) and the belt stays above the surface; once
    // embedded (or in a rut already) the soil between them moves with the belt and the belt
    // level sinks by Bekker at the footprint's pressure.
    let tips = part.height > 0.0 && part.thickness > 0.0 && z_hist <= 0.0;
    let z_tip = if tips {
        let fraction = (part.thickness / (2.0 * patch.half_len)).min(1.0);
        soil.sinkage(p / fraction, part.thickness)
    } else {
        f64::INFINITY
    };
    let (z, engaged) = if z_tip < part.height {
        (0.0, z_tip)
    } else {
        (soil.loaded_sinkage(p, b, z_hist), part.height)
    };
    let allow = (z + engaged) as f32;
    for c in m.solver_contacts.iter_mut() {
        c.dist += allow;
    }
    // Shear limit of the patch, N.
    let limit = if part.height > 0.0 {
        let tip = area * soil.shear_strength(p);
        let plough = force * soil.interface_phi.tan()
            + soil.passive_force(engaged, 2.0 * patch.half_width, p);
        tip.min(plough)
    } else {
        force * soil.interface_phi.tan()
    } * mob;
    // A track's manifolds share the track's coefficient of the last step (its patches' limits
    // over its load): the solver's split of the load among them (e.g. onto the rear under a
    // drawbar pull) does not change the track's thrust, as under Wong's uniform pressure.
    let shared = part
        .track
        .and_then(|t| state.track_mu.get(t).copied().flatten());
    *m.friction = match shared {
        Some(mu) => mu,
        None if force > 1e-3 => ((limit / force) as f32).min(MU_CAP),
        None => (soil.phi.tan() * mob) as f32,
    };
    let normal = *m.normal * sign;
    if let Some(back) = back {
        hold_parked(m.solver_contacts.iter_mut(), back, normal, sign);
    }
    if let Ok(mut pending) = state.pending.lock() {
        pending.push(Load {
            soil: soil_index,
            track: part.track,
            footprint: part.footprint(body),
            limit,
            patch,
            z,
            z_virgin: if engaged < part.height {
                0.0
            } else {
                soil.sinkage(p_rut, b)
            },
            b,
            force,
            body,
            part: part_h,
            ground: ground_h,
            normal: -normal,
        });
    }
}

/// A parked track's contacts target the sliding velocity that takes each contact point back to
/// where the parked parent held it, `-d / ANCHOR_TIME_S` (at most [`ANCHOR_MAX_MPS`]): the anchor
/// static friction has between steps on rigid ground (recycled contacts keep their points) and
/// soil contacts, rebuilt every step, do not. Still limited by the friction coefficient: a robot
/// the soil cannot hold slides, and moving releases the anchor. `back` takes the parent's pose
/// now to its anchor; `normal` is the soil's normal and `sign` +1 when the part is collider 1.
pub(super) fn hold_parked<'a>(
    contacts: impl Iterator<Item = &'a mut SolverContact>,
    back: Pose,
    normal: Vector,
    sign: f32,
) {
    for c in contacts {
        let p = if sign > 0.0 { c.anchor1 } else { c.anchor2 };
        let d = p - back * p;
        let d = d - normal * d.dot(normal);
        // The velocity of the part relative to the ground that removes the drift; the solver
        // drives (v1 - v2).t to -tangent_velocity.t.
        let w = (-d / ANCHOR_TIME_S).clamp_length_max(ANCHOR_MAX_MPS);
        c.tangent_velocity = -w * sign;
    }
}
