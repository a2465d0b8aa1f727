//! Input checks shared by the terrain kinds (placement, angles, counts, an empty terrain) and
//! the size limits of generated terrain.

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
