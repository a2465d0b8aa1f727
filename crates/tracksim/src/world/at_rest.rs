//! When a braked robot counts as at rest (friction then also acts in Rapier's bias pass).

/// Chassis speed below which a braked vehicle counts as at rest, m/s: 50x the creep it had
/// (0.2 mm/s), far below any driving speed.
pub const STICK_SPEED_MPS: f32 = 0.01;
/// Chassis turn rate below which a braked vehicle counts as at rest, rad/s.
pub const STICK_RATE_RAD_S: f32 = 0.01;
/// Distance from its last rest a braked robot must have moved for its contacts to be made
/// afresh when it comes to rest again, m: a stop from driving moves it metres, the noise that
/// carries a standing robot across [`STICK_SPEED_MPS`] microns.
pub const REST_REANCHOR_M: f32 = 5e-4;
