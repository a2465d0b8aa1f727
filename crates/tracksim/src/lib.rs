//! # tracksim
//!
//! Real-time simulation of non-deformable continuous tracks with grousers, after Okada, Kojima,
//! Ohno and Tadokoro, "Real-time Simulation of Non-Deformable Continuous Tracks with Explicit
//! Consideration of Friction and Grouser Geometry" (ICRA 2020), on the Rapier physics engine.
//!
//! Layers, each importing only the ones above it in this list (docs/ARCHITECTURE.md):
//! - [`error`], `check` (problem lists with key paths, f64 -> f32 conversions, limits),
//!   [`files`] (bounded reading of regular files, atomic writes), [`spill`] (a run's records
//!   at a bounded memory, the older ones on disk), [`rosmsg`] (ROS 2 messages, CDR and
//!   `ros2msg` schemas): the base;
//! - [`spec`]: what the TOML files say (serde, unknown keys rejected);
//! - [`geometry`]: track loops of straight and circular segments, grouser layout (exact);
//! - [`terrain`]: terrain kinds compiled and checked, file parsers, insertion into Rapier;
//! - [`model`]: the compiled, checked, immutable vehicle and scenario (SI units);
//! - [`tracks`]: the track methods behind one trait, and the one place a [`Method`] becomes an
//!   implementation;
//! - [`world`]: the running state ([`Simulation`]), its build stages, contact handling, one
//!   step, samples;
//! - [`run`]: a scenario run to its end (command timeline, outcome, summary) as a [`RunResult`];
//! - [`output`]: `trajectory.csv`, `summary.json`, plots, `run.mcap`;
//! - [`bundled`]: the bundled vehicles and scenarios, embedded: listed, exported, found by name;
//! - [`cases`]: the named cases that tests, `bench` and `validate` share;
//! - [`compare`]: one scenario run with several track methods;
//! - [`bench`](mod@bench), [`validate`]: the paper's Table II and Table IV;
//! - [`sensor_bench`]: what sensing costs, timed against no sensors in one run;
//! - [`env`]: learning environments (one, and many stepped on threads) over the stepping API;
//! - [`sessions`]: the runs of a folder tabulated (trainee, course, score, date);
//! - [`sweep`]: datasets: many runs of a randomised scenario, sharded, with a manifest;
//! - [`video`]: a finished run rendered to an MP4 (chase or onboard camera, HUD burnt in);
//! - `live`: `drive` and `view`, the 3-D page;
//! - `ros` (feature `ros`): `tracksim ros`, the scenario as a ROS 2 node.
//!
//! Units are SI (m, kg, s, rad); frames follow ROS REP 103 (x forward, y left, z up).

#![warn(clippy::too_many_lines)]

pub mod bench;
pub mod bundled;
pub mod camera_bench;
pub mod cases;
pub(crate) mod check;
pub mod compare;
pub mod ensemble;
pub mod env;
pub mod error;
pub mod files;
pub mod geometry;
pub mod import;
pub mod live;
pub mod model;
pub mod output;
pub mod render;
#[cfg(feature = "ros")]
pub mod ros;
pub mod rosmsg;
pub mod run;
pub mod sensor_bench;
pub mod sensors;
pub mod sessions;
pub mod spec;
pub mod spill;
pub mod sweep;
pub mod team_bench;
pub mod terrain;
pub mod tracks;
pub mod urdf;
pub mod validate;
pub mod video;
pub mod world;

pub use error::{Error, Result, SpecIssue};
pub use model::{
    Controls, Method, Overrides, Scenario, ScenarioTemplate, VehicleModel, compile_scenario,
    load_scenario, load_scenario_with, load_template, load_vehicle,
};
pub use run::{
    Outcome, RunOptions, RunResult, Runner, Scripted, Summary, Timeline, run_scenario,
    run_scenario_with,
};
pub use toml;
pub use world::Simulation;
