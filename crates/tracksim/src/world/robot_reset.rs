//! `impl Simulation`: one robot put back at its start in a world that goes on (issue 43: the
//! instructor's reset of one robot of several; a `[[commands]]` entry's `reset = true`).
//!
//! The world is built again from the compiled scenario (as [`Simulation::reset`] does, no file
//! read) and only the selected robot is taken from it: the build is deterministic and no body
//! or joint is ever removed, so the fresh world's handles of the robot are those of the running
//! one. Each of the robot's bodies (chassis, flippers, every track's links, belts and wheels)
//! is re-placed at its start pose (moved by the whole metres the floating origin has shifted
//! since) with its start velocities (zero) and no user force; each joint of the robot takes
//! its start data (motor targets, limits) and no impulse; and the robot's running parts (its
//! tracks' states: belt phase and speed integrators, odometry, flippers' targets, drawbar,
//! load window, faults) are the fresh world's. The other robots, the terrain, conveyors and
//! loose boxes and the low-friction patch go on as they were.
//!
//! Contacts: Rapier recycles a pair whose relative pose barely moved, its contacts frozen in
//! world space; the pairs of the robot's own parts (relative poses unchanged by the move) would
//! keep their contacts at its old place. A pair with a contact hook is never recycled, so the
//! robot's colliders ask for the hook for the next step only (the hook changes nothing on an
//! untagged pair, `contacts.rs`, but for the cull of speculative contacts where the file turns
//! it on, which is exact per step: `speculative_cull.rs`) and get their own back after it: the robot's contacts are made
//! afresh, the other robots' pairs recycle as without the reset.

use super::Simulation;
use crate::error::{Error, Result};
use rapier3d::prelude::*;

impl Simulation {
    /// Puts the selected robot back at its start (see the module docs): bodies at their start
    /// poses with zero velocities, joints and running parts as built, controls zeroed (belts
    /// commanded 0 m/s, flippers to their initial angles), its faults cleared; the clock and
    /// the other robots go on. Refused on deformable soil (its ruts and per-track state hold the
    /// robot's old place).
    pub fn reset_robot(&mut self) -> Result<()> {
        if self.soil.is_some() {
            return Err(Error::Build(
                "a reset of one robot is not modelled on deformable soil (the soil's ruts and \
                 each track's sinkage hold the robot's old place): restart the run instead"
                    .into(),
            ));
        }
        let k = self.focus;
        let mut fresh = super::build::build(self.scenario.clone())?;
        let bodies = self.robots[k].bodies();
        if bodies != fresh.robots[k].bodies() {
            return Err(Error::Build(format!(
                "robot `{}`: its rebuilt bodies are not the running world's; not reset",
                self.robots[k].name
            )));
        }
        let d = fresh.origin - self.origin;
        let shift = Vector::new(d.x as f32, d.y as f32, d.z as f32);
        for &h in &bodies {
            let src = &fresh.world.bodies[h];
            let mut pose = *src.position();
            pose.translation += shift;
            let (lin, ang) = (src.linvel(), src.angvel());
            let b = &mut self.world.bodies[h];
            b.set_position(pose, true);
            b.set_next_kinematic_position(pose);
            b.set_linvel(lin, true);
            b.set_angvel(ang, true);
            b.reset_forces(true);
            b.reset_torques(true);
        }
        for (j, src) in fresh.world.impulse_joints.iter() {
            if bodies.contains(&src.body1()) || bodies.contains(&src.body2()) {
                let (data, impulses) = (src.data, src.impulses);
                if let Some(mine) = self.world.impulse_joints.get_mut(j, true) {
                    mine.data = data;
                    mine.impulses = impulses;
                }
            }
        }
        std::mem::swap(&mut self.robots[k], &mut fresh.robots[k]);
        for &h in &bodies {
            for &c in self.world.bodies[h].colliders() {
                let col = &mut self.world.colliders[c];
                let own = col.active_hooks();
                self.fresh_pairs.push((c, own));
                col.set_active_hooks(own | ActiveHooks::MODIFY_SOLVER_CONTACTS);
            }
        }
        Ok(())
    }
}
