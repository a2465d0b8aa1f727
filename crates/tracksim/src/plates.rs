//! The multiple-plate track (paper Sec. II-B): a closed chain of thin plates on hinge joints
//! wrapped around sprocket and idler wheels, driven by the sprocket. Slow, deformable reference.

use crate::model::TrackModel;
use rapier3d::prelude::*;

/// A plate-chain track at run time.
#[derive(Debug)]
pub(crate) struct PlateTrack {
    /// Every body this track added (plates and wheels).
    pub bodies: Vec<RigidBodyHandle>,
}

impl PlateTrack {
    /// Sets the belt speed, m/s.
    pub(crate) fn set_speed(&mut self, _world: &mut PhysicsWorld, _v: f64) {}
    /// Called after every physics step.
    pub(crate) fn after_step(&mut self, _world: &mut PhysicsWorld, _dt: f64) {}
    /// Belt speed measured from the chain, m/s.
    pub(crate) fn measured_speed(&self, _world: &PhysicsWorld) -> f64 {
        0.0
    }
}

/// Builds the chain for `track` on `parent`.
pub(crate) fn build_plates(
    _world: &mut PhysicsWorld,
    track: &TrackModel,
    _parent: RigidBodyHandle,
    _groups: InteractionGroups,
    _min_mass: f64,
) -> Result<PlateTrack, String> {
    Err(format!(
        "track {}: the multiple-plate method is not available yet",
        track.name
    ))
}
