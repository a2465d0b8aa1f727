//! The check mode and the count of the cull of speculative contacts on `Simulation`
//! (`speculative_cull.rs`, issue 44).

use super::Simulation;
use super::speculative_cull::CullMark;
use std::sync::atomic::Ordering;

impl Simulation {
    /// Turns the cull's check mode on or off: while on, no manifold is culled, and every step
    /// records those the cull would have dropped ([`Simulation::take_cull_marks`]), so that a
    /// test can read the impulses the solver gave them. For checking the cull, not for runs.
    ///
    /// [`Simulation::take_cull_marks`]: Simulation::take_cull_marks
    pub fn set_cull_check(&mut self, on: bool) {
        self.cull.check = on.then(Default::default);
    }

    /// The manifolds the cull would have dropped since the last call (check mode; empty
    /// otherwise).
    pub fn take_cull_marks(&mut self) -> Vec<CullMark> {
        self.cull
            .check
            .as_mut()
            .and_then(|m| m.get_mut().ok())
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Manifolds culled since the start (`simulation.cull_speculative_contacts`).
    pub fn culled_manifolds(&self) -> u64 {
        self.cull.culled.load(Ordering::Relaxed)
    }
}
