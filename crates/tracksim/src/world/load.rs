//! Loading and compiling scenarios with the track method checked along with every other key
//! (the model layer leaves `simulation.method` to the track layer).

use crate::error::{Result, SpecIssue};
use crate::model::{Scenario, ScenarioTemplate, VehicleModel};
use crate::spec::ScenarioSpec;
use crate::tracks::Method;
use std::path::Path;

/// The problems of the keys the track layer interprets.
fn track_checks(spec: &ScenarioSpec) -> Vec<SpecIssue> {
    Method::parse("simulation.method", &spec.simulation.method)
        .err()
        .into_iter()
        .collect()
}

/// Loads a scenario file and the vehicle file it names (relative to the scenario's folder),
/// reporting every problem with its key path.
pub fn load_scenario(path: &Path) -> Result<Scenario> {
    crate::model::load_scenario_with(path, track_checks)
}

/// Loads a scenario file to be compiled for any seed (its `[randomize]` table sampled from
/// it), with every key checked as by [`load_scenario`].
pub fn load_template(path: &Path) -> Result<ScenarioTemplate> {
    ScenarioTemplate::load(path, track_checks)
}

/// Compiles a scenario whose vehicle is already loaded, reporting every problem.
pub fn compile_scenario(
    spec: &ScenarioSpec,
    vehicle: VehicleModel,
    base_dir: &Path,
) -> std::result::Result<Scenario, Vec<SpecIssue>> {
    crate::model::compile_scenario_with(spec, vehicle, base_dir, track_checks)
}
