//! A URDF `<origin>` as a transform, and its check.

use glam::{DAffine3, DQuat, DVec3, EulerRot};

/// A URDF `<origin>` as a transform (rpy: roll, pitch, yaw about the fixed x, y, z axes).
pub(super) fn pose(o: &urdf_rs::Pose) -> DAffine3 {
    let [r, p, y] = o.rpy.0;
    DAffine3::from_rotation_translation(
        DQuat::from_euler(EulerRot::ZYX, y, p, r),
        DVec3::from_array(o.xyz.0),
    )
}

/// True when every number of `o` is finite.
pub(super) fn finite_pose(o: &urdf_rs::Pose) -> bool {
    o.xyz.iter().chain(o.rpy.iter()).all(|v| v.is_finite())
}
