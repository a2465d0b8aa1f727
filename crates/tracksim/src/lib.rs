//! # tracksim
//!
//! Real-time simulation of non-deformable continuous tracks with grousers, after Okada, Kojima,
//! Ohno and Tadokoro, "Real-time Simulation of Non-Deformable Continuous Tracks with Explicit
//! Consideration of Friction and Grouser Geometry" (ICRA 2020), on the Rapier physics engine.
//!
//! Layers, from file to running world:
//! - [`spec`]: what the TOML files say (serde, unknown keys rejected);
//! - [`geometry`]: track loops of straight and circular segments, grouser layout (exact);
//! - [`terrain`]: the compiled terrain, its insertion into Rapier and height queries;
//! - [`model`]: the compiled, checked, immutable vehicle and scenario (SI units);
//! - [`sim`]: the running Rapier world and the per-step track update (rollback);
//! - [`run`]: running a scenario to the end and writing its outputs.
//!
//! Units are SI (m, kg, s, rad); frames follow ROS REP 103 (x forward, y left, z up).

pub(crate) mod baselines;
pub mod bench;
pub(crate) mod check;
pub mod error;
pub mod geometry;
pub mod model;
pub(crate) mod plates;
pub mod plot;
pub mod run;
pub mod sim;
pub mod spec;
pub mod terrain;
pub mod validate;

pub use error::{Error, Result, SpecIssue};
pub use model::{Scenario, VehicleModel, load_scenario, load_vehicle};
pub use run::{Outcome, RunOptions, RunResult, Summary, run_scenario, run_scenario_with};
pub use sim::Simulation;
pub use toml;
