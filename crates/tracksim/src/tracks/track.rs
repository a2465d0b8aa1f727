//! The one interface every track method implements (Chrono::Vehicle's `ChTrackAssembly`): the
//! world builds tracks through [`crate::tracks::build_track`] and then only talks to this trait.

use rapier3d::prelude::*;

/// What a track method needs to build one track.
pub struct BuildContext<'a> {
    /// The world to insert bodies, colliders and joints into.
    pub world: &'a mut PhysicsWorld,
    /// The body the track runs around (chassis or flipper arm), already in the world.
    pub parent: RigidBodyHandle,
    /// The track's index in the vehicle (used to tag colliders whose contacts it modifies).
    pub index: usize,
    /// Collision groups of the vehicle's colliders.
    pub groups: InteractionGroups,
    /// Smallest mass of any link or wheel body, kg (`simulation.min_link_mass_kg`).
    pub min_link_mass: f64,
}

/// Which collider of a contact pair belongs to the track, for [`Track::modify_contacts`].
#[derive(Clone, Copy, Debug)]
pub struct TrackContact {
    /// The track's collider.
    pub collider: ColliderHandle,
    /// +1 if the track's collider is the manifold's collider 1 (its normal points outward from
    /// the track), -1 if it is collider 2.
    pub sign: f32,
}

/// Largest distance, m, and angle, rad, seen between a track body's pose after a physics step
/// and where the method puts it (the joint error the solver left).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinkError {
    /// m.
    pub distance: f64,
    /// rad.
    pub angle: f64,
}

/// One track of a vehicle at run time, built by a track method.
pub trait Track: Send + Sync + std::fmt::Debug {
    /// Sets the commanded belt speed, m/s (positive drives forwards).
    fn set_belt_speed(&mut self, world: &mut PhysicsWorld, v: f64);
    /// The commanded belt speed, m/s (under a duty or torque command, the speed it drives
    /// towards: [`crate::model::DriveMotor::command_target`]).
    fn commanded_belt_speed(&self) -> f64;
    /// Sets a duty or torque command (tracks with a drive motor; the model refuses it for the
    /// others, so the default ignores it).
    fn set_motor_command(&mut self, _world: &mut PhysicsWorld, _cmd: crate::model::MotorCommand) {}
    /// Lets the belt's drive go (`true`: no drive force, the belt free-wheels, its speed set
    /// by the ground and the vehicle) or takes it back (`false`: the latest command applies);
    /// an instructor's fault (issue 43). Returns whether the method models it (the model
    /// refuses the fault for the others: `model::models_unpowered`).
    fn set_unpowered(&mut self, _world: &mut PhysicsWorld, _unpowered: bool) -> bool {
        false
    }
    /// Whether the belt is held (commanded to stand still): a speed set-point of 0; a duty or
    /// torque command never holds.
    fn holds_belt(&self) -> bool {
        self.commanded_belt_speed() == 0.0
    }
    /// The largest belt force the drive motor allows this step, N (None without a motor).
    fn belt_force_limit(&self) -> Option<f64> {
        None
    }
    /// Work after each physics step of `dt` s: integrate the belt position, measure the belt
    /// speed, and put the track's bodies where the method wants them (the paper's rollback).
    fn after_step(&mut self, world: &mut PhysicsWorld, dt: f64);
    /// Unwrapped belt position, m.
    fn belt_position(&self) -> f64;
    /// Belt phase, m: the belt position modulo the grouser pitch, in `[-p/2, p/2)` (0 without
    /// grousers).
    fn belt_phase(&self) -> f64;
    /// Belt speed measured after the last step, m/s (relative to the parent).
    fn measured_belt_speed(&self) -> f64;
    /// Every body this track added to the world.
    fn bodies(&self) -> Vec<RigidBodyHandle>;
    /// The grouser colliders among the colliders of [`Track::bodies`] (the others are belt);
    /// used to give grousers and belt their own contact compliance. Default: none.
    fn grouser_colliders(&self) -> Vec<ColliderHandle> {
        Vec::new()
    }
    /// Whether each of [`Track::grouser_colliders`] is one grouser posed on its footprint frame
    /// (x along the track, y across, z out): the soil gives such a collider a patch of one
    /// pitch (`world::soil`). Default: no (the soil then uses a collider's bounding box).
    fn grousers_on_footprints(&self) -> bool {
        false
    }
    /// The largest joint error seen since the start or the last [`Track::reset_link_error`].
    fn link_error(&self) -> LinkError {
        LinkError::default()
    }
    /// Forgets the largest joint error seen so far.
    fn reset_link_error(&mut self) {}
    /// Modifies the solver contacts of a contact pair one of whose colliders this track tagged
    /// with [`crate::tracks::track_tag`] (e.g. a surface velocity). Default: nothing.
    fn modify_contacts(&self, _ctx: &mut ContactModificationContext, _contact: TrackContact) {}
    /// Each link's pose relative to its parent and the pose the method wants it at (equal after
    /// a step up to float rounding). Empty for methods without segment links.
    fn link_relative_poses(&self, _world: &PhysicsWorld) -> Vec<(Pose, Pose)> {
        Vec::new()
    }
}
