//! The compiled solids every box-built terrain is made of: [`BoxModel`] (boxes, also generated
//! by staircases, inclines and the test obstacles) and [`CylinderModel`] (stair nosings).

use crate::render::Rgb;
use glam::{DQuat, DVec3};

/// A box obstacle, compiled.
#[derive(Clone, Debug)]
pub struct BoxModel {
    /// Centre, m.
    pub centre: DVec3,
    /// Half extents, m.
    pub half: DVec3,
    /// Yaw, rad.
    pub yaw: f64,
    /// Pitch, rad.
    pub pitch: f64,
    /// Friction coefficient.
    pub friction: f64,
    /// Index of its soil in [`TerrainModel::soils`] (None: rigid).
    pub soil: Option<usize>,
    /// Colour in camera images.
    pub color: Rgb,
}

impl BoxModel {
    /// Orientation.
    pub fn rotation(&self) -> DQuat {
        DQuat::from_rotation_z(self.yaw) * DQuat::from_rotation_y(self.pitch)
    }
}

/// A horizontal cylinder (e.g. a stair nosing), compiled.
#[derive(Clone, Debug)]
pub struct CylinderModel {
    /// Centre, m.
    pub centre: DVec3,
    /// Yaw, rad: the axis is the y axis rotated by this about z.
    pub yaw: f64,
    /// Half length along the axis, m.
    pub half_length: f64,
    /// Radius, m.
    pub radius: f64,
    /// Friction coefficient.
    pub friction: f64,
    /// Colour in camera images.
    pub color: Rgb,
}
