//! `[[terrain.hurdles]]`: ASTM E2802-style hurdles, each one box across the lane.

use super::TerrainModel;
use super::checks::check_place;
use super::frame::Frame;
use crate::check::Checker;
use crate::spec::HurdleSpec;
use glam::DVec3;

/// Checks one hurdle (key `k`) and adds its bar to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &HurdleSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.height_m"), s.height_m, "m");
    c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
    c.positive(&format!("{k}.width_m"), s.width_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    if c.issues.len() == n {
        let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
        t.boxes.push(fr.aabb(
            DVec3::new(0.0, -0.5 * s.width_m, 0.0),
            DVec3::new(s.thickness_m, 0.5 * s.width_m, s.height_m),
            s.friction,
        ));
    }
}
