//! The soil's work after a step (ruts, shear displacement, per-track figures, the compaction
//! impulse) and the soil's queries on `Simulation`.

use super::super::Simulation;
use super::super::rut_grid::RutGridStats;
use super::patch::Load;
use super::report::{RutCell, TrackSoil};
use super::state::{Anchor, Pressing, SoilState};
use super::{ANCHOR_SPEED_MPS, ANCHOR_TURN_RADPS, COMPACTION_MIN_SPEED_MPS, MU_CAP};
use rapier3d::prelude::*;

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
    pub(super) fn track_parent(&self, t: usize) -> RigidBodyHandle {
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
    pub(super) fn load_slip(&self, l: &Load, c: Vector) -> f64 {
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
    pub(super) fn load_normal(&self, l: &Load) -> f64 {
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
    pub(super) fn soil_contact_impulses(&self, state: &SoilState, n: usize) -> Vec<(f64, Vector)> {
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
        // The exact sum of the external contact impulses (`world/contact_balance.rs`).
        let external = self.robot_contact_impulse(self.focus);
        let missing = external - all_estimate;
        if all_normal > 0.0 {
            for t in per_track.iter_mut() {
                t.1 += missing * (t.0 / all_normal) as f32;
            }
        }
        per_track
    }

    /// [`Self::soil_after_step`] with the state taken out.
    pub(super) fn soil_update(&mut self, state: &mut SoilState) {
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
    pub(super) fn update_anchors(&self, state: &mut SoilState, figures: &[TrackSoil]) {
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
    pub(super) fn give_back_compaction(&mut self, work: f64, figures: &mut [TrackSoil]) {
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

    pub(super) fn rut_cell(
        &self,
        s: &SoilState,
        soil: usize,
        ix: i64,
        iy: i64,
        c: super::super::rut_grid::Cell,
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
