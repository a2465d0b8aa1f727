//! Conveyors and loose objects of a scenario's `[terrain]` (paper Fig. 8): a conveyor is a
//! track whose parent is the world (`[[terrain.conveyors]]`, its belt described exactly as a
//! vehicle's track), and loose boxes (`[[terrain.loose_boxes]]`) are free bodies it can carry.

use super::TrackSpec;
use serde::{Deserialize, Serialize};

fn default_friction() -> f64 {
    0.6
}

/// A conveyor fixed in the world, its belt running at a constant speed.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConveyorSpec {
    /// Origin of the conveyor's frame in the world, m: the belt's path (`belt.path`) is given
    /// in this frame (x along the belt's top run, y across, z up, rotated by `yaw_deg`).
    pub centre_m: [f64; 3],
    /// Rotation of the conveyor's frame about the world z axis, degrees.
    #[serde(default)]
    pub yaw_deg: f64,
    /// Belt speed, m/s (positive: the top run of a loop that turns about +y moves towards +x,
    /// i.e. the lower run moves towards -x, as a vehicle's track).
    pub belt_speed_mps: f64,
    /// The belt: name, width, mass, friction, path and cleats (`[grousers]`), with the keys of
    /// a vehicle's `[[tracks]]` (`parent`, `mirror`, `motor` and `compliance` do not apply).
    pub belt: TrackSpec,
}

/// A free box (a parcel) lying in the world.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LooseBoxSpec {
    /// Centre at the start, m.
    pub centre_m: [f64; 3],
    /// Full sizes along x, y, z, m.
    pub size_m: [f64; 3],
    /// Yaw at the start, degrees.
    #[serde(default)]
    pub yaw_deg: f64,
    /// Mass, kg (spread evenly: the inertia of a solid box).
    pub mass_kg: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}
