//! `[terrain.ground]`: checking the flat ground plane. Its compiled form is the pair
//! (surface height m, friction) in [`super::TerrainModel::ground`]; `insert.rs` turns it into
//! a half-space or a ground tile.

use crate::check::Checker;
use crate::spec::GroundSpec;

/// Checks `[terrain.ground]` and returns (surface height m, friction).
pub(super) fn compile(c: &mut Checker, g: &GroundSpec) -> (f64, f64) {
    c.non_negative("terrain.ground.friction", g.friction, "");
    c.finite("terrain.ground.z_m", &[g.z_m]);
    (g.z_m, g.friction)
}
