//! A flipper arm at run time (`Flipper`).

use glam::DVec3;
use rapier3d::prelude::*;

/// A flipper arm at run time.
#[derive(Debug)]
pub(crate) struct Flipper {
    pub(crate) body: RigidBodyHandle,
    pub(crate) joint: ImpulseJointHandle,
    /// Pivot axis in the body frame.
    pub(crate) axis: DVec3,
    /// Target angle, rad.
    pub(crate) target: f64,
    pub(crate) stiffness: f32,
    pub(crate) damping: f32,
    /// Joint limits [lower, upper], rad: targets are clamped to them.
    pub(crate) limits: Option<[f64; 2]>,
}
