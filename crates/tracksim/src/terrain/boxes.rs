//! `[[terrain.boxes]]`: each entry checked and added as a [`BoxModel`].

use super::solids::BoxModel;
use super::terrain_model::TerrainModel;
use crate::check::{Checker, v3};
use crate::render::Rgb;
use crate::spec::BoxSpec;

/// Checks one `[[terrain.boxes]]` entry (key `k`) and adds its box to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, b: &BoxSpec, t: &mut TerrainModel) {
    c.finite(&format!("{k}.centre_m"), &b.centre_m);
    for (j, s) in b.size_m.iter().enumerate() {
        c.positive(&format!("{k}.size_m[{j}]"), *s, "m");
    }
    c.finite(&format!("{k}.yaw_deg"), &[b.yaw_deg, b.pitch_deg]);
    c.non_negative(&format!("{k}.friction"), b.friction, "");
    let soil = b
        .soil
        .as_ref()
        .and_then(|s| t.add_soil(c, &format!("{k}.soil"), s));
    t.boxes.push(BoxModel {
        centre: v3(b.centre_m),
        half: v3(b.size_m) * 0.5,
        yaw: b.yaw_deg.to_radians(),
        pitch: b.pitch_deg.to_radians(),
        friction: b.friction,
        color: Rgb::default(),
        soil,
    });
}
