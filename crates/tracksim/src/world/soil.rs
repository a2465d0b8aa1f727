//! Deformable soil at run time (issue 30; docs/SOIL.md, docs/DESIGN.md "Soil"). Rapier still
//! resolves every contact; the soil decides how the ground pushes back, in the contact hook,
//! per contact manifold of a vehicle part with a soil surface:
//!
//! - **Normal**: the part owns a patch of ground (a grouser: one pitch of the track's
//!   footprint, `pitch x width`, centred on it; any other part: its bounding box seen from
//!   above). The patch's pressure is the manifold's normal force (last step's impulses,
//!   low-pass filtered with the soil's damping, as the contact compliance does) over its area;
//!   Bekker's law with the cells' plastic memory gives the sinkage (`SoilModel::loaded_sinkage`)
//!   and the solver is told the part may sink that deep (`dist += sinkage`): it pushes back
//!   only what is deeper. A grouser's tip sinks its height further: grousers are fully
//!   embedded and the soil between them moves with the belt (Wong's track model), so the belt
//!   surface of a track with grousers does not touch the soil (its contacts are dropped).
//! - **Tangential**: the manifold's friction coefficient is the patch's shear limit over its
//!   normal force. A grouser patch shears at the tip plane, `A (c + p tan phi)`, unless the
//!   soil ploughs past the grouser first: the smooth belt's `A p tan delta` plus the Rankine
//!   passive resistance of the grouser's face with the track's pressure as surcharge (the
//!   smaller governs). Other parts shear at the interface, `A p tan delta`. Either is
//!   mobilised by Janosi-Hanamoto with the mean shear displacement of the patch's cells.
//! - **After the step**: each loaded cell keeps its largest sinkage (the rut) and accumulates
//!   the slip of the part over it (its shear displacement), which restarts once a cell has been
//!   unloaded for [`SHEAR_RESET_S`]. Every deepening of a cell costs Bekker's work
//!   (`integral p dz` over its area, from its old depth to the new): Bekker's compaction
//!   resistance, given back as an impulse on the chassis against its horizontal motion (none
//!   when that would take more than half its momentum: a robot settling, not driving).
//! - **Reported forces**: the normal load is the solver's normal impulses (exact); the thrust
//!   is the friction impulses, whose vehicle total is measured by momentum (Rapier's twist
//!   friction keeps only its last substep's impulse; see
//!   [`Simulation::soil_contact_impulses`]).

use super::Simulation;
use super::rut_grid::{RutGrid, RutGridStats};
use crate::model::TrackModel;
use crate::terrain::SoilModel;
use crate::tracks::Track;
use glam::{DVec2, DVec3};
use rapier3d::prelude::*;
use std::collections::HashMap;
use std::sync::Mutex;

/// A cell unloaded this long forgets its shear displacement, s.
pub const SHEAR_RESET_S: f64 = 0.1;
/// Largest friction coefficient a soil contact gets (a light load on cohesive soil), -.
const MU_CAP: f32 = 5.0;
/// Cells whose centre lies within this of a patch's edge are outside it, m: far above the f32
/// rounding of a position near the floating origin (0.1 um), far below a cell.
const EDGE_MARGIN_M: f64 = 1e-6;
/// Below this chassis speed no compaction impulse is applied, m/s.
const COMPACTION_MIN_SPEED_MPS: f64 = 1e-3;
/// Time constant of the pressure a rut keeps, s: the footprint's pressure (its force over its
/// patches' area) low-pass filtered this long sets how deep a cell is pressed for good. A
/// track's grouser patches in contact alternate between N and N + 1 as grousers pass the
/// pulleys (one pitch of area: 6 % on PackBot), and the solver's force fluctuates; a cell
/// keeps its largest sinkage, so a rut that followed each step's pressure kept its peaks
/// (issue 38.4: sinkage 14 % over Bekker at n = 0.5 = the pressure over N patches, not the
/// mean).
const RUT_PRESSURE_TIME_S: f64 = 0.5;
/// A track whose belt is held and whose parent moves slower than this (horizontally) is
/// parked: its soil contacts hold on to where it was parked (static friction's anchor), m/s.
const ANCHOR_SPEED_MPS: f64 = 0.01;
/// ... and turns slower than this, rad/s.
const ANCHOR_TURN_RADPS: f64 = 0.05;
/// Time constant of a parked track's return to its anchor, s.
const ANCHOR_TIME_S: f32 = 0.2;
/// Largest speed of that return, m/s (below [`ANCHOR_SPEED_MPS`]: the return never releases
/// the anchor).
const ANCHOR_MAX_MPS: f32 = 0.002;

