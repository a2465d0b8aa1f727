//! One robot of the world ([`Robot`]): its bodies, tracks, flippers, odometry, drawbar and
//! load window, and its own scenario (the world with it as its one robot). Several robots share
//! one Rapier world; each gets a collision-group bit of its own ([`RobotCollision`]) so that
//! robots touch each other and never themselves, and its sensors see the other robots.

use super::drawbar::DrawbarState;
use super::track_loads::LoadWindow;
use super::{Flipper, Odometry};
use crate::model::{MAX_ROBOTS, Scenario};
use crate::tracks::{Track, VEHICLE_GROUP, WORLD_GROUP};
use rapier3d::prelude::*;
use std::sync::Arc;

/// A robot's running parts.
pub(crate) struct Robot {
    /// Its name (`[[vehicles]]`'s `name`; `model::DEFAULT_ROBOT_NAME` in a one-robot file).
    pub(crate) name: String,
    /// Its own scenario ([`Scenario::robot_view`]).
    pub(crate) view: Arc<Scenario>,
    pub(crate) body: RigidBodyHandle,
    pub(crate) tracks: Vec<Box<dyn Track>>,
    /// Index of its first track in the world's track tags (`tracks::track_tag`).
    pub(crate) first_track: usize,
    pub(crate) flippers: Vec<Flipper>,
    pub(crate) track_names: Vec<String>,
    pub(crate) flipper_names: Vec<String>,
    /// Some track has a drive motor (`[tracks.motor]`).
    pub(crate) has_motors: bool,
    /// Dead reckoning from the measured belt speeds.
    pub(crate) odometry: Odometry,
    /// The drawbar (`[drawbar]`), if any.
    pub(crate) drawbar: Option<DrawbarState>,
    /// The per-step track loads of the last output interval.
    pub(crate) load_window: LoadWindow,
    /// The robot's linear momentum before the last step, kg m/s (Rapier frame;
    /// `contact_balance.rs`).
    pub(crate) momentum_before: Vector,
    /// The faults in force (issue 43).
    pub(crate) faults: super::fault_state::FaultState,
}

impl Robot {
    /// Every body of the robot: chassis, flippers, then each track's bodies.
    pub(crate) fn bodies(&self) -> Vec<RigidBodyHandle> {
        std::iter::once(self.body)
            .chain(self.flippers.iter().map(|f| f.body))
            .chain(self.tracks.iter().flat_map(|t| t.bodies()))
            .collect()
    }
}

/// The collision groups that keep robots apart from themselves and in touch with each other.
#[derive(Clone, Copy, Debug)]
pub struct RobotCollision;

impl RobotCollision {
    /// The collision-group bit of robot `k` (< [`MAX_ROBOTS`]): groups 17 to 32, above the
    /// world's and the vehicle parts' groups.
    pub fn group(k: usize) -> Group {
        assert!(k < MAX_ROBOTS, "robot {k}: at most {MAX_ROBOTS}");
        Group::from_bits_truncate(1 << (16 + k))
    }

    /// Every robot's bit.
    pub fn all() -> Group {
        Group::from_bits_truncate(0xffff_0000)
    }

    /// What robot `k`'s sensors see: every collider but the robot's own (terrain, conveyors,
    /// loose boxes and the other robots).
    pub fn sensor_filter(k: usize) -> InteractionGroups {
        InteractionGroups::new(
            Group::ALL,
            Group::ALL
                .difference(VEHICLE_GROUP)
                .difference(Self::all())
                .union(Self::all().difference(Self::group(k))),
            InteractionTestMode::And,
        )
    }

    /// Gives robot `k`'s colliders its bit: each is a member of it, and each that sees the
    /// terrain sees the other robots too (the line-tip grousers' hulls and tips, which see one
    /// kind of terrain only, do not). In a one-robot world nothing new touches.
    pub(crate) fn apply(world: &mut PhysicsWorld, k: usize, bodies: &[RigidBodyHandle]) {
        let own = Self::group(k);
        let others = Self::all().difference(own);
        for &b in bodies {
            for &c in world.bodies[b].colliders().to_vec().iter() {
                let col = &mut world.colliders[c];
                let g = col.collision_groups();
                let filter = if g.filter.contains(WORLD_GROUP) {
                    g.filter.difference(own).union(others)
                } else {
                    g.filter.difference(Self::all())
                };
                col.set_collision_groups(InteractionGroups::new(
                    g.memberships.union(own),
                    filter,
                    g.test_mode,
                ));
            }
        }
    }
}
