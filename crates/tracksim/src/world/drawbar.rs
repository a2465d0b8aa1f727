//! The drawbar at run time (`[drawbar]`, issue 14.5): before every step the pull is computed
//! from the hitch's position and applied to the chassis at the hitch as a horizontal force
//! backwards along the start heading (Rapier's user force, reset and set again each step).

use crate::model::Drawbar;
use glam::DVec3;

/// A drawbar's state: where the hitch started (world frame) and the pull of the last step.
#[derive(Clone, Debug)]
pub(crate) struct DrawbarState {
    pub(crate) model: Drawbar,
    /// The hitch point at the start, world frame, m.
    pub(super) anchor: DVec3,
    /// The start heading (unit, horizontal); the pull acts along its opposite.
    pub(super) heading: DVec3,
    /// The pull applied in the last step, N.
    pub(crate) pull: f64,
}