/// How a vehicle collider loads the soil.
#[derive(Clone, Copy, Debug)]
struct Part {
    /// The track it belongs to, if any.
    track: Option<usize>,
    /// A grouser: half the pitch (along its x) and half the track width (its y), m; otherwise
    /// the patch is its bounding box.
    grouser: Option<(f64, f64)>,
    /// Grouser height, m (0 for other parts).
    height: f64,
    /// Grouser thickness along the track, m (its tip bears the load until it is embedded).
    thickness: f64,
    /// The belt surface of a track with grousers: its soil contacts are dropped.
    drop: bool,
}

/// What shares one pressure: a track, or a body that is not part of a track.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Footprint {
    Track(usize),
    Body(RigidBodyHandle),
}

impl Part {
    fn footprint(&self, body: RigidBodyHandle) -> Footprint {
        match self.track {
            Some(t) => Footprint::Track(t),
            None => Footprint::Body(body),
        }
    }
}

/// A patch of ground a part loads, in Rapier coordinates.
#[derive(Clone, Copy, Debug)]
struct Patch {
    centre: DVec2,
    /// Unit vector of the patch's length.
    along: DVec2,
    half_len: f64,
    half_width: f64,
}

impl Patch {
    fn area(&self) -> f64 {
        4.0 * self.half_len * self.half_width
    }
    /// Bekker's `b`: the smaller side, m.
    fn b(&self) -> f64 {
        2.0 * self.half_len.min(self.half_width)
    }
    /// Calls `f` with the world indices of every cell whose centre lies in the patch (the cell
    /// under the centre when none does).
    fn cells(&self, per_m: i64, origin_cells: (i64, i64), mut f: impl FnMut(i64, i64)) {
        let pm = per_m as f64;
        let across = DVec2::new(-self.along.y, self.along.x);
        let ex = self.along.x.abs() * self.half_len + across.x.abs() * self.half_width;
        let ey = self.along.y.abs() * self.half_len + across.y.abs() * self.half_width;
        let (x0, x1) = (
            ((self.centre.x - ex) * pm).floor() as i64,
            ((self.centre.x + ex) * pm).floor() as i64,
        );
        let (y0, y1) = (
            ((self.centre.y - ey) * pm).floor() as i64,
            ((self.centre.y + ey) * pm).floor() as i64,
        );
        let mut any = false;
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                let c = DVec2::new((ix as f64 + 0.5) / pm, (iy as f64 + 0.5) / pm) - self.centre;
                // A cell centre on the patch's edge (a 75 mm track is 7.5 cells of 1 cm) is
                // left out on both sides alike: without the margin, f32 rounding of the track's
                // position (y = +-0.1625 m) took the edge cell on the left and not on the right,
                // and turns on sand did not mirror.
                if c.dot(self.along).abs() <= self.half_len - EDGE_MARGIN_M
                    && c.dot(across).abs() <= self.half_width - EDGE_MARGIN_M
                {
                    any = true;
                    f(ix + origin_cells.0, iy + origin_cells.1);
                }
            }
        }
        if !any {
            f(
                (self.centre.x * pm).floor() as i64 + origin_cells.0,
                (self.centre.y * pm).floor() as i64 + origin_cells.1,
            );
        }
    }
}

/// A manifold's load on the soil this step, for the after-step update.
#[derive(Clone, Copy, Debug)]
struct Load {
    soil: usize,
    track: Option<usize>,
    footprint: Footprint,
    patch: Patch,
    /// The sinkage the solver was told (belt level, without the grouser height), m.
    z: f64,
    /// Bekker's sinkage at the patch's pressure on virgin soil (0 while the grousers' tips
    /// bear), m: what a cell loaded now is pressed to at least. (The patch's `z` follows the
    /// mean memory of its cells; a fresh cell does not inherit its neighbours' depth.)
    z_virgin: f64,
    /// Bekker's b, m.
    b: f64,
    /// The patch's shear limit, mobilised, N.
    limit: f64,
    /// The filtered normal force, N.
    force: f64,
    body: RigidBodyHandle,
    part: ColliderHandle,
    ground: ColliderHandle,
    /// Soil surface normal (Rapier frame, pointing out of the soil).
    normal: Vector,
}

