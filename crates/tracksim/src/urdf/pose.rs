//! A URDF `<origin>` as a transform, and its checks (finite; a frame within the f32 engine's
//! reach of the root link).

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

/// Why `frame` (a link's or a collision's, in the chassis frame) is too far from the chassis
/// for the f32 engine: its origin beyond [`crate::check::MAX_LENGTH_M`] (each `<origin>` is
/// within it, their sum along a chain may not be).
pub(super) fn too_far(frame: DAffine3) -> Option<String> {
    let t = frame.translation;
    let max = crate::check::MAX_LENGTH_M;
    (!t.is_finite() || t.abs().max_element() > max).then(|| {
        format!(
            "its frame is at [{}, {}, {}] m from the root link, beyond {max:e} m (the f32 \
             engine's bound); check the <origin>s along the chain and their units",
            crate::check::num(t.x),
            crate::check::num(t.y),
            crate::check::num(t.z)
        )
    })
}
