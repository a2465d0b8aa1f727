//! Changes a caller makes to a scenario file before it is compiled ([`Overrides`]: the track
//! method, the duration, the solver iterations, the commands of another file), so that an
//! overridden value is checked like the file's own, with its key, and the compiled scenario
//! records what was overridden ([`super::Scenario::overridden`]).

use super::{Method, VehicleModel, compile_commands};
use crate::error::{Error, Result, SpecIssue};
use crate::spec::CommandSpec;
use std::path::{Path, PathBuf};

/// What to change in a scenario file before compiling it (`None`: the file's value).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Track method (`simulation.method`).
    pub method: Option<Method>,
    /// Simulated duration, s (`simulation.duration_s`).
    pub duration_s: Option<f64>,
    /// Solver iterations (`simulation.solver_iterations`).
    pub solver_iterations: Option<usize>,
    /// A file of `[[commands]]` replacing the scenario's (e.g. the `commands.toml` of a
    /// `tracksim drive` session).
    pub commands: Option<PathBuf>,
}

/// A file holding only `[[commands]]`, as `tracksim drive` records a session (`commands.toml`).
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CommandsFile {
    #[serde(default)]
    commands: Vec<CommandSpec>,
}

/// The commands of an override file, read once and checked against each vehicle.
#[derive(Clone, Debug)]
pub(crate) struct OverrideCommands {
    path: PathBuf,
    specs: Vec<CommandSpec>,
}

impl OverrideCommands {
    /// The commands compiled for `vehicle`; problems name the commands file.
    pub(crate) fn compile(&self, vehicle: &VehicleModel) -> Result<Vec<super::Command>> {
        compile_commands(&self.specs, vehicle).map_err(|issues| Error::Invalid {
            path: self.path.clone(),
            issues,
        })
    }
}

impl Overrides {
    /// No override: the file as it is.
    pub fn is_empty(&self) -> bool {
        *self == Overrides::default()
    }

    /// The keys of the file these overrides replace.
    pub fn keys(&self) -> Vec<String> {
        self.keys_and_flags()
            .into_iter()
            .map(|(k, _)| k.to_string())
            .collect()
    }

    /// Each overridden key with the command-line flag that sets it.
    fn keys_and_flags(&self) -> Vec<(&'static str, &'static str)> {
        [
            (self.method.is_some(), "simulation.method", "--method"),
            (
                self.duration_s.is_some(),
                "simulation.duration_s",
                "--duration",
            ),
            (
                self.solver_iterations.is_some(),
                "simulation.solver_iterations",
                "--solver-iterations",
            ),
            (self.commands.is_some(), "commands", "--commands"),
        ]
        .into_iter()
        .filter(|(set, ..)| *set)
        .map(|(_, k, f)| (k, f))
        .collect()
    }

    /// Writes the overridden values into a scenario file's table `doc` (the commands are
    /// removed: they come from [`Overrides::read_commands`] once the vehicle is known).
    pub(crate) fn apply(&self, doc: &mut toml::Table) {
        let sim = doc
            .entry("simulation")
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let Some(sim) = sim.as_table_mut() {
            if let Some(m) = self.method {
                sim.insert("method".into(), toml::Value::String(m.name()));
            }
            if let Some(d) = self.duration_s {
                sim.insert("duration_s".into(), toml::Value::Float(d));
            }
            if let Some(n) = self.solver_iterations {
                let n = i64::try_from(n).unwrap_or(i64::MAX);
                sim.insert("solver_iterations".into(), toml::Value::Integer(n));
            }
        }
        if self.commands.is_some() {
            doc.remove("commands");
        }
    }

    /// Reads the commands file, if one is given (its problems name it).
    pub(crate) fn read_commands(&self) -> Result<Option<OverrideCommands>> {
        let Some(path) = &self.commands else {
            return Ok(None);
        };
        let f: CommandsFile = super::read::read_toml(path)?;
        Ok(Some(OverrideCommands {
            path: path.clone(),
            specs: f.commands,
        }))
    }

    /// Marks the problems of overridden keys as such (the value is the caller's, not the
    /// file's), naming the command-line flag that sets each.
    pub(crate) fn mark(&self, issues: Vec<SpecIssue>) -> Vec<SpecIssue> {
        let keys = self.keys_and_flags();
        issues
            .into_iter()
            .map(|i| match keys.iter().find(|(k, _)| i.key == *k) {
                Some((k, flag)) => SpecIssue::new(format!("{k} (overridden: {flag})"), i.message),
                None => i,
            })
            .collect()
    }
}

/// Loads a file of `[[commands]]` (the format of a scenario's) for `vehicle`: the commands
/// that replace a scenario's (`tracksim run --commands FILE`).
pub fn load_commands(path: &Path, vehicle: &VehicleModel) -> Result<Vec<super::Command>> {
    let o = Overrides {
        commands: Some(path.to_path_buf()),
        ..Overrides::default()
    };
    match o.read_commands()? {
        Some(c) => c.compile(vehicle),
        None => Ok(Vec::new()),
    }
}