/// What one track does in the soil over the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct TrackSoil {
    /// Mean sinkage of the track's loaded patches weighted by their load (belt level below the
    /// undisturbed surface), m; 0 off soil.
    pub sinkage_m: f64,
    /// Largest sinkage of a loaded patch, m.
    pub max_sinkage_m: f64,
    /// The soil's normal load on the track, N.
    pub normal_n: f64,
    /// The soil's shear force on the track along the chassis's forward axis, N (its thrust).
    pub thrust_n: f64,
    /// Compaction resistance given back this step, N (work of compacting fresh soil over the
    /// distance driven).
    pub compaction_n: f64,
    /// Area of the loaded patches, m^2 (the contact area `A` of Wong's thrust).
    pub contact_area_m2: f64,
    /// Length of ground the loaded patches span along the chassis's x, m (Wong's `l`).
    pub contact_length_m: f64,
}

/// The soil state of a simulation.
pub(crate) struct SoilState {
    soils: Vec<SoilModel>,
    grid: RutGrid,
    parts: HashMap<ColliderHandle, Part>,
    pending: Mutex<Vec<Load>>,
    /// Each loaded footprint's soil force, low-pass filtered, N, and the area of its
    /// patches, m^2, from the last step. A track is one footprint: its belt does not stretch
    /// (the paper's non-deformable track), so its patches share one pressure, Wong's uniform
    /// pressure (the solver's split of a rigid link's load among its contacts is arbitrary).
    /// Any other part is its own footprint.
    bodies: HashMap<Footprint, (f64, f64, f64)>,
    tracks: Vec<TrackSoil>,
    /// Each track's friction coefficient for the next step: its patches' mobilised limits over
    /// its load (None off soil).
    track_mu: Vec<Option<f32>>,
    /// Steps a cell keeps its shear displacement unloaded.
    reset_steps: u32,
    /// Buffers the after-step update reuses (no allocation per step once warmed up).
    buffers: Buffers,
    /// The cells deepened lately, with a sequence number (at most [`RECENT_CELLS`]), for the
    /// live view.
    recent: std::collections::VecDeque<(u64, usize, i64, i64)>,
    /// Sequence number of the next deepened cell.
    seq: u64,
    /// The vehicle's linear momentum before the step, N s (Rapier frame): the exact measure of
    /// the friction impulses (see [`Simulation::soil_contact_impulses`]).
    momentum_before: Vector,
    /// Each parked track's anchor: its parent body, the parent's pose when it was parked
    /// (Rapier frame) and the floating origin then (see [`Simulation::update_anchors`]).
    anchors: Vec<Option<Anchor>>,
}

/// Where a parked track's parent stood when it was parked.
#[derive(Clone, Copy, Debug)]
struct Anchor {
    parent: RigidBodyHandle,
    pose: Pose,
    origin: DVec3,
}

/// A footprint's raw soil force this step, N, its patches' area, m^2, its soil and Bekker's
/// `b`, m.
type RawLoad = (f64, f64, usize, f64);

/// The after-step update's buffers, kept between steps.
#[derive(Default)]
struct Buffers {
    loads: Vec<Load>,
    raw: HashMap<Footprint, RawLoad>,
    seen: std::collections::HashSet<ColliderHandle>,
    bodies: HashMap<Footprint, (f64, f64, f64)>,
}

/// A cell is reported to the live view again each time its rut reaches a multiple of this, m.
const RUT_REPORT_STEP_M: f32 = 5e-4;
/// Deepened cells the live feed can catch up on.
const RECENT_CELLS: usize = 65_536;

impl std::fmt::Debug for SoilState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SoilState")
            .field("soils", &self.soils.len())
            .field("grid", &self.grid.stats())
            .finish()
    }
}

