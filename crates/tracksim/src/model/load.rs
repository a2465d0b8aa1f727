//! Reading files: TOML parsing with the file named in every error, and loading of vehicle and
//! scenario files (a scenario's vehicle file is found relative to the scenario's folder).

use super::overrides::OverrideCommands;
use super::{Overrides, Scenario, ScenarioTemplate, VehicleModel, compile_scenario};
use crate::check::shorten;
use crate::error::{Error, Result, SpecIssue};
use crate::spec::{ScenarioSpec, VehicleSpec};
use std::path::Path;

/// Reads and parses a TOML file into `T`, naming the file in every error: a regular file of
/// at most [`crate::files::MAX_TOML_BYTES`], parsed with line and column in errors, then read
/// again strictly ([`crate::spec::strict`]: no table given as an array, no array too long).
pub fn read_toml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    let text = crate::files::read_text_bounded(path, crate::files::MAX_TOML_BYTES)?;
    parse_toml(path, &text)
}

/// Parses TOML `text` (of the file `path`) into `T` as [`read_toml`] does.
pub fn parse_toml<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<T> {
    let parse = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message: explain(&message),
    };
    let doc: toml::Table = toml::from_str(text).map_err(|e| parse(e.to_string()))?;
    let typed: T = toml::from_str(text).map_err(|e| parse(e.to_string()))?;
    crate::spec::strict::from_value::<T>(&toml::Value::Table(doc)).map_err(|e| parse(e.0))?;
    Ok(typed)
}

/// A parser message for the user: serde's "unknown field `x`, expected one of ..." (and
/// "unknown variant") rewritten with a "did you mean" and the whole list of accepted names,
/// which comes from the code; every other line (the file's text) cut by [`shorten`].
fn explain(message: &str) -> String {
    message
        .lines()
        .map(|l| explain_unknown(l).unwrap_or_else(|| shorten(l)))
        .collect::<Vec<_>>()
        .join("\n")
}

/// serde's message of an unknown key or variant (possibly after a key path and `: `),
/// rewritten; `None` for any other line.
fn explain_unknown(line: &str) -> Option<String> {
    let (at, what, rest) = ["unknown field `", "unknown variant `"]
        .iter()
        .find_map(|p| line.find(p).map(|i| (i, *p, &line[i + p.len()..])))?;
    let (given, expected) = match rest.rfind("`, expected ") {
        Some(i) => (&rest[..i], &rest[i + "`, expected ".len()..]),
        None => (rest.strip_suffix("`, there are no fields")?, ""),
    };
    // The names are between backticks: "one of `a`, `b`", "`a` or `b`", "`a`".
    let names: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    let what = if what.contains("field") {
        "key"
    } else {
        "value"
    };
    Some(format!(
        "{}{}",
        shorten(&line[..at]),
        crate::check::unknown_name(what, given, &names)
    ))
}

/// Reads a scenario file as [`read_toml`] does; a vehicle file (`[body]` or `[[tracks]]`, no
/// `[vehicle]`) is refused with how to use it instead of its first unknown key.
pub fn read_scenario_spec(path: &Path) -> Result<ScenarioSpec> {
    let text = crate::files::read_text_bounded(path, crate::files::MAX_TOML_BYTES)?;
    if let Ok(doc) = toml::from_str::<toml::Table>(&text)
        && !doc.contains_key("vehicle")
        && (doc.contains_key("body") || doc.contains_key("tracks"))
    {
        let name = path
            .file_name()
            .map_or("VEHICLE.toml".into(), |n| n.to_string_lossy());
        return Err(Error::Invalid {
            path: path.to_path_buf(),
            issues: vec![SpecIssue::new(
                "",
                format!(
                    "this is a vehicle file (it has `[body]` or `[[tracks]]` and no \
                     `[vehicle]`), not a scenario; a scenario names it in its `[vehicle]` table, \
                     `file = \"{}\"` (relative to the scenario file's folder): see \
                     scenarios/packbot_flat.toml, which names ../vehicles/packbot510.toml; to \
                     check the vehicle alone run `tracksim check {}`",
                    crate::check::echoed(&name),
                    crate::check::echoed(&path.display().to_string()),
                ),
            )],
        });
    }
    parse_toml(path, &text)
}

/// Loads and compiles a vehicle file.
pub fn load_vehicle(path: &Path) -> Result<VehicleModel> {
    let spec: VehicleSpec = read_toml(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    super::compile_vehicle_in(&spec, dir).map_err(|issues| Error::Invalid {
        path: path.to_path_buf(),
        issues,
    })
}

/// Loads a scenario file and the vehicle file it names (relative to the scenario's folder),
/// reporting every problem with its key path. A file with a `[randomize]` table is sampled
/// with its own `simulation.seed` ([`ScenarioTemplate`] samples other seeds).
pub fn load_scenario(path: &Path) -> Result<Scenario> {
    load_scenario_with(path, &Overrides::default())
}

/// [`load_scenario`] with `overrides` written into the file's keys before it is compiled: an
/// overridden value is checked like the file's own (its problems keyed "KEY (overridden:
/// FLAG)"),
/// and [`Scenario::overridden`] lists the keys.
pub fn load_scenario_with(path: &Path, overrides: &Overrides) -> Result<Scenario> {
    ScenarioTemplate::load_with(path, overrides)?.file_scenario()
}

/// Loads a scenario file to be compiled for any seed (its `[randomize]` table sampled from
/// it), with every key checked as by [`load_scenario`] ([`ScenarioTemplate::load`]).
pub fn load_template(path: &Path) -> Result<ScenarioTemplate> {
    ScenarioTemplate::load(path)
}

/// Reads a scenario file into its spec and its table, with `overrides` written into both.
pub(crate) fn read_scenario(
    path: &Path,
    overrides: &Overrides,
) -> Result<(ScenarioSpec, toml::Table)> {
    let spec = read_scenario_spec(path)?;
    let text = crate::files::read_text_bounded(path, crate::files::MAX_TOML_BYTES)?;
    let mut doc: toml::Table = parse_toml(path, &text)?;
    if overrides.is_empty() {
        return Ok((spec, doc));
    }
    overrides.apply(&mut doc);
    let spec = crate::spec::strict::from_value(&toml::Value::Table(doc.clone())).map_err(|e| {
        Error::Parse {
            path: path.to_path_buf(),
            message: format!("with the overrides of {}: {e}", overrides.keys().join(", ")),
        }
    })?;
    Ok((spec, doc))
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
        sc.commands = c.compile(&sc.vehicle)?;
    }
    sc.source = Some(path.to_path_buf());
    sc.overridden = overrides.keys();
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
        (None, Some(inline)) => super::compile_vehicle_in(inline, dir).map_err(|issues| {
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
