//! `Simulation` built, reset, controlled and asked: construction (`new`, `reset`), the controls,
//! and the basic queries (the scenario, time, tracks, flippers, bodies).

use super::Simulation;
use crate::model::Method;
use crate::model::{Controls, Scenario};
use crate::tracks::LinkError;
use rapier3d::prelude::*;
use std::sync::Arc;

impl Simulation {
    /// Builds the world for a scenario: terrain, then the vehicle at its start pose, belts at
    /// rest and flippers held at their initial angles.
    pub fn new(sc: &Scenario) -> crate::error::Result<Self> {
        Self::from_shared(Arc::new(sc.clone()))
    }

    /// [`Simulation::new`] for a scenario shared with other simulations.
    pub fn from_shared(sc: Arc<Scenario>) -> crate::error::Result<Self> {
        super::build::build(sc)
    }

    /// Rebuilds the world from the compiled scenario (no file is read again), at time 0 with
    /// belts at rest; `seed` replaces the scenario's seed (reported in summaries; random
    /// terrain pieces keep their own `seed` keys).
    pub fn reset(&mut self, seed: Option<u64>) -> crate::error::Result<()> {
        let mut fresh = super::build::build(self.scenario.clone())?;
        fresh.seed = seed.unwrap_or(self.seed);
        fresh.focus = self.focus;
        *self = fresh;
        Ok(())
    }

    /// Applies a step's controls: every `Some` belt speed (m/s), flipper target (rad) and
    /// motor duty or torque command.
    pub fn apply(&mut self, c: &Controls) {
        if !c.faults.is_empty() {
            self.apply_faults(&c.faults);
        }
        for (i, v) in c.belt_speed.iter().enumerate() {
            if let Some(v) = v {
                self.set_belt_speed(i, *v);
            }
        }
        for (i, a) in c.flipper_angle.iter().enumerate() {
            if let Some(a) = a {
                self.set_flipper_angle(i, *a);
            }
        }
        for (i, m) in c.motor.iter().enumerate() {
            if let Some(m) = m {
                self.set_motor_command(i, *m);
            }
        }
    }

    /// Sets a duty or torque command on track `i` (a track with a drive motor; others ignore
    /// it). A later belt speed replaces it.
    pub fn set_motor_command(&mut self, i: usize, cmd: crate::model::MotorCommand) {
        let rb = &mut self.robots[self.focus];
        rb.faults.wanted[i] = super::fault_state::BeltCommand::Motor(cmd);
        if rb.faults.track[i] != crate::model::TrackFault::Stopped {
            rb.tracks[i].set_motor_command(&mut self.world, cmd);
        }
    }

    /// Body-level command: forward speed m/s and yaw rate rad/s (skid steering, see
    /// [`Controls::twist`]).
    pub fn set_twist(&mut self, forward: f64, yaw_rate: f64) {
        let c = Controls::twist(&self.rb().view.vehicle, forward, yaw_rate);
        self.apply(&c);
    }

    /// Sets the belt speed of track `i`, m/s (positive drives forwards).
    pub fn set_belt_speed(&mut self, i: usize, v: f64) {
        let rb = &mut self.robots[self.focus];
        rb.faults.wanted[i] = super::fault_state::BeltCommand::Speed(v);
        // A stopped track (a fault) holds its belt at 0 whatever is commanded.
        let v = if rb.faults.track[i] == crate::model::TrackFault::Stopped {
            0.0
        } else {
            v
        };
        rb.tracks[i].set_belt_speed(&mut self.world, v);
    }

    /// Sets the target angle of flipper `i`, rad (clamped to the joint's limits, if it has
    /// them).
    pub fn set_flipper_angle(&mut self, i: usize, a: f64) {
        if self.robots[self.focus].faults.jammed[i] {
            // A jammed flipper (a fault) stays where it is; the target applies once freed.
            self.robots[self.focus].faults.wanted_flipper[i] = a;
            return;
        }
        let fl = &mut self.robots[self.focus].flippers[i];
        let a = match fl.limits {
            Some([lo, hi]) => a.clamp(lo, hi),
            None => a,
        };
        fl.target = a;
        if let Some(j) = self.world.impulse_joints.get_mut(fl.joint, true) {
            j.data
                .set_motor_position(JointAxis::AngX, a as f32, fl.stiffness, fl.damping);
        }
    }

    /// The selected robot's scenario: the compiled scenario, with the selected robot as its one
    /// robot in a world of several ([`Scenario::robot_view`]).
    pub fn scenario(&self) -> &Scenario {
        &self.rb().view
    }

    /// The whole world's compiled scenario (every robot: [`Scenario::team`]).
    pub fn world_scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The track method the vehicle was built with.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The colour of every collider in camera images.
    pub fn appearance(&self) -> &super::Appearance {
        &self.appearance
    }

    /// Seed of this run (the scenario's unless [`Simulation::reset`] gave another).
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Time step, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Track names in output order.
    pub fn track_names(&self) -> &[String] {
        &self.robots[self.focus].track_names
    }

    /// Flipper names in output order.
    pub fn flipper_names(&self) -> &[String] {
        &self.robots[self.focus].flipper_names
    }

    /// Commanded belt speed of track `i`, m/s.
    pub fn commanded_belt_speed(&self, i: usize) -> f64 {
        self.robots[self.focus].tracks[i].commanded_belt_speed()
    }

    /// Target angle of flipper `i`, rad.
    pub fn flipper_target(&self, i: usize) -> f64 {
        self.robots[self.focus].flippers[i].target
    }

    /// Largest distance, m, and angle, rad, seen between a track body's pose after a physics
    /// step and where its method puts it, over all tracks of every robot and steps so far.
    pub fn max_link_error(&self) -> (f64, f64) {
        let e = self
            .robots
            .iter()
            .flat_map(|r| r.tracks.iter())
            .map(|t| t.link_error())
            .fold(LinkError::default(), |a, b| LinkError {
                distance: a.distance.max(b.distance),
                angle: a.angle.max(b.angle),
            });
        (e.distance, e.angle)
    }

    /// Forgets the largest link error seen so far (e.g. after the landing transient).
    pub fn reset_max_link_error(&mut self) {
        for t in self.robots.iter_mut().flat_map(|r| r.tracks.iter_mut()) {
            t.reset_link_error();
        }
    }

    /// Handle of the chassis body.
    pub fn body_handle(&self) -> RigidBodyHandle {
        self.robots[self.focus].body
    }

    /// Unwrapped belt position of track `i`, m.
    pub fn belt_position(&self, i: usize) -> f64 {
        self.robots[self.focus].tracks[i].belt_position()
    }

    /// Belt speed of track `i` as its encoder measures it, m/s.
    pub fn measured_belt_speed(&self, i: usize) -> f64 {
        self.robots[self.focus].tracks[i].measured_belt_speed()
    }

    /// Handle of flipper `i`'s body.
    pub fn flipper_body(&self, i: usize) -> RigidBodyHandle {
        self.robots[self.focus].flippers[i].body
    }

    /// For track `i`: each link's pose relative to its parent and the pose it must have
    /// (`shift(phase)`). After a step both are equal up to float rounding.
    pub fn link_relative_poses(&self, i: usize) -> Vec<(Pose, Pose)> {
        self.robots[self.focus].tracks[i].link_relative_poses(&self.world)
    }

    /// Every body of the selected robot: chassis, flippers, then each track's bodies.
    pub fn vehicle_bodies(&self) -> Vec<RigidBodyHandle> {
        self.rb().bodies()
    }
}
