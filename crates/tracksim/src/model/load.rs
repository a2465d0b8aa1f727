//! Loading a scenario: the entry points that read a file ([`super::read`]) and compile it
//! ([`super::compile_file`]) through a [`ScenarioTemplate`].

use super::overrides::Overrides;
use super::scenario::Scenario;
use super::template::ScenarioTemplate;
use crate::error::Result;
use std::path::Path;

/// Loads a scenario file and the vehicle file it names (relative to the scenario's folder),
/// reporting every problem with its key path. A file with a `[randomize]` table is sampled
/// with its own `simulation.seed` ([`ScenarioTemplate`] samples other seeds).
pub fn load_scenario(path: &Path) -> Result<Scenario> {
    load_scenario_with(path, &Overrides::default())
}

/// [`load_scenario`] with `overrides` written into the file's keys before it is compiled: an
/// overridden value is checked like the file's own (its problems keyed "KEY (overridden:
/// FLAG)"),
/// and [`super::ScenarioData::overridden`] lists the keys.
pub fn load_scenario_with(path: &Path, overrides: &Overrides) -> Result<Scenario> {
    ScenarioTemplate::load_with(path, overrides)?.file_scenario()
}

/// Loads a scenario file to be compiled for any seed (its `[randomize]` table sampled from
/// it), with every key checked as by [`load_scenario`] ([`ScenarioTemplate::load`]).
pub fn load_template(path: &Path) -> Result<ScenarioTemplate> {
    ScenarioTemplate::load(path)
}
