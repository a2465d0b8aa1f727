//! `[[terrain.inclines]]`: inclined planes, each a thin tilted box.

use super::TerrainModel;
use super::checks::{check_angle, check_place};
use super::frame::Frame;
use crate::check::Checker;
use crate::spec::InclineSpec;
use glam::DVec3;

/// Checks one incline (key `k`) and adds its plate to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &InclineSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    check_angle(c, &format!("{k}.angle_deg"), s.angle_deg);
    c.positive(&format!("{k}.length_m"), s.length_m, "m");
    c.positive(&format!("{k}.width_m"), s.width_m, "m");
    c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let soil = s
        .soil
        .as_ref()
        .and_then(|soil| t.add_soil(c, &format!("{k}.soil"), soil));
    if c.issues.len() == n {
        let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
        let mut plate = fr.plate(
            DVec3::ZERO,
            0.0,
            s.angle_deg.to_radians(),
            s.length_m,
            s.width_m,
            s.thickness_m,
            s.friction,
        );
        plate.soil = soil;
        t.boxes.push(plate);
    }
}