/// Builds the soil state when the terrain has soil: every vehicle collider is given its part.
pub(crate) fn build_soil(
    world: &PhysicsWorld,
    soils: &[SoilModel],
    models: &[TrackModel],
    tracks: &[Box<dyn Track>],
    vehicle_bodies: &[RigidBodyHandle],
    dt: f64,
) -> Option<SoilState> {
    if soils.is_empty() {
        return None;
    }
    let mut parts = HashMap::new();
    for &b in vehicle_bodies {
        for &h in world.bodies[b].colliders() {
            parts.insert(
                h,
                Part {
                    track: None,
                    grouser: None,
                    height: 0.0,
                    thickness: 0.0,
                    drop: false,
                },
            );
        }
    }
    for (i, (model, track)) in models.iter().zip(tracks).enumerate() {
        let per_grouser = track.grousers_on_footprints();
        let grousers = track.grouser_colliders();
        let g = model.grousers.as_ref();
        for b in track.bodies() {
            for &h in world.bodies[b].colliders() {
                let is_grouser = grousers.contains(&h);
                let part = Part {
                    track: Some(i),
                    grouser: match (is_grouser && per_grouser, g) {
                        (true, Some(g)) => {
                            Some((0.5 * g.layout.pitch(&model.path), 0.5 * model.width))
                        }
                        _ => None,
                    },
                    height: if is_grouser {
                        g.map_or(0.0, |g| g.height)
                    } else {
                        0.0
                    },
                    thickness: g.map_or(0.0, grouser_thickness),
                    drop: !is_grouser && g.is_some() && !grousers.is_empty(),
                };
                parts.insert(h, part);
            }
        }
    }
    Some(SoilState {
        grid: RutGrid::new(soils.iter().map(|s| s.max_tiles).collect()),
        soils: soils.to_vec(),
        parts,
        pending: Mutex::new(Vec::new()),
        bodies: HashMap::new(),
        tracks: vec![TrackSoil::default(); models.len()],
        track_mu: vec![None; models.len()],
        reset_steps: (SHEAR_RESET_S / dt).ceil() as u32,
        recent: std::collections::VecDeque::new(),
        seq: 0,
        momentum_before: Vector::ZERO,
        anchors: vec![None; models.len()],
        buffers: Buffers::default(),
    })
}

/// Thickness along the track of a track's first grouser shape, m.
fn grouser_thickness(g: &crate::model::GrouserModel) -> f64 {
    match g.shapes.first() {
        Some(crate::model::GrouserShape::Box { half, .. }) => 2.0 * half.x,
        Some(crate::model::GrouserShape::Convex(pts)) => {
            let (lo, hi) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.x), b.max(p.x)));
            (hi - lo).max(0.0)
        }
        None => 0.0,
    }
}

/// The floating origin in whole cells of `soil`.
fn origin_cells(soil: &SoilModel, origin: DVec3) -> (i64, i64) {
    let per_m = soil.cells_per_m();
    (
        origin.x.round() as i64 * per_m,
        origin.y.round() as i64 * per_m,
    )
}

/// The patch part `p` of collider `c` loads.
fn patch_of(p: &Part, c: &Collider) -> Patch {
    let pos = c.position();
    let t = pos.translation;
    let centre = DVec2::new(t.x as f64, t.y as f64);
    match p.grouser {
        Some((half_len, half_width)) => {
            let x = pos.rotation * Vector::X;
            let along = DVec2::new(x.x as f64, x.y as f64)
                .try_normalize()
                .unwrap_or(DVec2::X);
            Patch {
                centre,
                along,
                half_len,
                half_width,
            }
        }
        None => {
            let a = c.compute_aabb();
            let (lo, hi) = (a.mins, a.maxs);
            Patch {
                centre: DVec2::new(0.5 * (lo.x + hi.x) as f64, 0.5 * (lo.y + hi.y) as f64),
                along: DVec2::X,
                half_len: (0.5 * (hi.x - lo.x) as f64).max(1e-3),
                half_width: (0.5 * (hi.y - lo.y) as f64).max(1e-3),
            }
        }
    }
}

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
fn hold_parked<'a>(
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

/// When a load presses its cells: the step's number (from 1), the time s, the step s, and the
/// floating origin.
#[derive(Clone, Copy)]
struct Pressing {
    step: u32,
    time: f32,
    dt: f64,
    origin: DVec3,
}

