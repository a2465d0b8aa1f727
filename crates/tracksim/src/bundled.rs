//! The bundled vehicles and scenarios, embedded in the library (so in every binary): listed
//! with their descriptions, exported into a folder (`tracksim export`), and found by name from
//! anywhere (`tracksim run packbot_flat`), without the source tree.
//!
//! A name resolves to a file of the bundle extracted once per version into a data folder
//! ([`data_dir`]): `TRACKSIM_DATA_DIR` if set, else `$XDG_CACHE_HOME/tracksim/VERSION` or
//! `$HOME/.cache/tracksim/VERSION`. Files that already hold the bundled bytes are left alone.

use crate::error::{Error, Result};
use include_dir::{Dir, DirEntry, include_dir};
use std::path::{Path, PathBuf};

static VEHICLES: Dir<'_> = include_dir!("$CARGO_MANIFEST_DIR/../../vehicles");
static SCENARIOS: Dir<'_> = include_dir!("$CARGO_MANIFEST_DIR/../../scenarios");

/// What a bundled file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A vehicle file (`vehicles/`).
    Vehicle,
    /// A scenario file (`scenarios/`, sub-folders included).
    Scenario,
}

/// A bundled TOML file.
#[derive(Clone, Debug)]
pub struct BundledFile {
    /// Path in the bundle, e.g. `scenarios/classic/packbot_drawbar.toml`.
    pub path: String,
    /// Its name: the path without the top folder and `.toml`, e.g. `classic/packbot_drawbar`.
    pub name: String,
    /// Vehicle or scenario.
    pub kind: Kind,
    /// The file's `description`.
    pub description: String,
    contents: &'static [u8],
}

fn files_of(dir: &'static Dir<'static>, top: &str, out: &mut Vec<(String, &'static [u8])>) {
    for e in dir.entries() {
        match e {
            DirEntry::Dir(d) => files_of(d, top, out),
            DirEntry::File(f) => out.push((format!("{top}/{}", f.path().display()), f.contents())),
        }
    }
}

/// Every bundled file (TOML, meshes, height maps), by path in the bundle.
fn all_files() -> Vec<(String, &'static [u8])> {
    let mut out = Vec::new();
    files_of(&VEHICLES, "vehicles", &mut out);
    files_of(&SCENARIOS, "scenarios", &mut out);
    out.sort();
    out
}

fn description(text: &[u8]) -> String {
    std::str::from_utf8(text)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| t.get("description")?.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// The bundled vehicle and scenario files, vehicles first, each sorted by path.
pub fn list() -> Vec<BundledFile> {
    let mut out: Vec<BundledFile> = all_files()
        .into_iter()
        .filter(|(p, _)| p.ends_with(".toml"))
        .map(|(path, contents)| {
            let (top, rest) = path.split_once('/').expect("a top folder");
            BundledFile {
                name: rest.trim_end_matches(".toml").to_string(),
                kind: if top == "vehicles" {
                    Kind::Vehicle
                } else {
                    Kind::Scenario
                },
                description: description(contents),
                path,
                contents,
            }
        })
        .collect();
    out.sort_by_key(|f| (f.kind == Kind::Scenario, f.path.clone()));
    out
}

/// Writes the whole bundle (`vehicles/`, `scenarios/` with their assets) into `dir`, keeping
/// its layout so that scenarios find their vehicles; returns the files written (a file that
/// already holds the same bytes is not rewritten, nor listed).
pub fn export(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (path, contents) in all_files() {
        let p = dir.join(&path);
        if std::fs::read(&p).is_ok_and(|old| old == contents) {
            continue;
        }
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|source| Error::Io {
                path: parent.to_path_buf(),
                source,
            })?;
        }
        crate::files::write_atomic(&p, contents)?;
        written.push(p);
    }
    Ok(written)
}

/// The folder the bundle is extracted into to be used by name (see the module's notes).
pub fn data_dir() -> PathBuf {
    let version = env!("CARGO_PKG_VERSION");
    if let Some(d) = std::env::var_os("TRACKSIM_DATA_DIR") {
        return PathBuf::from(d);
    }
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir);
    cache.join("tracksim").join(version)
}

/// The bundle extracted into [`data_dir`] (written on first use); returns that folder, which
/// holds `vehicles/` and `scenarios/`.
pub fn extracted() -> Result<PathBuf> {
    let dir = data_dir();
    export(&dir)?;
    Ok(dir)
}

/// The bundled file called `name` (`packbot_flat`, `classic/packbot_drawbar`, with or without
/// `.toml`, or its bundle path `scenarios/packbot_flat.toml`), if there is one.
pub fn find(name: &str) -> Option<BundledFile> {
    let name = name.trim_end_matches(".toml");
    let files = list();
    files
        .iter()
        .find(|f| f.kind == Kind::Scenario && (f.name == name || f.path == format!("{name}.toml")))
        .or_else(|| {
            files
                .iter()
                .find(|f| f.name == name || f.path == format!("{name}.toml"))
        })
        .cloned()
}

/// The path of the bundled file called `name`, extracted with the whole bundle; `None` when
/// no bundled file has that name.
pub fn resolve(name: &str) -> Result<Option<PathBuf>> {
    match find(name) {
        Some(f) => Ok(Some(extracted()?.join(f.path))),
        None => Ok(None),
    }
}

impl BundledFile {
    /// The file's bytes.
    pub fn contents(&self) -> &'static [u8] {
        self.contents
    }
}
