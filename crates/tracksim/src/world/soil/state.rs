//! The soil state of a simulation (`SoilState`): the rut grid, the parts, the footprints' filtered
//! loads, the anchors of parked tracks; built by `build_soil`, pressed by `SoilState::press`.

use super::super::rut_grid::RutGrid;
use super::patch::{Footprint, Load, Part, origin_cells};
use super::report::TrackSoil;
use super::{RUT_PRESSURE_TIME_S, SHEAR_RESET_S};
use crate::model::TrackModel;
use crate::terrain::SoilModel;
use crate::tracks::Track;
use glam::DVec3;
use rapier3d::prelude::*;
use std::collections::HashMap;
use std::sync::Mutex;

/// The soil state of a simulation.
pub(crate) struct SoilState {
    pub(super) soils: Vec<SoilModel>,
    pub(super) grid: RutGrid,
    pub(super) parts: HashMap<ColliderHandle, Part>,
    pub(super) pending: Mutex<Vec<Load>>,
    /// Each loaded footprint's soil force, low-pass filtered, N, and the area of its
    /// patches, m^2, from the last step. A track is one footprint: its belt does not stretch
    /// (the paper's non-deformable track), so its patches share one pressure, Wong's uniform
    /// pressure (the solver's split of a rigid link's load among its contacts is arbitrary).
    /// Any other part is its own footprint.
    pub(super) bodies: HashMap<Footprint, (f64, f64, f64)>,
    pub(super) tracks: Vec<TrackSoil>,
    /// Each track's friction coefficient for the next step: its patches' mobilised limits over
    /// its load (None off soil).
    pub(super) track_mu: Vec<Option<f32>>,
    /// Steps a cell keeps its shear displacement unloaded.
    pub(super) reset_steps: u32,
    /// Buffers the after-step update reuses (no allocation per step once warmed up).
    pub(super) buffers: Buffers,
    /// The cells deepened lately, with a sequence number (at most [`RECENT_CELLS`]), for the
    /// live view.
    pub(super) recent: std::collections::VecDeque<(u64, usize, i64, i64)>,
    /// Sequence number of the next deepened cell.
    pub(super) seq: u64,
    /// Each parked track's anchor: its parent body, the parent's pose when it was parked
    /// (Rapier frame) and the floating origin then (see [`Simulation::update_anchors`]).
    pub(super) anchors: Vec<Option<Anchor>>,
}

/// Where a parked track's parent stood when it was parked.
#[derive(Clone, Copy, Debug)]
pub(super) struct Anchor {
    pub(super) parent: RigidBodyHandle,
    pub(super) pose: Pose,
    pub(super) origin: DVec3,
}

/// A footprint's raw soil force this step, N, its patches' area, m^2, its soil and Bekker's
/// `b`, m.
pub(super) type RawLoad = (f64, f64, usize, f64);

/// The after-step update's buffers, kept between steps.
#[derive(Default)]
pub(super) struct Buffers {
    pub(super) loads: Vec<Load>,
    pub(super) raw: HashMap<Footprint, RawLoad>,
    pub(super) seen: std::collections::HashSet<ColliderHandle>,
    pub(super) bodies: HashMap<Footprint, (f64, f64, f64)>,
}

/// A cell is reported to the live view again each time its rut reaches a multiple of this, m.
pub(super) const RUT_REPORT_STEP_M: f32 = 5e-4;
/// Deepened cells the live feed can catch up on.
pub(super) const RECENT_CELLS: usize = 65_536;

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
        anchors: vec![None; models.len()],
        buffers: Buffers::default(),
    })
}

/// Thickness along the track of a track's first grouser shape, m.
pub(super) fn grouser_thickness(g: &crate::model::GrouserModel) -> f64 {
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

/// When a load presses its cells: the step's number (from 1), the time s, the step s, and the
/// floating origin.
#[derive(Clone, Copy)]
pub(super) struct Pressing {
    pub(super) step: u32,
    pub(super) time: f32,
    pub(super) dt: f64,
    pub(super) origin: DVec3,
}

impl SoilState {
    /// Presses load `l`'s cells (its part slipping at `slip` m/s over them): each keeps its
    /// largest sinkage and adds the slip to its shear displacement (restarting once unloaded
    /// for [`SHEAR_RESET_S`]); returns the work of compacting the fresh cells, J.
    pub(super) fn press(&mut self, l: &Load, slip: f64, at: Pressing) -> f64 {
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
    pub(super) fn filter_footprints(&mut self, raw: &HashMap<Footprint, RawLoad>, dt: f64) {
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
