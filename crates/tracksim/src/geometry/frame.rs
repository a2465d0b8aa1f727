//! An orthonormal frame on a track path ([`Frame`]).

use glam::{DQuat, DVec3};

/// An orthonormal frame on a track path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Origin, m.
    pub origin: DVec3,
    /// Unit tangent (direction of belt travel).
    pub tangent: DVec3,
    /// Unit lateral axis (the loop's axis).
    pub lateral: DVec3,
    /// Unit outward normal.
    pub normal: DVec3,
}

impl Frame {
    /// The frame's rotation (columns: tangent, lateral, normal).
    pub fn rotation(&self) -> DQuat {
        DQuat::from_mat3(&glam::DMat3::from_cols(
            self.tangent,
            self.lateral,
            self.normal,
        ))
    }

    /// Maps a point given in this frame's coordinates into the track frame, m.
    pub fn to_track(&self, local: DVec3) -> DVec3 {
        self.origin + self.tangent * local.x + self.lateral * local.y + self.normal * local.z
    }
}
