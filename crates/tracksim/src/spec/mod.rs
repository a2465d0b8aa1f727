//! What the files say: serde structs for vehicle and scenario files (TOML). Unknown keys are
//! rejected. Units are SI unless the key name says otherwise (`angle_deg`).
//!
//! These structs are only a description; [`crate::model`] checks and compiles them. This layer
//! depends on nothing else in the crate.
//!
//! - `vehicle.rs`: vehicle files ([`VehicleSpec`] and its parts);
//! - `scenario.rs`: scenario files ([`ScenarioSpec`] and its parts);
//! - `terrain.rs`: a scenario's `[terrain]` table ([`TerrainSpec`] and its parts);
//! - `randomize.rs`: a scenario's `[randomize]` table ([`RandomParamSpec`]);
//! - `conveyor.rs`: conveyors and loose boxes of `[terrain]` ([`ConveyorSpec`], [`LooseBoxSpec`]).
//! - `course.rs`: a scenario's `[course]` table ([`CourseSpec`]): gates, repetitions, faults.
//! - `expect.rs`: a scenario's `[expect]` table ([`ExpectSpec`]): what a run must show.
//! - `fault.rs`: a command's `fault` table ([`FaultSpec`]): what an instructor injects.
//! - `sensor.rs`: a vehicle's `[[sensors]]` table ([`SensorSpec`]).
//! - `strict.rs`: the strict second pass ([`strict::from_value`]): no table read from an array
//!   by position, no fixed-size array with extra entries.

mod conveyor;
mod course;
mod expect;
mod fault;
mod randomize;
mod scenario;
mod sensor;
pub mod strict;
mod terrain;
mod vehicle;

pub use conveyor::*;
pub use course::*;
pub use expect::*;
pub use fault::*;
pub use randomize::*;
pub use scenario::*;
pub use sensor::*;
pub use terrain::*;
pub use vehicle::*;