impl SoilState {
    /// Presses load `l`'s cells (its part slipping at `slip` m/s over them): each keeps its
    /// largest sinkage and adds the slip to its shear displacement (restarting once unloaded
    /// for [`SHEAR_RESET_S`]); returns the work of compacting the fresh cells, J.
    fn press(&mut self, l: &Load, slip: f64, at: Pressing) -> f64 {
        let soil = &self.soils[l.soil];
        let oc = origin_cells(soil, at.origin);
        let cell_area = soil.cell * soil.cell;
        let reset = self.reset_steps;
        let step = at.step;
        let mut grid = self.grid.writer(l.soil, step);
        let mut fresh_work = 0.0;
        let (recent, seq) = (&mut self.recent, &mut self.seq);
        let z = l.z_virgin as f32;
        l.patch.cells(soil.cells_per_m(), oc, |ix, iy| {
            let cell = grid.cell(ix, iy);
            let first = cell.last == 0;
            if first || cell.last + reset < step {
                cell.j = 0.0;
            }
            // Every deepening of a cell costs Bekker's work from its old depth to the new one
            // (a cell under a track is pressed a little deeper whenever the track's pressure
            // peaks): the work given back sums to the work of the ruts left (issue 38.4; only
            // the first press of a cell was counted, and the ruts held 2x the work given back
            // at n = 0.5).
            if z > cell.z_max {
                fresh_work += cell_area * soil.compaction_work(cell.z_max as f64, l.z_virgin, l.b);
            }
            if first {
                cell.t_first = at.time;
            }
            // For the live view: a cell whose rut reaches a new half millimetre (a gradual
            // deepening crosses the levels too; a threshold on each step's increment missed it).
            let level = |d: f32| (d / RUT_REPORT_STEP_M).floor();
            if z > cell.z_max && (cell.z_max <= 0.0 || level(z) > level(cell.z_max)) {
                if recent.len() == RECENT_CELLS {
                    recent.pop_front();
                }
                recent.push_back((*seq, l.soil, ix, iy));
                *seq += 1;
            }
            cell.z_max = cell.z_max.max(z);
            cell.j += (slip * at.dt) as f32;
            cell.last = step;
        });
        fresh_work
    }

    /// Each footprint's force, low-pass filtered with the soil's damping over its local
    /// stiffness (a Kelvin-Voigt element, as the contact compliance), from this step's raw
    /// forces `raw` (force N, area m^2, soil, Bekker's b m). `dt` in s.
    fn filter_footprints(&mut self, raw: &HashMap<Footprint, RawLoad>, dt: f64) {
        let mut bodies = std::mem::take(&mut self.buffers.bodies);
        bodies.clear();
        for (&h, &(force_now, area, soil_i, b)) in raw {
            let soil = &self.soils[soil_i];
            let (previous, previous_rut) = self.bodies.get(&h).map_or((0.0, 0.0), |v| (v.0, v.2));
            // The stiffness at the larger of the two loads on Bekker's curve: a first contact
            // (nothing filtered yet) is not taken as stiff as the elastic line.
            let p = previous.max(force_now) / area;
            let z = soil.sinkage(p, b);
            let k_local = if z > 1e-6 {
                soil.n * p / z
            } else {
                soil.elastic_stiffness
            };
            let tau = soil.damping / k_local.max(1.0);
            let gain = if tau > dt { dt / tau } else { 1.0 };
            let rut_gain = (dt / RUT_PRESSURE_TIME_S).min(1.0);
            bodies.insert(
                h,
                (
                    previous + gain * (force_now - previous),
                    area,
                    previous_rut + rut_gain * (force_now / area.max(1e-9) - previous_rut),
                ),
            );
        }
        self.buffers.bodies = std::mem::replace(&mut self.bodies, bodies);
    }

    /// The figures of the last step, per track.
    pub(crate) fn track_soil(&self) -> &[TrackSoil] {
        &self.tracks
    }

    /// The rut grid.
    pub(crate) fn grid(&self) -> &RutGrid {
        &self.grid
    }

    /// The soils.
    pub(crate) fn soils(&self) -> &[SoilModel] {
        &self.soils
    }
}

impl Simulation {
    /// The soil's work after a step (see the module docs): ruts, shear displacement, the
    /// per-track figures and the compaction impulse. `step` is the number of the step just
    /// taken (from 1).
    pub(crate) fn soil_after_step(&mut self) {
        let Some(mut state) = self.soil.take() else {
            return;
        };
        self.soil_update(&mut state);
        self.soil = Some(state);
    }

    /// The body track `t` runs on.
    fn track_parent(&self, t: usize) -> RigidBodyHandle {
        match self.scenario.vehicle.tracks[t].parent {
            crate::model::Parent::Body => self.robots[0].body,
            crate::model::Parent::Flipper(i) => self.robots[0].flippers[i].body,
        }
    }

    /// The slip over the ground at load `l`'s patch centre `c`, after the solve, m/s: for a
    /// track, the belt surface's (its parent's motion plus the belt running backwards along the
    /// parent's x at the measured belt speed), as Janosi's shear displacement of a track counts
    /// it (the grousers' own path on the pulleys would add the kinematics of entering and
    /// leaving the soil); for another part, its own. Without the normal component.
    fn load_slip(&self, l: &Load, c: Vector) -> f64 {
        let v = match l.track {
            Some(t) => {
                let parent = &self.world.bodies[self.track_parent(t)];
                parent.velocity_at_point(c)
                    - parent.rotation()
                        * Vector::X
                        * self.robots[0].tracks[t].measured_belt_speed() as f32
            }
            None => self.world.bodies[l.body].velocity_at_point(c),
        };
        (v - l.normal * v.dot(l.normal)).length() as f64
    }

