//! The world of an SDF file as a tracksim scenario (`world.toml` beside the imported vehicle):
//! its static models as terrain (`urdf::sdf::world_terrain_lenient`: what tracksim's terrain
//! cannot hold is left out and listed), the robot model's pose in the world as the start
//! (x, y, yaw; placement sets the height), and the flat scenario's command.

use super::write::{FLAT_BELT_SPEED_MPS, drive_for, prune, relative};
use crate::spec::TerrainSpec;
use std::path::Path;

/// Simulated time of the world scenario, s.
pub const WORLD_DURATION_S: f64 = 20.0;

/// The file name of the world scenario.
pub const WORLD_FILE: &str = "world.toml";

/// Whether the XML text `xml` is an SDF file holding a `<world>`.
pub fn has_world(xml: &str) -> bool {
    roxmltree::Document::parse(xml).is_ok_and(|d| {
        d.root_element().has_tag_name("sdf")
            && d.root_element().children().any(|c| c.has_tag_name("world"))
    })
}

/// Mesh and height-map files made relative to the folder `out` the scenario is written in.
fn files_relative_to(t: &mut TerrainSpec, model: &Path, out: &Path) {
    let dir = model.parent().unwrap_or(Path::new("."));
    let rel = |f: &str| -> String {
        let p = Path::new(f);
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            dir.join(p)
        };
        relative(out, &p).to_string_lossy().replace('\\', "/")
    };
    for m in &mut t.meshes {
        m.file = rel(&m.file.to_string_lossy()).into();
    }
    for h in &mut t.heightfields {
        h.file = rel(&h.file.to_string_lossy()).into();
    }
}

/// The world scenario's text for the SDF file `model` (robot model `sdf_model`, vehicle file
/// `vehicle` beside it) written into `out`, and the lines of what was left out of the world.
pub fn world_text(
    model: &Path,
    sdf_model: Option<&str>,
    vehicle: &str,
    out: &Path,
) -> Result<(String, Vec<String>), String> {
    let flat = |issues: Vec<crate::error::SpecIssue>| {
        issues
            .iter()
            .map(|i| format!("{}: {}", i.key, i.message))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let world = crate::urdf::sdf::world_terrain_lenient(model).map_err(flat)?;
    let start = crate::urdf::sdf::model_start_pose(model, sdf_model).map_err(flat)?;
    let mut terrain = world.terrain;
    files_relative_to(&mut terrain, model, out);
    let left: Vec<String> = world
        .left_out
        .iter()
        .map(|i| format!("left out of the world: {}: {}", i.key, i.message))
        .collect();
    let mut t = toml::Table::new();
    t.insert(
        "description".into(),
        format!(
            "{} (imported) in the world of {} at {FLAT_BELT_SPEED_MPS} m/s",
            vehicle.trim_end_matches(".toml"),
            model
                .file_name()
                .map_or(String::new(), |f| f.to_string_lossy().into_owned())
        )
        .into(),
    );
    let mut veh = toml::Table::new();
    veh.insert("file".into(), vehicle.into());
    if let Some(p) = start {
        let x = p.matrix3.x_axis;
        veh.insert("x_m".into(), p.translation.x.into());
        veh.insert("y_m".into(), p.translation.y.into());
        veh.insert("yaw_deg".into(), x.y.atan2(x.x).to_degrees().into());
    }
    t.insert("vehicle".into(), veh.into());
    let mut tv = toml::Value::try_from(&terrain).map_err(|e| e.to_string())?;
    prune(&mut tv);
    t.insert("terrain".into(), tv);
    drive_for(&mut t, WORLD_DURATION_S);
    let body = toml::to_string(&t).map_err(|e| e.to_string())?;
    let mut head = vec![
        "Written by `tracksim import`: the SDF world's static models as terrain, the robot at its \
         pose in the world, all tracks at 0.3 m/s."
            .to_string(),
    ];
    head.extend(left.iter().cloned());
    let comments: String = head.iter().map(|l| format!("# {l}\n")).collect();
    Ok((format!("{comments}{body}"), left))
}
