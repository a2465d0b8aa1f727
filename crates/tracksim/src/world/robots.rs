//! The world's robots on `Simulation`: how many, their names, the selected one, the build order
//! (the check that no two start overlapping is a build stage: `build.rs`).

use super::Simulation;
use super::robot::{Robot, RobotCollision};
use rapier3d::prelude::*;

impl Simulation {
    /// The robot the per-robot queries and controls act on.
    pub(crate) fn rb(&self) -> &Robot {
        &self.robots[self.focus]
    }

    /// Robots in the world.
    pub fn robot_count(&self) -> usize {
        self.robots.len()
    }

    /// The robots' names, in file order.
    pub fn robot_names(&self) -> Vec<String> {
        self.robots.iter().map(|r| r.name.clone()).collect()
    }

    /// Selects robot `k` for the per-robot queries and controls (`sample`, `body_pose`,
    /// `set_belt_speed`, `apply`, `scenario`, ...). Panics if `k` >= [`Simulation::robot_count`].
    pub fn select(&mut self, k: usize) {
        assert!(k < self.robots.len(), "robot {k} of {}", self.robots.len());
        self.focus = k;
    }

    /// The robots' indices in the order they were built (by start pose, whatever the file's
    /// order): a caller that sets several robots' controls at once sets them in this order, so
    /// that Rapier's internal order (its modified joints, hence its solver's) does not follow
    /// the file's.
    pub fn build_order(&self) -> &[usize] {
        &self.order
    }

    /// The selected robot's index.
    pub fn selected(&self) -> usize {
        self.focus
    }

    /// The selected robot's name.
    pub fn robot_name(&self) -> &str {
        &self.rb().name
    }

    /// What the selected robot's sensors see ([`RobotCollision::sensor_filter`]).
    pub fn sensor_filter(&self) -> InteractionGroups {
        RobotCollision::sensor_filter(self.focus)
    }
}