    /// The soil's normal force on load `l`'s part over the last step, N (the solver's total).
    fn load_normal(&self, l: &Load) -> f64 {
        self.world
            .narrow_phase
            .contact_pair(l.part, l.ground)
            .map_or(0.0, |pair| {
                pair.solver_manifolds()
                    .iter()
                    .flat_map(|m| m.points.iter())
                    .map(|p| p.data.impulse as f64)
                    .sum::<f64>()
            })
            / self.dt
    }

    /// The vehicle's linear momentum, N s (Rapier frame).
    fn vehicle_momentum(&self) -> Vector {
        self.vehicle_bodies()
            .into_iter()
            .map(|h| {
                let b = &self.world.bodies[h];
                b.linvel() * b.mass()
            })
            .sum()
    }

    /// Before a step on soil: keeps the vehicle's momentum for the after-step measure.
    pub(crate) fn soil_before_step(&mut self) {
        if self.soil.is_some() {
            let p = self.vehicle_momentum();
            if let Some(s) = self.soil.as_mut() {
                s.momentum_before = p;
            }
        }
    }

    /// The soil's contact impulses on each track over the last step, N s: normal (exact, the
    /// solver's total) and friction (Rapier frame), the friction measured by momentum.
    ///
    /// Rapier's twist friction does not write its total friction impulse back; the last
    /// substep's (`warmstart_tangent_world`) times the substeps is what it keeps, and on soil,
    /// where the contacts slide and their coefficient changes every step, that read 2.4x the
    /// vehicle's change of momentum on snow at steady speed (issue 38.4). The vehicle's
    /// momentum change over the step less gravity, the user forces (the drawbar) and the exact
    /// normal impulses is the exact sum of the friction impulses on it; the difference to the
    /// summed estimates is shared among the contacts by their normal impulse (the split among
    /// tracks keeps the estimate's).
    fn soil_contact_impulses(&self, state: &SoilState, n: usize) -> Vec<(f64, Vector)> {
        let substeps = self.world.integration_parameters.num_solver_iterations as f32;
        let mut per_track = vec![(0.0f64, Vector::ZERO); n];
        // Every contact of the vehicle with something else: its normal impulse and estimated
        // friction impulse.
        let (mut all_normal, mut all_estimate) = (0.0f64, Vector::ZERO);
        for pair in self.world.narrow_phase.contact_pairs() {
            let (p1, p2) = (
                state.parts.get(&pair.collider1),
                state.parts.get(&pair.collider2),
            );
            let (part, s, other) = match (p1, p2) {
                (Some(p), None) => (p, 1.0f32, pair.collider2),
                (None, Some(p)) => (p, -1.0, pair.collider1),
                _ => continue,
            };
            let soil = crate::terrain::tagged_soil(self.world.colliders[other].user_data).is_some();
            for m in pair.solver_manifolds() {
                let normal: f32 = m.points.iter().map(|p| p.data.impulse).sum();
                // Impulse on the part: the manifold's normal points from collider 1 to 2.
                let nv = -m.data.normal * normal * s;
                let fv = m.points.first().map_or(Vector::ZERO, |p| {
                    p.data.warmstart_tangent_world * substeps * s
                });
                all_normal += normal as f64;
                all_estimate += nv + fv;
                if let (true, Some(t)) = (soil, part.track) {
                    per_track[t].0 += normal as f64;
                    per_track[t].1 += fv;
                }
            }
        }
        // The exact sum of the external contact impulses.
        let dt = self.dt as f32;
        let mut external = self.vehicle_momentum() - state.momentum_before;
        for h in self.vehicle_bodies() {
            let b = &self.world.bodies[h];
            external -= (self.world.gravity * b.mass() * b.gravity_scale() + b.user_force()) * dt;
        }
        let missing = external - all_estimate;
        if all_normal > 0.0 {
            for t in per_track.iter_mut() {
                t.1 += missing * (t.0 / all_normal) as f32;
            }
        }
        per_track
    }

