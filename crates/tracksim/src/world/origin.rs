//! The floating origin: the Rapier world (single precision) is kept near the vehicle, and every
//! output is given in world coordinates in f64 as `origin + local`.
//!
//! Why: Rapier works in f32, whose spacing at 1000 m is 61 um; each step's displacement of a
//! body is rounded to it, which biased a PackBot at 0.3 m/s to 0.305 m/s at 100 m from the
//! origin, 0.244 m/s at 1000 m and a standstill at 3000 m. With the world shifted by whole
//! metres whenever the chassis is more than [`ORIGIN_SHIFT_M`] from the local origin, every body
//! stays within a few metres of it, where the spacing is below 0.5 um, wherever the robot
//! drives (docs/DESIGN.md has the measurements).
//!
//! A shift translates every body (the terrain's fixed bodies too) by the same whole number of
//! metres: for bodies within a factor of two of the shift the f32 subtraction is exact
//! (Sterbenz), contact manifolds and joints are held in body frames, so the physics does not
//! see it, with one exception: Rapier's contact recycling (`contact_recycling`, on by default)
//! keeps a pair whose *relative* pose barely moved with its solver contacts frozen in world
//! space (anchors and normal). A shift moves every body by the same amount, so every resting
//! pair would be recycled with contact points one shift away from the bodies: on a slope, mesh
//! or height field that was a kick of metres per second at the first step after the shift
//! (issue 23.1). The step after a shift therefore runs with recycling off, so every pair's
//! contacts are computed afresh at the new place.

/// Distance (x or y) of the chassis from the local origin beyond which the world is shifted, m.
pub const ORIGIN_SHIFT_M: f64 = 2.0;

/// The shift, m (a whole number), that brings coordinate `v` m back near 0, or 0 if `v` is
/// within [`ORIGIN_SHIFT_M`].
pub(crate) fn shift_for(v: f64) -> f64 {
    if v.abs() > ORIGIN_SHIFT_M {
        v.round()
    } else {
        0.0
    }
}
