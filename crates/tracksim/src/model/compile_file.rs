//! Compiling what was read from disk: a vehicle file into its [`VehicleModel`], and a scenario
//! file's spec with its vehicle (a file relative to the scenario's folder, or inline) into a
//! [`Scenario`], problems keyed with the file and its overrides.

use super::compile_scenario::compile_scenario;
use super::compile_vehicle::compile_vehicle_in;
use super::overrides::{OverrideCommands, Overrides};
use super::read::read_toml;
use super::scenario::Scenario;
use super::vehicle::VehicleModel;
use crate::error::{Error, Result, SpecIssue};
use crate::spec::{ScenarioSpec, VehicleSpec};
use std::path::Path;

/// Loads and compiles a vehicle file.
pub fn load_vehicle(path: &Path) -> Result<VehicleModel> {
    let spec: VehicleSpec = read_toml(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    compile_vehicle_in(&spec, dir).map_err(|issues| Error::Invalid {
        path: path.to_path_buf(),
        issues,
    })
}

/// Compiles the parsed scenario file at `path` (without sampling `[randomize]`) with the
/// commands of an override file, if any.
pub(crate) fn compile_file(
    path: &Path,
    spec: &ScenarioSpec,
    vehicle: VehicleModel,
    overrides: &Overrides,
    commands: Option<&OverrideCommands>,
) -> Result<Scenario> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut sc = compile_scenario(spec, vehicle, dir).map_err(|issues| Error::Invalid {
        path: path.to_path_buf(),
        issues: overrides.mark(issues),
    })?;
    if let Some(c) = commands {
        sc.0.commands = c.compile(&sc.vehicle)?;
    }
    sc.0.source = Some(path.to_path_buf());
    sc.0.overridden = overrides.keys();
    Ok(sc)
}

/// Compiles a scenario written as TOML `text` (not a file: `name` stands for it in errors)
/// with `vehicle` in place of its `vehicle.file` and `overrides` written into its keys first
/// (checked like its own); relative paths are taken from the folder `dir`.
pub fn compile_scenario_text(
    name: &str,
    text: &str,
    vehicle: VehicleModel,
    dir: &Path,
    overrides: &Overrides,
) -> Result<Scenario> {
    let parse = |e: &dyn std::fmt::Display| Error::Parse {
        path: name.into(),
        message: e.to_string(),
    };
    if overrides.commands.is_some() {
        return Err(Error::Build(format!(
            "{name}: a commands file overrides a scenario file's commands, not a text's"
        )));
    }
    let spec: ScenarioSpec = if overrides.is_empty() {
        toml::from_str(text).map_err(|e| parse(&e))?
    } else {
        let mut doc: toml::Table = toml::from_str(text).map_err(|e| parse(&e))?;
        overrides.apply(&mut doc);
        crate::spec::strict::from_value(&toml::Value::Table(doc)).map_err(|e| parse(&e))?
    };
    let mut sc = compile_scenario(&spec, vehicle, dir).map_err(|issues| Error::Invalid {
        path: name.into(),
        issues: overrides.mark(issues),
    })?;
    sc.0.overridden = overrides.keys();
    Ok(sc)
}

/// The vehicle of a scenario file: its `vehicle.file` (relative to the scenario's folder) or
/// its `[vehicle.inline]`, compiled.
pub(crate) fn scenario_vehicle(path: &Path, spec: &ScenarioSpec) -> Result<VehicleModel> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let invalid = |issues| Error::Invalid {
        path: path.to_path_buf(),
        issues,
    };
    match (&spec.vehicle.file, &spec.vehicle.inline) {
        (Some(file), None) => {
            let vpath = dir.join(file);
            if !vpath.exists() {
                return Err(invalid(vec![SpecIssue::new(
                    "vehicle.file",
                    format!(
                        "vehicle file {} not found (paths are relative to the scenario file's folder)",
                        vpath.display()
                    ),
                )]));
            }
            if let Err(e) = crate::files::check_regular(&vpath, crate::files::MAX_TOML_BYTES) {
                return Err(invalid(vec![SpecIssue::new("vehicle.file", e.to_string())]));
            }
            load_vehicle(&vpath)
        }
        (None, Some(inline)) => compile_vehicle_in(inline, dir).map_err(|issues| {
            invalid(
                issues
                    .into_iter()
                    .map(|i| SpecIssue::new(format!("vehicle.inline.{}", i.key), i.message))
                    .collect(),
            )
        }),
        _ => Err(invalid(vec![SpecIssue::new(
            "vehicle",
            "give exactly one of `file` (a vehicle file) or `[vehicle.inline]`",
        )])),
    }
}
