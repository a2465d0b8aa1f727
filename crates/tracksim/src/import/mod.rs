//! `tracksim import MODEL.urdf` (issue 42): a vehicle file that runs, proposed from a robot
//! model as it is found, and a flat-ground scenario beside it. The tracks are found (the
//! paper's ContinuousTrack plugin, Gazebo's TrackedVehicle plugin, or link names), their paths
//! proposed from the plugin's segments or the track links' collision shapes, and every guess
//! reported.
//!
//! - `continuous_track.rs`: the paper's plugin read from the URDF's `<gazebo>` blocks;
//! - `pattern.rs`: its trajectory and pattern as a tracksim path and grousers;
//! - `propose.rs`: a path from a track link's collision shapes ([`ProposedTrack`]);
//! - `hull.rs`: the convex hull of pulley circles;
//! - `select.rs`: which links are tracks, and the separation and height found;
//! - `report.rs`: the guesses ([`ImportReport`]);
//! - `write.rs`: the vehicle and scenario files (TOML written with the `toml` crate);
//! - `world.rs`: an SDF file's world as a scenario (`world.toml`).
//!
//! Units: metres, kilograms, seconds, radians (degrees only where a key says so).

mod continuous_track;
mod hull;
mod pattern;
mod propose;
mod report;
mod select;
mod world;
mod write;

pub use continuous_track::{ContinuousTrackPlugin, PatternElement, PluginSegment};
pub use propose::{
    BELT_MASS_FRACTION, DEFAULT_GROUSER_HEIGHT_M, DEFAULT_GROUSER_LENGTH_M,
    DEFAULT_GROUSER_PITCH_M, MIN_BELT_MASS_KG, ProposedPath, ProposedTrack,
};
pub use report::{Geometry, ImportReport, PLUGIN_MISMATCH_FRACTION, TrackSource};
pub use world::{WORLD_DURATION_S, WORLD_FILE};
pub use write::{FLAT_BELT_SPEED_MPS, FLAT_DURATION_S};

use crate::error::{Error, Result, SpecIssue};
use std::path::{Path, PathBuf};

/// Largest model file read, bytes.
const MAX_MODEL_BYTES: u64 = 64 << 20;

/// The file names `import` writes the scenario under.
pub const SCENARIO_FILE: &str = "flat.toml";

/// What `import` wrote.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The vehicle file.
    pub vehicle: PathBuf,
    /// The flat-ground scenario.
    pub scenario: PathBuf,
    /// The SDF world's scenario (`world.toml`), when the model file holds a `<world>`.
    pub world: Option<PathBuf>,
    /// What was guessed.
    pub report: ImportReport,
}

fn invalid(model: &Path, key: &str, message: String) -> Error {
    Error::Invalid {
        path: model.to_path_buf(),
        issues: vec![SpecIssue::new(key, message)],
    }
}

/// Reads `model` and proposes its tracks, writing nothing.
pub fn propose(model: &Path) -> Result<ImportReport> {
    propose_model(model, None)
}

/// [`propose`] for the SDF `<model>` named `sdf_model` (a URDF file takes none).
pub fn propose_model(model: &Path, sdf_model: Option<&str>) -> Result<ImportReport> {
    let robot =
        crate::urdf::UrdfRobot::load_model(model, sdf_model).map_err(|issues| Error::Invalid {
            path: model.to_path_buf(),
            issues,
        })?;
    let xml = crate::files::read_text_bounded(model, MAX_MODEL_BYTES)?;
    let sel = select::select(&robot, &xml).map_err(|m| invalid(model, "tracks", m))?;
    let geometry = select::geometry(&robot, &sel.tracks, &xml);
    let (flippers, rigid) = select::flippers(&robot, &sel.tracks);
    Ok(ImportReport {
        model: model.to_path_buf(),
        robot: robot.name.clone(),
        source: sel.source,
        tracks: sel.tracks,
        flippers,
        rigid,
        model_warnings: robot.warnings.clone(),
        skipped: sel.skipped,
        geometry,
        sdf_model: sdf_model.map(String::from),
    })
}

/// The vehicle file's name for `model`: its stem, with characters other than letters, digits,
/// `-` and `_` made `_`.
fn vehicle_name(model: &Path) -> String {
    let stem = model
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "robot".into());
    let clean: String = stem
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let clean = if clean == "flat" {
        "flat_robot".into()
    } else {
        clean
    };
    format!("{clean}.toml")
}

fn write_new(path: &Path, text: &str, force: bool) -> Result<()> {
    if !force && path.exists() {
        return Err(invalid(
            path,
            "out",
            "exists already; pass --force to overwrite it, or another --out folder".into(),
        ));
    }
    std::fs::write(path, text).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Imports `model` into the folder `out` (created if need be): the vehicle file
/// `<model stem>.toml` and the scenario [`SCENARIO_FILE`]; both are loaded back before this
/// returns, so what is written runs. Existing files are kept unless `force`.
pub fn import(model: &Path, out: &Path, force: bool) -> Result<Imported> {
    import_model(model, None, out, force)
}

/// [`import`] for the SDF `<model>` named `sdf_model`; an SDF file with a `<world>` also gets
/// [`WORLD_FILE`], the world's static models as terrain with the robot at its pose there.
pub fn import_model(
    model: &Path,
    sdf_model: Option<&str>,
    out: &Path,
    force: bool,
) -> Result<Imported> {
    let report = propose_model(model, sdf_model)?;
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let urdf = write::relative(out, model);
    let urdf = urdf.to_string_lossy().replace('\\', "/");
    let vehicle = out.join(vehicle_name(model));
    let scenario = out.join(SCENARIO_FILE);
    let vtext = write::vehicle_text(&report, &urdf).map_err(|m| invalid(&vehicle, "toml", m))?;
    let file_name = vehicle_name(model);
    let stext = write::scenario_text(&report.robot, &file_name)
        .map_err(|m| invalid(&scenario, "toml", m))?;
    let xml = crate::files::read_text_bounded(model, MAX_MODEL_BYTES)?;
    let world = if world::has_world(&xml) {
        let (text, _) = world::world_text(model, sdf_model, &file_name, out)
            .map_err(|m| invalid(model, "world", m))?;
        Some((out.join(WORLD_FILE), text))
    } else {
        None
    };
    write_new(&vehicle, &vtext, force)?;
    write_new(&scenario, &stext, force)?;
    if let Some((path, text)) = &world {
        write_new(path, text, force)?;
    }
    crate::model::load_vehicle(&vehicle)?;
    crate::model::load_scenario(&scenario)?;
    if let Some((path, _)) = &world {
        crate::model::load_scenario(path)?;
    }
    Ok(Imported {
        vehicle,
        scenario,
        world: world.map(|w| w.0),
        report,
    })
}
