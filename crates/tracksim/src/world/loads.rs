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
        let robot = &self.robots[self.focus];
        // A collider of this robot's chassis or flippers (its tracks' are `track_of`'s).
        let on_robot = |h: ColliderHandle| {
            cs.get(h)
                .and_then(|c| c.parent())
                .is_some_and(|b| b == robot.body || robot.flippers.iter().any(|f| f.body == b))
        };
        let forward = self.world.bodies[robot.body].rotation() * Vector::X;
        let inv_dt = 1.0 / self.dt;
        let substeps = self.world.integration_parameters.num_solver_iterations as f32;
        // Every contact of the robot with anything else, for the exact sum
        // (`contact_balance.rs`): normal impulses and the estimated contact impulses.
        let (mut all_normal, mut estimate) = (0.0f32, Vector::ZERO);
        for p in self.world.narrow_phase.contact_pairs() {
            let (t1, t2) = (track_of(p.collider1), track_of(p.collider2));
            let mine1 = t1.is_some() || on_robot(p.collider1);
            let mine2 = t2.is_some() || on_robot(p.collider2);
            // The sign turning "impulse on collider 1" into the robot's.
            let sign = match (mine1, mine2) {
                (true, false) => 1.0f32,
                (false, true) => -1.0,
                _ => continue,
            };
            // The track whose belt touches the terrain here, if it does.
            let track = match (t1, t2) {
                (Some(t), None) if terrain(p.collider2) => loads.get_mut(t),
                (None, Some(t)) if terrain(p.collider1) => loads.get_mut(t),
                _ => None,
            };
            let mut track = track;
            for m in p.solver_manifolds() {
                let i = manifold_impulse(m, substeps);
                all_normal += i.normal;
                estimate += (i.normal_vec + i.friction) * sign;
                let Some(load) = track.as_deref_mut() else {
                    continue;
                };
                load.contacts += i.contacts;
                load.normal_n += i.normal as f64 * inv_dt;
                let (rn, ft) = (
                    (sign * i.normal_vec).dot(forward) as f64 * inv_dt,
                    (sign * i.friction).dot(forward) as f64 * inv_dt,
                );
                load.reaction_n += rn;
                load.friction_traction_n += ft;
                load.traction_n += rn + ft;
            }
        }
        // What the friction estimates miss of the exact sum, shared by normal impulse.
        if all_normal > 0.0 {
            let missing = self.robot_contact_impulse(self.focus) - estimate;
            let per_newton = (missing / all_normal).dot(forward) as f64;
            for l in loads.iter_mut() {
                let extra = per_newton * l.normal_n;
                l.friction_traction_n += extra;
                l.traction_n += extra;
            }
        }
    }
}
