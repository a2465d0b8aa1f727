//! What each track feels from the terrain (issue 14.2): its contact points, the normal load and
//! the traction along the chassis's forward axis, from the impulses Rapier's solver applied in
//! the last step (divided by the step).
//!
//! Attribution: a contact belongs to a track when its vehicle collider sits on one of the
//! track's bodies (links, wheels, plates) or carries the track's tag (constraint-to-ground belts
//! on the chassis). Normal forces are the points' total impulses over the step. Friction:
//! Rapier's default (simplified) friction model solves one friction impulse per manifold and
//! writes its last substep's value, in world coordinates, to every point of the manifold
//! (`ContactData::warmstart_tangent_world`); it is counted once per manifold, scaled by the
//! step's total normal impulse over the last substep's (exact while sliding, where friction
//! follows the load; issue 58: scaled by the number of substeps, as before, it read 8-10 %
//! above a tether's pull at 8 solver iterations, 2-3 % at 4); an estimate during impacts. Checked at rest on 0 and 20 deg against m g cos and m g sin
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

use rapier3d::prelude::*;
use std::collections::HashMap;

/// The terrain's force on one track over the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
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
    pub(super) owners: TrackOwners,
    /// Steps in the window: the output interval in steps, 1 to [`MAX_LOAD_WINDOW_STEPS`].
    pub(super) len: usize,
    /// The loads of the last `len` steps (fewer at the start), oldest overwritten first.
    pub(super) ring: Vec<Vec<TrackLoad>>,
    /// Where the next step goes in `ring`.
    pub(super) next: usize,
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
