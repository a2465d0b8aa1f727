//! What each track feels from the terrain (issue 14.2): its contact points, the normal load and
//! the traction along the chassis's forward axis, from the impulses Rapier's solver applied in
//! the last step (divided by the step).
//!
//! Attribution: a contact belongs to a track when its vehicle collider sits on one of the
//! track's bodies (links, wheels, plates) or carries the track's tag (constraint-to-ground belts
//! on the chassis). Normal forces are the points' total impulses over the step. Friction:
//! Rapier's default (simplified) friction model solves one friction impulse per manifold and
//! writes its last substep's value, in world coordinates, to every point of the manifold
//! (`ContactData::warmstart_tangent_world`); it is counted once per manifold, times the number
//! of substeps (`simulation.solver_iterations`): exact in steady state, an estimate during
//! impacts. Checked at rest on 0 and 20 deg against m g cos and m g sin
//! (tests/suite/issue_14_track_outputs.rs).
//!
//! What is reported ([`Simulation::track_loads`], the samples) is the mean over the steps of
//! the last output interval ([`LoadWindow`]), the interval's impulse over its duration, not one
//! step's: a rigid vehicle's contacts share the load from step to step in a way the solver
//! settles anew each step (issue 38: a PackBot driving straight on level ground rocked with a
//! period of 2 steps, roll rate +-0.045 rad/s, its per-step loads alternating 99/43 and
//! 35/90 N), and one step in every ten read that alternation as a steady split of 94/36 N or
//! 34/90 N depending on where it started; the mean over the interval was 64.0/63.5 N, the sum
//! m g to 0.01 %. [`Simulation::track_loads_last_step`] gives the last step's figures.

use super::Simulation;
use crate::tracks::WORLD_GROUP;
use crate::tracks::tagged_track;
use rapier3d::prelude::*;
use std::collections::HashMap;

/// The terrain's force on one track over the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackLoad {
    /// Active solver contact points between the track and the terrain.
    pub contacts: usize,
    /// Sum of the contact normal forces (the load the track carries), N.
    pub normal_n: f64,
    /// The terrain's whole contact force on the track (normal and friction) along the chassis's
    /// forward axis (body x), N: positive pushes the vehicle forwards. The sum of the two below.
    pub traction_n: f64,
    /// The friction part of [`Self::traction_n`], N: the belt's grip on the surfaces it
    /// touches, what drives the vehicle (and brakes it).
    pub friction_traction_n: f64,
    /// The normal part of [`Self::traction_n`], N: the reaction of the surfaces pushing on the
    /// track, forward component (a wall or a step's riser the track is pressed against reads
    /// negative; on a slope the ground's normal force has a part along the chassis's x too).
    pub reaction_n: f64,
}

/// Which track owns each vehicle body ([`Simulation::track_owners`]): fixed for the life of a
/// simulation, so a caller that reads the loads every control period builds it once.
pub type TrackOwners = HashMap<RigidBodyHandle, usize>;

/// Longest window of [`LoadWindow`], steps (an output interval of 1 s at 1 ms).
pub const MAX_LOAD_WINDOW_STEPS: usize = 1000;

/// The per-step track loads of the last output interval (a ring of at most `len` steps), whose
/// mean is what [`Simulation::track_loads`] reports.
#[derive(Clone, Debug, Default)]
pub(crate) struct LoadWindow {
    /// Which track owns each vehicle body (fixed for the life of the simulation).
    owners: TrackOwners,
    /// Steps in the window: the output interval in steps, 1 to [`MAX_LOAD_WINDOW_STEPS`].
    len: usize,
    /// The loads of the last `len` steps (fewer at the start), oldest overwritten first.
    ring: Vec<Vec<TrackLoad>>,
    /// Where the next step goes in `ring`.
    next: usize,
}

impl LoadWindow {
    /// A window of one output interval `interval` s at step `dt` s.
    pub(crate) fn new(owners: TrackOwners, interval: f64, dt: f64) -> Self {
        let steps = (interval / dt).round();
        let len = if steps.is_finite() && steps >= 1.0 {
            (steps as usize).min(MAX_LOAD_WINDOW_STEPS)
        } else {
            1
        };
        LoadWindow {
            owners,
            len,
            ring: Vec::with_capacity(len),
            next: 0,
        }
    }
}

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
                let mut normal = 0.0f32;
                let mut friction = None;
                for sc in &m.data.solver_contacts {
                    let id = (sc.contact_id[0] & !NEW_CONTACT_BIT) as usize;
                    let Some(pt) = m.points.get(id) else { continue };
                    normal += pt.data.impulse;
                    friction.get_or_insert(pt.data.warmstart_tangent_world);
                    load.contacts += 1;
                }
                // Impulses on collider 1: the normal one pushes it against the normal.
                let n = -m.data.normal * normal;
                let t = friction.unwrap_or(Vector::ZERO) * substeps;
                load.normal_n += normal as f64 * inv_dt;
                let (rn, ft) = (
                    (sign * n).dot(forward) as f64 * inv_dt,
                    (sign * t).dot(forward) as f64 * inv_dt,
                );
                load.reaction_n += rn;
                load.friction_traction_n += ft;
                load.traction_n += rn + ft;
            }
        }
    }
}
