//! Conveyors and loose boxes, compiled (paper Fig. 8): a conveyor is a [`TrackModel`] whose
//! parent is the world, at a pose, with a belt speed; its belt is checked by the same stages as
//! a vehicle's track (`compile_track.rs`), so its path and cleats are those of any track.

use super::TrackModel;
use crate::check::{Checker, v3};
use crate::spec::{ConveyorSpec, LooseBoxSpec};
use crate::terrain::BoxModel;
use glam::{DQuat, DVec3};

/// A conveyor fixed in the world.
#[derive(Clone, Debug)]
pub struct ConveyorModel {
    /// The belt, its path in the conveyor's frame (parent: the world at [`Self::rotation`]).
    pub belt: TrackModel,
    /// Origin of the conveyor's frame in the world, m.
    pub centre: DVec3,
    /// Yaw of the conveyor's frame, rad.
    pub yaw: f64,
    /// Belt speed, m/s.
    pub speed: f64,
}

impl ConveyorModel {
    /// Orientation of the conveyor's frame in the world.
    pub fn rotation(&self) -> DQuat {
        DQuat::from_rotation_z(self.yaw)
    }
}

/// A free box.
#[derive(Clone, Debug)]
pub struct LooseBoxModel {
    /// Its solid at the start (centre, half extents, yaw, friction; pitch 0).
    pub solid: BoxModel,
    /// Mass, kg.
    pub mass: f64,
}

/// Checks `[[terrain.conveyors]]` and compiles them; problems go to `c` with their key paths.
pub(super) fn compile_conveyors(c: &mut Checker, specs: &[ConveyorSpec]) -> Vec<ConveyorModel> {
    let mut out = Vec::new();
    for (i, s) in specs.iter().enumerate() {
        let k = format!("terrain.conveyors[{i}]");
        c.finite(&format!("{k}.centre_m"), &s.centre_m);
        c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
        c.finite(&format!("{k}.belt_speed_mps"), &[s.belt_speed_mps]);
        let bk = format!("{k}.belt");
        let b = &s.belt;
        for (key, set) in [
            ("parent", b.parent != "body"),
            ("mirror", b.mirror.is_some()),
            ("mirror_parent", b.mirror_parent.is_some()),
            ("motor", b.motor.is_some()),
            ("compliance", b.compliance.is_some()),
        ] {
            if set {
                c.push(
                    format!("{bk}.{key}"),
                    "does not apply to a conveyor (its belt hangs on the world and runs at belt_speed_mps): remove it",
                );
            }
        }
        // `parent` reported above: checked as "body" so it is not reported twice.
        let b = crate::spec::TrackSpec {
            parent: "body".into(),
            ..b.clone()
        };
        let mut belts = Vec::new();
        super::compile_track::compile_track(
            c,
            &super::mounts::Mounts::of_flippers(std::iter::empty()),
            &bk,
            &b,
            &mut belts,
        );
        if let Some(belt) = belts.into_iter().next() {
            out.push(ConveyorModel {
                belt,
                centre: v3(s.centre_m),
                yaw: s.yaw_deg.to_radians(),
                speed: s.belt_speed_mps,
            });
        }
    }
    out
}

/// Checks `[[terrain.loose_boxes]]` and compiles them.
pub(super) fn compile_loose_boxes(c: &mut Checker, specs: &[LooseBoxSpec]) -> Vec<LooseBoxModel> {
    specs
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let k = format!("terrain.loose_boxes[{i}]");
            c.finite(&format!("{k}.centre_m"), &s.centre_m);
            for (j, v) in s.size_m.iter().enumerate() {
                c.positive(&format!("{k}.size_m[{j}]"), *v, "m");
            }
            c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
            c.positive(&format!("{k}.mass_kg"), s.mass_kg, "kg");
            c.non_negative(&format!("{k}.friction"), s.friction, "");
            LooseBoxModel {
                solid: BoxModel {
                    centre: v3(s.centre_m),
                    half: v3(s.size_m) * 0.5,
                    yaw: s.yaw_deg.to_radians(),
                    pitch: 0.0,
                    friction: s.friction,
                    color: crate::render::palette::LOOSE_BOX,
                    soil: None,
                },
                mass: s.mass_kg,
            }
        })
        .collect()
}
