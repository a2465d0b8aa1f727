//! The compiled, immutable model (MuJoCo's `mjModel` idea): vehicle and scenario checked and
//! converted to SI units and radians, ready to be instantiated any number of times.
//!
//! - `vehicle.rs`: the compiled vehicle ([`VehicleModel`] and its parts);
//! - `compile_vehicle.rs`: [`compile_vehicle`] (name, body, flippers, track names), with one
//!   track's stages (parents, belt, grousers, path, omitted segments, mirror) in
//!   `compile_track.rs`;
//! - `compliance.rs`: a track's contact compliance ([`Compliance`], `[tracks.compliance]`) and
//!   the rubber formulas giving its stiffness;
//! - `motor.rs`: a track's drive motor ([`DriveMotor`], `[tracks.motor]`);
//! - `drawbar.rs`: a drawbar load on the chassis ([`Drawbar`], `[drawbar]`);
//! - `conveyor.rs`: conveyors (tracks on the world, [`ConveyorModel`]) and loose boxes
//!   ([`LooseBoxModel`]) of `[terrain]`;
//! - `course.rs`: a scenario's `[course]` ([`CourseModel`]: gates, repetitions, penalties);
//! - `expect.rs`: a scenario's `[expect]` table ([`Expectation`]);
//! - `fault.rs`: a command's `fault` table compiled ([`Faults`], [`TrackFault`]): an
//!   instructor's injected faults (issue 43);
//! - `controls.rs`: the inputs of one step ([`Controls`]) and timed [`Command`]s;
//! - `steering.rs`: a twist command as belt speeds, per track or per side ([`Steering`]);
//! - `method.rs`: the track method as data ([`Method`]: names, what it models);
//! - `scenario.rs`: the compiled scenario ([`Scenario`], immutable: it seals its
//!   [`ScenarioData`], built and edited only in `model/`), [`SolverSettings`], [`OutcomeModel`];
//! - `compile_scenario.rs`: [`compile_scenario`] (vehicle overrides, terrain, simulation
//!   settings with the method, commands, outcome);
//! - `read.rs`: reading files, once each, into their specs ([`read_toml`],
//!   [`read_scenario_spec`]);
//! - `compile_file.rs`: a vehicle file compiled ([`load_vehicle`]), a scenario file's spec and
//!   vehicle compiled into a [`Scenario`];
//! - `load.rs`: the entry points ([`load_scenario`], [`load_scenario_with`] with [`Overrides`],
//!   [`load_template`]);
//! - `overrides.rs`: what a caller changes in a file before it is compiled ([`Overrides`]);
//! - `randomize.rs`: the `[randomize]` table checked and sampled from a seed ([`Randomizer`]);
//! - `template.rs`: a scenario file kept to be compiled for any seed ([`ScenarioTemplate`]);
//! - `team.rs`: several robots in one world ([`Team`], [`RobotModel`], [`TeamRule`]);
//!   `robot_view.rs`: a robot as the one robot of its world ([`Scenario::robot_view`]);
//!   `outcome.rs`: a robot's outcome conditions ([`OutcomeModel`]); `compile_team.rs`: a `[[vehicles]]` file compiled robot by robot;
//! - `wheel.rs`: a lugged wheel's rolling circle ([`rolling_radius`]) and its lugs.

#![warn(clippy::too_many_lines)]

mod compile_file;
mod compile_scenario;
mod compile_sensor;
mod compile_team;
mod compile_track;
mod compile_urdf;
mod compile_vehicle;
mod compliance;
mod controls;
mod conveyor;
mod course;
mod design;
mod drawbar;
mod expect;
mod fault;
mod load;
mod method;
mod motor;
mod mounts;
mod outcome;
mod overrides;
mod randomize;
mod read;
mod robot_view;
mod scenario;
mod sensor;
mod steering;
mod team;
mod template;
mod vehicle;
mod wheel;

pub use crate::urdf::{UrdfReport, UrdfRobot};
pub use compile_file::{compile_scenario_text, load_vehicle};
pub use compile_scenario::*;
pub use compile_sensor::{
    MAX_RATE_HZ, MAX_RAYS, MAX_SENSOR_RANGE_M, RESERVED_SENSOR_NAMES, SENSOR_KINDS,
};
pub use compile_team::robot_name_problem;
pub use compile_track::MAX_GROUSERS;
pub use compile_vehicle::*;
pub use compliance::{
    Compliance, ContactSpring, belt_compression_stiffness, lug_compression_stiffness,
    lug_tip_stiffness,
};
pub use controls::*;
pub use conveyor::{ConveyorModel, LooseBoxModel};
pub use course::{
    CourseModel, CourseObstacle, Gate, GateKind, MAX_COURSE_NAME_CHARS, MAX_COURSE_OBSTACLES,
    MAX_GATES, MAX_REPETITIONS, Penalties,
};
pub use design::*;
pub use drawbar::{Drawbar, DrawbarLoad};
pub use expect::{DEFAULT_ENSEMBLE_MEMBERS, EnsembleExpectation, Expectation, Range};
pub(crate) use fault::compile_faults;
pub use fault::{
    Faults, FrictionPatch, MAX_LATENCY_S, MAX_PATCH_FRICTION, TrackFault, models_unpowered,
};
pub use load::{load_scenario, load_scenario_with, load_template};
pub use method::Method;
pub(crate) use motor::compile_motor;
pub use motor::{DriveMotor, ElectricalState, MotorCommand, MotorElectrics};
pub use outcome::OutcomeModel;
pub use overrides::{Overrides, StartOffset, load_commands};
pub use randomize::*;
pub use read::{parse_toml, read_scenario_spec, read_toml};
pub use scenario::*;
pub use sensor::*;
pub use steering::{SIDE_EPSILON_M, Steering, side_of, side_separation};
pub use team::{DEFAULT_ROBOT_NAME, MAX_ROBOT_SPREAD_M, MAX_ROBOTS, RobotModel, Team, TeamRule};
pub use template::*;
pub use vehicle::*;
pub use wheel::rolling_radius;