    /// [`Self::soil_after_step`] with the state taken out.
    fn soil_update(&mut self, state: &mut SoilState) {
        // The step's loads; the hook's next ones go into last step's (emptied) buffer.
        let mut loads = std::mem::take(&mut state.buffers.loads);
        match state.pending.get_mut() {
            Ok(p) => std::mem::swap(p, &mut loads),
            Err(_) => return,
        }
        let step = self.steps.min(u32::MAX as u64 - 1) as u32 + 1;
        let forward = self.world.bodies[self.robots[0].body].rotation() * Vector::X;
        let n = state.tracks.len();
        let mut figures = vec![TrackSoil::default(); n];
        let mut weighted = vec![0.0f64; n];
        let mut weight = vec![0.0f64; n];
        let mut span = vec![(f64::MAX, f64::MIN, 0.0f64); n];
        let mut limits = vec![(0.0f64, 0.0f64); n];
        let mut work = 0.0f64;
        // Each footprint's raw soil force this step, its patches' area, soil and Bekker's b.
        let mut raw = std::mem::take(&mut state.buffers.raw);
        raw.clear();
        // A part with several manifolds against one surface (a compound shape) loads its patch
        // once.
        let mut seen = std::mem::take(&mut state.buffers.seen);
        seen.clear();
        let impulses = self.soil_contact_impulses(state, n);
        for l in &loads {
            if !seen.insert(l.part) {
                continue;
            }
            let c = self.world.colliders[l.part].position().translation;
            let slip = self.load_slip(l, c);
            let normal = self.load_normal(l);
            let e = raw.entry(l.footprint).or_insert((0.0, 0.0, l.soil, l.b));
            e.0 += normal;
            e.1 += l.patch.area();
            let loaded = l.force > 0.0 || normal > 0.0;
            if loaded {
                let at = Pressing {
                    step,
                    time: self.time as f32,
                    dt: self.dt,
                    origin: self.origin,
                };
                work += state.press(l, slip, at);
            }
            let Some(t) = l.track else { continue };
            let f = &mut figures[t];
            limits[t].0 += l.limit;
            limits[t].1 += l.force;
            weight[t] += l.force;
            weighted[t] += l.force * l.z;
            if loaded {
                f.max_sinkage_m = f.max_sinkage_m.max(l.z);
                f.contact_area_m2 += l.patch.area();
                let x = c.dot(forward) as f64;
                let sp = &mut span[t];
                *sp = (sp.0.min(x), sp.1.max(x), sp.2.max(2.0 * l.patch.half_len));
            }
        }
        for (f, (normal, friction)) in figures.iter_mut().zip(&impulses) {
            f.normal_n = normal / self.dt;
            f.thrust_n = friction.dot(forward) as f64 / self.dt;
        }
        state.filter_footprints(&raw, self.dt);
        loads.clear();
        state.buffers.loads = loads;
        state.buffers.raw = raw;
        state.buffers.seen = seen;
        for (((f, w), sp), total) in figures.iter_mut().zip(&weighted).zip(&span).zip(&weight) {
            if *total > 0.0 {
                f.sinkage_m = w / total;
            }
            if sp.1 >= sp.0 {
                f.contact_length_m = sp.1 - sp.0 + sp.2;
            }
        }
        self.give_back_compaction(work, &mut figures);
        self.update_anchors(state, &figures);
        state.tracks = figures;
        state.track_mu = limits
            .iter()
            .map(|&(lim, force)| (force > 1e-3).then(|| ((lim / force) as f32).min(MU_CAP)))
            .collect();
    }

    /// Anchors each parked track on soil (its belt held, its parent nearly still, loaded) where
    /// its parent stands, keeping an anchor while it stays parked; releases the others.
    fn update_anchors(&self, state: &mut SoilState, figures: &[TrackSoil]) {
        for (t, f) in figures.iter().enumerate() {
            let parent = self.track_parent(t);
            let b = &self.world.bodies[parent];
            let v = b.linvel();
            let parked = self.robots[0].tracks[t].holds_belt()
                && f.normal_n > 0.0
                && (v.x.hypot(v.y) as f64) < ANCHOR_SPEED_MPS
                && (b.angvel().length() as f64) < ANCHOR_TURN_RADPS;
            let a = &mut state.anchors[t];
            *a = match *a {
                Some(a) if parked && a.parent == parent && a.origin == self.origin => Some(a),
                _ if parked => Some(Anchor {
                    parent,
                    pose: *b.position(),
                    origin: self.origin,
                }),
                _ => None,
            };
        }
    }

