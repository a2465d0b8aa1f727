//! A local frame on the floor (origin and yaw) in which the generated obstacles (staircases,
//! inclines, stepfields, ramps, hurdles, gaps) are laid out: local x is the direction of
//! travel, local y to its left, z up.

use super::BoxModel;
use crate::render::Rgb;
use glam::{DQuat, DVec3};

/// A local frame on the floor: origin and yaw.
pub(super) struct Frame {
    /// Origin (on the floor), m.
    origin: DVec3,
    /// Rotation about z from the world x axis, rad.
    pub(super) yaw: f64,
}

impl Frame {
    /// The frame at (x, y, z) m turned by `yaw_deg` degrees about z.
    pub(super) fn new(x: f64, y: f64, z: f64, yaw_deg: f64) -> Self {
        Frame {
            origin: DVec3::new(x, y, z),
            yaw: yaw_deg.to_radians(),
        }
    }
    /// World position of the local point `p`, m.
    pub(super) fn point(&self, p: DVec3) -> DVec3 {
        self.origin + DQuat::from_rotation_z(self.yaw) * p
    }
    /// An axis-aligned box (in this frame) from its min and max corners.
    pub(super) fn aabb(&self, lo: DVec3, hi: DVec3, friction: f64) -> BoxModel {
        BoxModel {
            centre: self.point((lo + hi) * 0.5),
            half: (hi - lo) * 0.5,
            yaw: self.yaw,
            pitch: 0.0,
            friction,
            color: Rgb::default(),
            soil: None,
        }
    }
    /// A sloped plate whose top surface starts at `low` (middle of its lower edge, local) and
    /// rises at `angle` rad along the local horizontal direction `dir_yaw` rad, over the
    /// slope length `ls`; `w` wide, `t` thick.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn plate(
        &self,
        low: DVec3,
        dir_yaw: f64,
        angle: f64,
        ls: f64,
        w: f64,
        t: f64,
        friction: f64,
    ) -> BoxModel {
        let d = DVec3::new(dir_yaw.cos(), dir_yaw.sin(), 0.0);
        let u = d * angle.cos() + DVec3::Z * angle.sin();
        let n = -d * angle.sin() + DVec3::Z * angle.cos();
        BoxModel {
            centre: self.point(low + u * (ls * 0.5) - n * (t * 0.5)),
            half: DVec3::new(ls * 0.5, w * 0.5, t * 0.5),
            yaw: self.yaw + dir_yaw,
            pitch: -angle,
            friction,
            color: Rgb::default(),
            soil: None,
        }
    }
}
