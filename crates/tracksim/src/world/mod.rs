//! The running state (MuJoCo's `mjData` idea): a Rapier world holding one vehicle built from a
//! compiled [`Scenario`] by its track method, advanced by [`Simulation::step`] with the controls
//! the caller sets ([`Simulation::apply`]); nothing is applied behind the caller's back (a
//! scenario file's `[[commands]]` are one source of controls: `crate::run::Timeline`).
//!
//! The stage modules are private: what they make public is re-exported here, and
//! [`Simulation`]'s methods are listed in one place in `docs/API.md`.
//!
//! - `build`: the build stages of [`Simulation::new`];
//! - `compliance`: grousers and belts as springs and dampers (`[tracks.compliance]`);
//! - `contacts`: the contact hook (contact slop for every method, and forwarding of tagged
//!   contacts to the track that owns them);
//! - `drawbar`: the drawbar's pull on the chassis (`[drawbar]`);
//! - `conveyor`: conveyors (tracks on the world) and loose boxes, built and stepped;
//! - `step`: the stages of one step;
//! - `sample`: what is recorded of the state ([`Sample`], [`PoseRpy`]) and contact queries;
//! - `mass`: the vehicle weighs what its file says (floored link masses taken back from
//!   their parents), and the report of every part's mass;
//! - `origin`: the floating origin that keeps the f32 world near the vehicle;
//! - `odometry`: what the robot's encoders report (skid-steer dead reckoning);
//! - `track_loads`: the terrain's force on each track (contacts, normal load, traction);
//! - `soil`: deformable soil in the contact hook (Bekker, Mohr-Coulomb, Janosi), its
//!   after-step memory and the per-track sinkage and thrust; `rut_grid`: the bounded grid of
//!   ruts and shear displacement.

#![warn(clippy::too_many_lines)]

mod build;
mod compliance;
mod contacts;
mod conveyor;
mod drawbar;
mod mass;
mod odometry;
mod origin;
mod robot;
mod rut_grid;
mod sample;
mod soil;
mod step;
mod track_loads;

pub use mass::{MIN_PARENT_MASS_FRACTION, MassReport, PartMass};
pub use odometry::Odometry;
pub use origin::ORIGIN_SHIFT_M;
pub use robot::RobotCollision;
pub use rut_grid::RutGridStats;
pub use sample::{DriveSample, ICR_MIN_RATE_RAD_S, PoseRpy, Sample, slip_ratio};
pub use soil::{RutCell, SHEAR_RESET_S, TrackSoil};
pub use step::{STICK_RATE_RAD_S, STICK_SPEED_MPS};
pub use track_loads::{MAX_LOAD_WINDOW_STEPS, TrackLoad, TrackOwners};

use crate::model::Method;
use crate::model::{Controls, Scenario};
use crate::tracks::LinkError;
use glam::DVec3;
use rapier3d::prelude::*;
use robot::Robot;
use std::sync::Arc;

/// Clearance between the vehicle's lowest point and the ground at start, m.
pub const START_CLEARANCE_M: f64 = 0.001;
/// Linear speed above which a body is declared to have blown up, m/s.
pub const MAX_SPEED_MPS: f32 = 50.0;

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

/// Vehicles on a terrain in a Rapier world, advanced one step at a time: one robot, or several
/// (`[[vehicles]]`, issue 40). The per-robot queries and controls (`sample`, `body_pose`,
/// `set_belt_speed`, `track_loads`, ...) act on the selected robot ([`Simulation::select`],
/// robot 0 until changed); [`Simulation::step`] advances every robot.
pub struct Simulation {
    /// The Rapier world; public for inspection (and for advanced users). Its coordinates are
    /// relative to [`Simulation::origin`] (the floating origin).
    pub world: PhysicsWorld,
    /// World position of the Rapier world's origin, m.
    origin: DVec3,
    /// The compiled scenario it was built from (shared: many simulations can hold one).
    scenario: Arc<Scenario>,
    method: Method,
    /// Uncorrected penetration of vehicle contacts, m (`simulation.contact_slop_m`).
    slop: f32,
    /// `simulation.held_friction_in_bias_pass`: while every belt is held, friction also acts in
    /// Rapier's position-correction pass (the brake holds).
    held_friction_in_bias_pass: bool,
    /// The tracks' contact springs (`[tracks.compliance]`), by compliance tag index (every
    /// robot's).
    springs: Vec<compliance::SolverSpring>,
    /// The flat-ground tile kept under the robots (`terrain::GROUND_TILE_HALF_M`).
    ground_tile: Option<RigidBodyHandle>,
    /// The robots, in file order.
    robots: Vec<Robot>,
    /// The robot the per-robot queries and controls act on.
    focus: usize,
    /// The robots' indices in the order they were built (by start pose): the order every
    /// stage that changes the world visits them, so that Rapier's internal order (its modified
    /// bodies and joints, hence its solver's) never follows the file's order.
    order: Vec<usize>,
    dt: f64,
    time: f64,
    steps: u64,
    seed: u64,
    /// Conveyors and loose boxes.
    conveyors: conveyor::Conveyors,
    /// Deformable soil, when the terrain has some.
    soil: Option<soil::SoilState>,
}

impl Simulation {
    /// Builds the world for a scenario: terrain, then the vehicle at its start pose, belts at
    /// rest and flippers held at their initial angles.
    pub fn new(sc: &Scenario) -> crate::error::Result<Self> {
        Self::from_shared(Arc::new(sc.clone()))
    }

    /// [`Simulation::new`] for a scenario shared with other simulations.
    pub fn from_shared(sc: Arc<Scenario>) -> crate::error::Result<Self> {
        build::build(sc)
    }

    /// Rebuilds the world from the compiled scenario (no file is read again), at time 0 with
    /// belts at rest; `seed` replaces the scenario's seed (reported in summaries; random
    /// terrain pieces keep their own `seed` keys).
    pub fn reset(&mut self, seed: Option<u64>) -> crate::error::Result<()> {
        let mut fresh = build::build(self.scenario.clone())?;
        fresh.seed = seed.unwrap_or(self.seed);
        fresh.focus = self.focus;
        *self = fresh;
        Ok(())
    }

    /// Applies a step's controls: every `Some` belt speed (m/s), flipper target (rad) and
    /// motor duty or torque command.
    pub fn apply(&mut self, c: &Controls) {
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
        self.robots[self.focus].tracks[i].set_motor_command(&mut self.world, cmd);
    }

    /// Body-level command: forward speed m/s and yaw rate rad/s (skid steering, see
    /// [`Controls::twist`]).
    pub fn set_twist(&mut self, forward: f64, yaw_rate: f64) {
        let c = Controls::twist(&self.rb().view.vehicle, forward, yaw_rate);
        self.apply(&c);
    }

    /// Sets the belt speed of track `i`, m/s (positive drives forwards).
    pub fn set_belt_speed(&mut self, i: usize, v: f64) {
        self.robots[self.focus].tracks[i].set_belt_speed(&mut self.world, v);
    }

    /// Sets the target angle of flipper `i`, rad (clamped to the joint's limits, if it has
    /// them).
    pub fn set_flipper_angle(&mut self, i: usize, a: f64) {
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
