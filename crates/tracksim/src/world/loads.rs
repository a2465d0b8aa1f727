//! Per-track contact loads on `Simulation`, from the solver's impulses.

use super::Simulation;
use super::contact_balance::manifold_impulse;
use super::track_loads::{TrackLoad, TrackOwners};
use crate::tracks::WORLD_GROUP;
use crate::tracks::tagged_track;
use rapier3d::prelude::*;

impl Simulation {
    /// The terrain's force on every track: the mean over the steps of the last output interval
    /// (`simulation.output_interval_s`; fewer steps at the start, zero before the first step).
    /// Contacts: the last step's count.
    pub fn track_loads(&self) -> Vec<TrackLoad> {
        let mut loads = vec![TrackLoad::default(); self.robots[self.focus].tracks.len()];
        self.track_loads_mean_into(&mut loads);
        loads
    }

    /// [`Simulation::track_loads`] into `loads` (one per track, in track order), without
    /// allocating: what the learner's observation reads, so it equals the CLI's columns.
    pub fn track_loads_mean_into(&self, loads: &mut [TrackLoad]) {
        for l in loads.iter_mut() {
            *l = TrackLoad::default();
        }
        let w = &self.robots[self.focus].load_window;
        if w.ring.is_empty() {
            return;
        }
        for step in &w.ring {
            for (l, s) in loads.iter_mut().zip(step) {
                l.normal_n += s.normal_n;
                l.traction_n += s.traction_n;
                l.friction_traction_n += s.friction_traction_n;
                l.reaction_n += s.reaction_n;
            }
        }
        let k = w.ring.len() as f64;
        let last = (w.next + w.ring.len() - 1) % w.ring.len();
        for (l, s) in loads.iter_mut().zip(&w.ring[last]) {
            l.normal_n /= k;
            l.traction_n /= k;
            l.friction_traction_n /= k;
            l.reaction_n /= k;
            l.contacts = s.contacts;
        }
    }

    /// The terrain's force on every track over the last step alone (zero before the first
    /// step).
    pub fn track_loads_last_step(&self) -> Vec<TrackLoad> {
        let mut loads = vec![TrackLoad::default(); self.robots[self.focus].tracks.len()];
        self.track_loads_into(&self.robots[self.focus].load_window.owners, &mut loads);
        loads
    }

    /// Adds the last step's loads to the window (after every step).
    pub(crate) fn record_track_loads(&mut self) {
        let n = self.robots[self.focus].tracks.len();
        let mut w = std::mem::take(&mut self.robots[self.focus].load_window);
        if w.ring.len() < w.len {
            w.ring.push(vec![TrackLoad::default(); n]);
        }
        let slot = w.next;
        self.track_loads_into(&w.owners, &mut w.ring[slot]);
        w.next = (slot + 1) % w.len;
        self.robots[self.focus].load_window = w;
    }

    /// The track owning each body of the tracks (links, wheels, plates), by body handle.
    pub fn track_owners(&self) -> TrackOwners {
        self.robots[self.focus]
            .tracks
            .iter()
            .enumerate()
            .flat_map(|(i, t)| t.bodies().into_iter().map(move |b| (b, i)))
            .collect()
    }

    /// The last step's loads ([`Simulation::track_loads_last_step`]) into `loads` (one per
    /// track, in track order) with the owners `owner` of [`Simulation::track_owners`], without
    /// allocating.
    pub fn track_loads_into(&self, owner: &TrackOwners, loads: &mut [TrackLoad]) {
        for l in loads.iter_mut() {
            *l = TrackLoad::default();
        }
        if self.steps() == 0 {
            return;
        }
        let cs = &self.world.colliders;
        // Tags number every robot's tracks one after another; this robot's are its own.
        let (first, n) = (self.rb().first_track, self.rb().tracks.len());
        let own_tag = |u: u128| {
            tagged_track(u)
                .and_then(|g| g.checked_sub(first))
                .filter(|&i| i < n)
        };
        let track_of = |h: ColliderHandle| -> Option<usize> {
            let c = cs.get(h)?;
            own_tag(c.user_data).or_else(|| c.parent().and_then(|b| owner.get(&b).copied()))
        };
        let terrain = |h: ColliderHandle| {
            cs.get(h)
                .is_some_and(|c| c.collision_groups().memberships.contains(WORLD_GROUP))
        };
        let forward = self.world.bodies[self.robots[self.focus].body].rotation() * Vector::X;
        let inv_dt = 1.0 / self.dt;
        let substeps = self.world.integration_parameters.num_solver_iterations as f32;
        // What the friction estimates miss of the robot's exact contact impulse, shared by
        // normal impulse (`contact_balance.rs`).
        let correction = self.friction_correction(self.focus);
        for p in self.world.narrow_phase.contact_pairs() {
            // The track's collider and the sign turning "force on collider 1" into its force.
            let (track, sign) = match (track_of(p.collider1), track_of(p.collider2)) {
                (Some(t), None) if terrain(p.collider2) => (t, 1.0f32),
                (None, Some(t)) if terrain(p.collider1) => (t, -1.0f32),
                _ => continue,
            };
            let Some(load) = loads.get_mut(track) else {
                continue;
            };
            for m in p.solver_manifolds() {
                let i = manifold_impulse(m, substeps);
                load.contacts += i.contacts;
                let t = i.friction * sign + correction * i.normal;
                load.normal_n += i.normal as f64 * inv_dt;
                let (rn, ft) = (
                    (sign * i.normal_vec).dot(forward) as f64 * inv_dt,
                    t.dot(forward) as f64 * inv_dt,
                );
                load.reaction_n += rn;
                load.friction_traction_n += ft;
                load.traction_n += rn + ft;
            }
        }
    }
}
