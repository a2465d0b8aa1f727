//! Input checks shared by the terrain kinds (placement, angles, counts, an empty terrain) and
//! the size limits of generated terrain.

use super::TerrainModel;
use crate::check::Checker;

/// Checks a place-and-yaw quadruple.
pub(super) fn check_place(c: &mut Checker, k: &str, x: f64, y: f64, z: f64, yaw: f64) {
    c.finite(&format!("{k}.x_m"), &[x]);
    c.finite(&format!("{k}.y_m"), &[y]);
    c.finite(&format!("{k}.z_m"), &[z]);
    c.finite(&format!("{k}.yaw_deg"), &[yaw]);
}

/// Checks an angle in degrees: finite, 0 < a < 90.
pub(super) fn check_angle(c: &mut Checker, key: &str, a: f64) {
    if !(a.is_finite() && a > 0.0 && a < 90.0) {
        c.push(
            key,
            format!("must be a finite angle with 0 < angle < 90 degrees, got {a}"),
        );
    }
}

/// Checks a count: 1 <= n <= max.
pub(super) fn check_count(c: &mut Checker, key: &str, n: u32, max: u32) {
    if n == 0 || n > max {
        c.push(
            key,
            format!("must be a whole number from 1 to {max}, got {n}"),
        );
    }
}

/// Largest number of grid vertices a height field may have (a 2000 x 2000 grid).
pub(super) const MAX_GRID_VERTICES: usize = 4_000_000;
/// Largest number of boxes one generator may make.
pub(super) const MAX_GENERATED_BOXES: usize = 100_000;

/// Largest number of boxes and cylinders of a whole terrain (given and generated).
pub const MAX_TERRAIN_SHAPES: usize = 100_000;
/// Largest number of height-field vertices of a whole terrain.
pub const MAX_TERRAIN_VERTICES: usize = 16_000_000;

/// Reports a terrain beyond the limits of the whole: shapes and grid vertices.
pub(super) fn check_total(c: &mut Checker, terrain: &TerrainModel) {
    let shapes = terrain.boxes.len() + terrain.cylinders.len();
    if shapes > MAX_TERRAIN_SHAPES {
        c.push(
            "terrain",
            format!(
                "{shapes} boxes and cylinders in all, more than the limit of \
                 {MAX_TERRAIN_SHAPES}: use fewer or larger ones, or a height field"
            ),
        );
    }
    let vertices: usize = terrain
        .heightfields
        .iter()
        .map(|h| h.rows * h.cols)
        .sum::<usize>()
        + terrain
            .meshes
            .iter()
            .map(|m| m.vertices.len())
            .sum::<usize>();
    if vertices > MAX_TERRAIN_VERTICES {
        c.push(
            "terrain",
            format!(
                "{vertices} height-field and mesh vertices in all, more than the limit of \
                 {MAX_TERRAIN_VERTICES}: downsample them"
            ),
        );
    }
}

/// Reports a terrain with nothing to drive on (only when nothing else is wrong).
pub(super) fn check_not_empty(c: &mut Checker, terrain: &TerrainModel) {
    let empty = terrain.ground.is_none()
        && terrain.boxes.is_empty()
        && terrain.cylinders.is_empty()
        && terrain.heightfields.is_empty()
        && terrain.meshes.is_empty();
    if empty && c.issues.is_empty() {
        c.push(
            "terrain",
            "nothing to drive on: add [terrain.ground] (flat ground), [[terrain.boxes]], \
             [[terrain.staircases]], [[terrain.inclines]], [[terrain.heightfields]], \
             [[terrain.rough]], [[terrain.meshes]] or a test obstacle ([[terrain.stepfields]], \
             [[terrain.pitch_roll_ramps]], [[terrain.hurdles]], [[terrain.gaps]])",
        );
    }
}
