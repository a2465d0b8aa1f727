//! Reading files: a file read once (bounded, a regular file), its TOML parsed with the file
//! named in every error (line and column, unknown keys with a suggestion, the strict checks of
//! [`crate::spec::strict`]); a vehicle file given as a scenario refused with how to use it.

use crate::check::shorten;
use crate::error::{Error, Result, SpecIssue};
use crate::spec::ScenarioSpec;
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
    parse_with_table(path, text).map(|(typed, _)| typed)
}

/// [`parse_toml`], also giving the parsed table.
fn parse_with_table<T: serde::de::DeserializeOwned>(
    path: &Path,
    text: &str,
) -> Result<(T, toml::Table)> {
    let parse = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message: explain(&message),
    };
    if let Some(m) = xml_model(text) {
        return Err(Error::Parse {
            path: path.to_path_buf(),
            message: m,
        });
    }
    let doc: toml::Table = toml::from_str(text).map_err(|e| parse(e.to_string()))?;
    let typed: T = toml::from_str(text).map_err(|e| parse(e.to_string()))?;
    crate::spec::strict::from_value::<T>(&toml::Value::Table(doc.clone()))
        .map_err(|e| parse(e.0))?;
    Ok((typed, doc))
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
    parse_scenario(path, &text).map(|(spec, _)| spec)
}

/// Parses a scenario file's `text` into its spec and table (see [`read_scenario_spec`]).
fn parse_scenario(path: &Path, text: &str) -> Result<(ScenarioSpec, toml::Table)> {
    if let Ok(doc) = toml::from_str::<toml::Table>(text)
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
    parse_with_table(path, text)
}

/// Reads a scenario file once into its spec and its table (the text parsed for line and
/// column in errors, the strict checks run on the table).
pub(crate) fn read_scenario_table(path: &Path) -> Result<(ScenarioSpec, toml::Table)> {
    let text = crate::files::read_text_bounded(path, crate::files::MAX_TOML_BYTES)?;
    parse_scenario(path, &text)
}

/// What to do with an XML robot model (URDF, SDF, xacro) given where a tracksim TOML file is
/// read, or `None` for text that is not XML.
fn xml_model(text: &str) -> Option<String> {
    let start = text.trim_start_matches('\u{feff}').trim_start();
    if !start.starts_with('<') {
        return None;
    }
    let kind = if start.contains("<sdf") {
        "an SDF model or world"
    } else if start.contains("<robot") {
        "a URDF robot"
    } else {
        "an XML file"
    };
    Some(format!(
        "this is {kind}, not a tracksim TOML file: a vehicle file names a URDF robot with \
         `urdf = \"robot.urdf\"` (or an SDF file, `urdf = \"robot.sdf\"`, with `sdf_model = \
         \"NAME\"` when it has several models) beside its `[[tracks]]` (docs/URDF.md), \
         and a scenario names the vehicle file in `[vehicle] file`"
    ))
}