    /// Compaction: the work `work` J of pressing soil deeper this step, taken from the
    /// chassis's horizontal motion as an impulse (none when that would take more than half its
    /// momentum: settling, not driving); its force is
    /// shared among the tracks by their load in `figures`.
    fn give_back_compaction(&mut self, work: f64, figures: &mut [TrackSoil]) {
        let b = &mut self.world.bodies[self.robots[0].body];
        let vh = Vector::new(b.linvel().x, b.linvel().y, 0.0);
        let speed = vh.length() as f64;
        if work <= 0.0 || speed <= COMPACTION_MIN_SPEED_MPS {
            return;
        }
        let momentum = b.mass() as f64 * speed;
        let j = work / speed;
        // Work that would take more than half the chassis's momentum was not done by its
        // horizontal motion: the soil settling under a robot at rest (or starting), which its
        // descent pays (the solver's normal contacts). Since every deepening of a cell counts
        // (not only the first press), giving it back clamped to half the momentum read as a
        // 2 N compaction resistance on a parked robot still settling.
        if j > 0.5 * momentum {
            return;
        }
        b.apply_impulse(-vh / speed as f32 * j as f32, true);
        let force = j / self.dt;
        let total: f64 = figures.iter().map(|f| f.normal_n).sum();
        for f in figures.iter_mut() {
            if total > 0.0 {
                f.compaction_n = force * f.normal_n / total;
            }
        }
    }

    /// The soil's figures for every track over the last step (empty without soil).
    pub fn track_soil(&self) -> Vec<TrackSoil> {
        self.soil
            .as_ref()
            .map(|s| s.track_soil().to_vec())
            .unwrap_or_default()
    }

    /// What the rut grid holds (None without soil).
    pub fn rut_grid_stats(&self) -> Option<RutGridStats> {
        self.soil.as_ref().map(|s| s.grid().stats())
    }

    /// Every loaded soil cell (see [`RutCell`]); sorted by soil, then tile, then y, then x.
    pub fn ruts(&self) -> Vec<RutCell> {
        let Some(s) = self.soil.as_ref() else {
            return Vec::new();
        };
        s.grid()
            .loaded_cells()
            .into_iter()
            .map(|(soil, ix, iy, c)| self.rut_cell(s, soil, ix, iy, c))
            .collect()
    }

    /// At most `max` of the cells deepened from sequence number `seq` on (those still held:
    /// the newest 65,536), and the sequence number to ask from next time; for a live view.
    pub fn ruts_since(&self, seq: u64, max: usize) -> (Vec<RutCell>, u64) {
        let Some(s) = self.soil.as_ref() else {
            return (Vec::new(), seq);
        };
        // Sequence numbers increase along the queue.
        let start = s.recent.partition_point(|r| r.0 < seq);
        let taken: Vec<_> = s.recent.iter().skip(start).take(max).copied().collect();
        let next = match s.recent.get(start + taken.len()) {
            Some(r) => r.0,
            None => s.seq,
        };
        let cells = taken
            .into_iter()
            .filter_map(|(_, soil, ix, iy)| {
                let c = s.grid().reader(soil).cell(ix, iy).copied()?;
                Some(self.rut_cell(s, soil, ix, iy, c))
            })
            .collect();
        (cells, next)
    }

    fn rut_cell(
        &self,
        s: &SoilState,
        soil: usize,
        ix: i64,
        iy: i64,
        c: super::rut_grid::Cell,
    ) -> RutCell {
        let m = &s.soils()[soil];
        let (x, y) = ((ix as f64 + 0.5) * m.cell, (iy as f64 + 0.5) * m.cell);
        RutCell {
            soil,
            x_m: x,
            y_m: y,
            surface_z_m: self.scenario.terrain.height_at(x, y).unwrap_or(0.0),
            cell_m: m.cell,
            depth_m: c.z_max as f64,
            t_s: c.t_first as f64,
        }
    }
}

/// A loaded soil cell, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RutCell {
    /// Index of the soil.
    pub soil: usize,
    /// Cell centre x, m.
    pub x_m: f64,
    /// Cell centre y, m.
    pub y_m: f64,
    /// Height of the undisturbed surface there, m (the terrain's top).
    pub surface_z_m: f64,
    /// Cell side, m.
    pub cell_m: f64,
    /// Largest sinkage the cell was pressed to (the rut's depth; the elastic rebound,
    /// `p / K_e`, is below a tenth of a millimetre for the presets), m.
    pub depth_m: f64,
    /// Time the cell was first loaded, s.
    pub t_s: f64,
}
