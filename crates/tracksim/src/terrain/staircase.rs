//! `[[terrain.staircases]]`: straight staircases built from boxes, with optional rounded
//! nosings (cylinders).

use super::checks::{check_count, check_place};
use super::frame::Frame;
use super::{CylinderModel, TerrainModel};
use crate::check::Checker;
use crate::render::Rgb;
use crate::spec::StaircaseSpec;
use glam::DVec3;

/// Checks one staircase (key `k`) and adds its steps to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &StaircaseSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.rise_m"), s.rise_m, "m");
    c.positive(&format!("{k}.run_m"), s.run_m, "m");
    c.positive(&format!("{k}.width_m"), s.width_m, "m");
    check_count(c, &format!("{k}.count"), s.count, 10_000);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let landing = s.landing_m.unwrap_or(0.0);
    c.non_negative(&format!("{k}.landing_m"), landing, "m");
    let r = s.nosing_radius_m.unwrap_or(0.0);
    if let Some(r) = s.nosing_radius_m {
        c.positive(&format!("{k}.nosing_radius_m"), r, "m");
        if r > s.rise_m.min(s.run_m) {
            c.push(
                format!("{k}.nosing_radius_m"),
                format!(
                    "must not exceed rise_m ({}) or run_m ({}), got {r}: make it smaller or \
                     leave it out for sharp edges",
                    s.rise_m, s.run_m
                ),
            );
        }
    }
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let hw = 0.5 * s.width_m;
    for step in 1..=s.count {
        let front = (step - 1) as f64 * s.run_m;
        let depth = if step == s.count {
            s.run_m + landing
        } else {
            s.run_m
        };
        let top = step as f64 * s.rise_m;
        let back = front + depth;
        if r > 0.0 {
            t.boxes.push(fr.aabb(
                DVec3::new(front + r, -hw, 0.0),
                DVec3::new(back, hw, top),
                s.friction,
            ));
            if top - r > 1e-9 {
                t.boxes.push(fr.aabb(
                    DVec3::new(front, -hw, 0.0),
                    DVec3::new(front + r, hw, top - r),
                    s.friction,
                ));
            }
            t.cylinders.push(CylinderModel {
                centre: fr.point(DVec3::new(front + r, 0.0, top - r)),
                yaw: fr.yaw,
                half_length: hw,
                radius: r,
                friction: s.friction,
                color: Rgb::default(),
            });
        } else {
            t.boxes.push(fr.aabb(
                DVec3::new(front, -hw, 0.0),
                DVec3::new(back, hw, top),
                s.friction,
            ));
        }
    }
}
