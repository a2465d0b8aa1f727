//! `[[terrain.gaps]]`: ASTM E2801-style gaps, two box platforms with a gap between them.

use super::TerrainModel;
use super::checks::check_place;
use super::frame::Frame;
use crate::check::Checker;
use crate::spec::GapSpec;
use glam::DVec3;

/// Checks one gap (key `k`) and adds its two platforms to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &GapSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.gap_width_m"), s.gap_width_m, "m");
    c.positive(&format!("{k}.height_m"), s.height_m, "m");
    c.positive(&format!("{k}.platform_length_m"), s.platform_length_m, "m");
    c.positive(&format!("{k}.width_m"), s.width_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    if c.issues.len() == n {
        let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
        let (l, g, hw) = (s.platform_length_m, s.gap_width_m, 0.5 * s.width_m);
        t.boxes.push(fr.aabb(
            DVec3::new(-l, -hw, 0.0),
            DVec3::new(0.0, hw, s.height_m),
            s.friction,
        ));
        t.boxes.push(fr.aabb(
            DVec3::new(g, -hw, 0.0),
            DVec3::new(g + l, hw, s.height_m),
            s.friction,
        ));
    }
}
