//! `[[terrain.pitch_roll_ramps]]`: ASTM E2826/E2827-style fields of pitch or roll ramps, each
//! panel a thin sloped plate.

use super::TerrainModel;
use super::checks::{check_angle, check_count, check_place};
use super::frame::Frame;
use crate::check::Checker;
use crate::spec::{PitchRollRampSpec, RampOrientation};
use glam::DVec3;

/// Checks one ramp field (key `k`) and adds its panels to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &PitchRollRampSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    check_angle(c, &format!("{k}.angle_deg"), s.angle_deg);
    c.positive(&format!("{k}.panel_m"), s.panel_m, "m");
    check_count(c, &format!("{k}.count"), s.count, 1000);
    check_count(c, &format!("{k}.lanes"), s.lanes, 1000);
    c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let a = s.angle_deg.to_radians();
    let p = s.panel_m;
    let ls = p / a.cos();
    let half_w = 0.5 * p * s.lanes as f64;
    let len = p * s.count as f64;
    use std::f64::consts::{FRAC_PI_2, PI};
    match s.orientation {
        RampOrientation::Pitch => {
            for i in 0..s.count {
                let (low_x, dir) = if i % 2 == 0 {
                    (i as f64 * p, 0.0)
                } else {
                    ((i + 1) as f64 * p, PI)
                };
                let low = DVec3::new(low_x, 0.0, 0.0);
                t.boxes
                    .push(fr.plate(low, dir, a, ls, 2.0 * half_w, s.thickness_m, s.friction));
            }
        }
        RampOrientation::Roll => {
            for j in 0..s.lanes {
                // Lane j spans y in [half_w - (j + 1) p, half_w - j p].
                let (low_y, dir) = if j % 2 == 0 {
                    (half_w - (j + 1) as f64 * p, FRAC_PI_2)
                } else {
                    (half_w - j as f64 * p, -FRAC_PI_2)
                };
                let low = DVec3::new(0.5 * len, low_y, 0.0);
                t.boxes
                    .push(fr.plate(low, dir, a, ls, len, s.thickness_m, s.friction));
            }
        }
    }
}
