//! `tracksim check`: vehicle and scenario files checked without running them.

use super::{Failure, scenario_file};
use std::path::{Path, PathBuf};
use tracksim::Error;

/// Check vehicle and scenario files without running them; print every problem.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// Files to check (vehicle or scenario files, told apart by their keys; or bundled names).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

/// Tells a vehicle file from a scenario file by its top-level keys.
fn is_vehicle_file(path: &Path) -> Result<bool, Error> {
    let text = tracksim::files::read_text_bounded(path, tracksim::files::MAX_TOML_BYTES)?;
    let table: tracksim::toml::Table = tracksim::model::parse_toml(path, &text)?;
    Ok(table.contains_key("body") || table.contains_key("tracks") || table.contains_key("urdf"))
}

/// What is simulated of a scenario: the built world's masses, then each vehicle's design (a
/// block per robot in a file with several).
fn scenario_text(f: &Path) -> Result<String, Error> {
    let s = tracksim::load_scenario(f)?;
    // Build it (no step) to show what is simulated: every part's mass.
    let mut sim = tracksim::Simulation::new(&s)?;
    let mut lines = vec![format!(
        "scenario with {} robot(s), {:.1} s, method {}",
        sim.robot_count(),
        s.duration,
        s.method
    )];
    for k in 0..sim.robot_count() {
        sim.select(k);
        let v = &sim.scenario().vehicle;
        lines.push(format!(
            "robot \"{}\": vehicle \"{}\"",
            sim.robot_name(),
            v.name
        ));
        if let Some(u) = &v.urdf {
            lines.extend(u.lines());
        }
        lines.extend(sim.mass_report().lines());
        lines.extend(tracksim::model::design_report(v).lines());
    }
    Ok(lines.join("\n       "))
}

/// What a vehicle file imports and its design, after building it as a run would (on flat
/// ground, no step): the checks made while building (the link-mass floor taken back from the
/// chassis, issue 45) are the same for `check` and `run`.
fn vehicle_text(f: &Path) -> Result<String, Error> {
    let v = tracksim::load_vehicle(f)?;
    let mut lines = vec![format!("vehicle \"{}\"", v.name)];
    if let Some(u) = &v.urdf {
        lines.extend(u.lines());
    }
    lines.extend(tracksim::model::design_report(&v).lines());
    let dir = f.parent().unwrap_or(Path::new("."));
    let name = f.display().to_string();
    let overrides = tracksim::Overrides::default();
    let sc =
        tracksim::model::compile_scenario_text(&name, "[terrain.ground]\n", v, dir, &overrides)?;
    // A problem found while building is the vehicle file's.
    tracksim::Simulation::new(&sc).map_err(|e| match e {
        Error::Invalid { issues, .. } => Error::Invalid {
            path: f.to_path_buf(),
            issues,
        },
        e => e,
    })?;
    Ok(lines.join("\n       "))
}

/// `tracksim check`: exits 2 if any file has a problem (all are reported).
pub fn check(a: CheckArgs) -> Result<(), Failure> {
    let mut failed = false;
    for given in &a.files {
        let f = scenario_file(given)?;
        let r = is_vehicle_file(&f).and_then(|vehicle| {
            if vehicle {
                vehicle_text(&f)
            } else {
                scenario_text(&f)
            }
        });
        match r {
            Ok(what) => out!("ok     {}: {what}", f.display()),
            Err(e) => {
                out!("error  {e}");
                failed = true;
            }
        }
    }
    if failed {
        Err(Failure::Reported)
    } else {
        Ok(())
    }
}
