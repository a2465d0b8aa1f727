//! The running state (MuJoCo's `mjData` idea): a Rapier world holding one vehicle built from a
//! compiled [`Scenario`] by its track method, advanced by [`Simulation::step`] with the controls
//! the caller sets ([`Simulation::apply`]); nothing is applied behind the caller's back (a
//! scenario file's `[[commands]]` are one source of controls: `crate::run::Timeline`).
//!
//! The stage modules are private: what they make public is re-exported here, and
//! [`Simulation`]'s methods are listed in one place in `docs/API.md`.
//!
//! Two kinds of files, so that no two import each other: the types of [`Simulation`]'s fields
//! (they import nothing of it) and the `impl Simulation` blocks (never named here).
//!
//! - Types: `appearance` (the colour of every collider in camera images), `flipper` (a
//!   flipper arm), `robot` (one robot's bodies, tracks, flippers,
//!   odometry, drawbar and loads; [`RobotCollision`]), `drawbar` (a drawbar's state), `fault_state` (a robot's faults in force),
//!   `conveyor` (conveyors and loose boxes, built), `compliance` (grousers and belts as springs
//!   and dampers), `odometry` (what the encoders report), `origin` (the floating origin's
//!   shift rule), `sample` ([`Sample`], [`PoseRpy`]), `track_loads` ([`TrackLoad`]), `mass`
//!   ([`MassReport`]), `at_rest` (when a braked robot is at rest), `soil` (deformable soil:
//!   Bekker, Mohr-Coulomb, Janosi; its state, the contact hook's stage and the after-step
//!   update), `rut_grid` (the bounded grid of ruts and shear displacement) and
//!   `friction_patch` (the contact hook's stage of a low-friction patch: issue 43).
//! - `impl Simulation`: `simulation` (construction, controls, basic queries), `build` (the
//!   build stages of [`Simulation::new`] and the overlap check), `robots` (selection),
//!   `step` (the stages of one step), `contacts` (the contact hook: soil, the track's own
//!   contacts, compliance, slop), `sampling` (samples and contact queries), `loads` (the
//!   terrain's force on each track), `floating_origin` (the shift of the f32 world near the
//!   robots), `mass_stage` (floored link masses taken back from their parents; the report),
//!   `drawbar_pull`, `conveyor_queries`, `faults` (a track stopped or unpowered, a flipper
//!   jammed, a low-friction patch on the ground: issue 43), `robot_reset` (one robot put back
//!   at its start while the world goes on: issue 43).

#![warn(clippy::too_many_lines)]

mod appearance;
mod at_rest;
mod build;
mod compliance;
mod contact_balance;
mod contacts;
mod conveyor;
mod conveyor_queries;
mod cull_check;
mod drawbar;
mod drawbar_pull;
mod fault_state;
mod faults;
mod flipper;
mod floating_origin;
mod friction_patch;
mod loads;
mod mass;
mod mass_stage;
mod odometry;
mod origin;
mod robot;
mod robot_reset;
mod robots;
mod rut_grid;
mod sample;
mod sampling;
mod simulation;
mod soil;
mod speculative_cull;
mod step;
mod track_loads;

pub use appearance::Appearance;
pub use at_rest::{STICK_RATE_RAD_S, STICK_SPEED_MPS};
pub(crate) use flipper::Flipper;
pub use friction_patch::PatchChange;
pub use mass::{MIN_PARENT_MASS_FRACTION, MassReport, PartMass};
pub use odometry::Odometry;
pub use origin::ORIGIN_SHIFT_M;
pub use robot::RobotCollision;
pub use rut_grid::RutGridStats;
pub use sample::{
    DriveSample, ICR_MIN_RATE_RAD_S, PoseRpy, SLIP_MIN_SPEED_MPS, Sample, slip_ratio,
};
pub use soil::{RutCell, SHEAR_RESET_S, TrackSoil};
pub use speculative_cull::{CULL_MARGIN_M, CullMark};
pub use track_loads::{MAX_LOAD_WINDOW_STEPS, TrackLoad, TrackOwners};

use crate::model::Method;
use crate::model::Scenario;
use glam::DVec3;
use rapier3d::prelude::*;
use robot::Robot;
use std::sync::Arc;

/// Clearance between the vehicle's lowest point and the ground at start, m.
pub const START_CLEARANCE_M: f64 = 0.001;
/// Linear speed above which a body is declared to have blown up, m/s.
pub const MAX_SPEED_MPS: f32 = 50.0;
/// Angular speed above which a chassis or flipper is declared to have blown up, rad/s
/// (955 rpm). Issue 58: a tethered PackBot near the friction limit of friction 0.9 ground spun
/// up to 447 rad/s and ran on to exit 0. A robot's own drive turns it at 2 v / B (a few rad/s);
/// converting all of a 5 m fall into spin gives a chassis of 0.1 m radius of gyration 31 rad/s.
pub const MAX_ANGULAR_SPEED_RAD_S: f32 = 100.0;

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
    /// Whether every robot was braked at rest in the last step ([`Simulation::step`]): the
    /// step in which they come to rest creates their contacts afresh, so that the brake holds
    /// them where they stopped, not where the contacts began.
    held_at_rest: bool,
    /// Every robot's chassis position in the last step they were all braked at rest (Rapier's
    /// frame), m; empty before the first.
    rest_positions: Vec<rapier3d::math::Vector>,
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
    /// The colour of every collider in camera images.
    appearance: Appearance,
    /// The low-friction patch on the ground (`fault.patch`, issue 43), if one is in force.
    friction_patch: Option<crate::model::FrictionPatch>,
    /// Every change of the patch so far, in order (`Simulation::patch_changes`).
    patch_log: Vec<PatchChange>,
    /// Whether the ground's colliders ask for the contact hook (since the first patch).
    ground_hooked: bool,
    /// `simulation.cull_speculative_contacts`: manifolds with the ground that cannot act in a
    /// step are not solved (`speculative_cull.rs`; off by default), and its check mode.
    cull: speculative_cull::CullState,
    /// The colliders of a robot put back at its start since the last step
    /// (`Simulation::reset_robot`) with their own contact hooks: asked for the hook for the next
    /// step (so that Rapier recycles none of their pairs), given back theirs after it.
    fresh_pairs: Vec<(
        rapier3d::prelude::ColliderHandle,
        rapier3d::prelude::ActiveHooks,
    )>,
}
