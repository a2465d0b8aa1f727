//! SDFormat (1.6 to 1.9) files: a `<model>` read as the robot a URDF file gives, and a
//! `<world>`'s static models read as terrain. A parser of its own on roxmltree (every message
//! names the file, the element and its line); `docs/URDF.md`, "SDF".
//!
//! - `file.rs`: the file read and parsed, the context of messages, number lists, the choice
//!   of the robot's model (`sdf_model`, else the one model with a tracked-vehicle plugin,
//!   else the only non-static model);
//! - `pose.rs`: `<pose>` (rpy, degrees, quaternion) and the frames of a model (`relative_to`,
//!   default frames, `<frame>`), resolved into the model frame;
//! - `geometry.rs`: collision geometry and the files `<uri>`s name (`model://`, `file://`,
//!   relative; web addresses refused);
//! - `model.rs`: a model converted into `UrdfSource` (links, inertials, collisions, joints,
//!   lines, the plugin, `<mu>`), so the URDF path's tree walk, checks and compile are shared;
//! - `world.rs`: static models as terrain entries (`TerrainSpec`).
//!
//! Public entry points for other layers (`tracksim import`): [`world_terrain`],
//! [`world_terrain_lenient`] and [`model_start_pose`]; a robot is read with
//! `UrdfRobot::load_model`.

mod file;
mod geometry;
mod model;
mod pose;
mod world;

pub use world::{ROTATION_TOLERANCE, WorldSolid};

pub(in crate::urdf) use model::read_model;

use crate::error::SpecIssue;
use crate::spec::TerrainSpec;
use std::path::Path;

/// A world's terrain read leniently: what could be read, and what could not.
#[derive(Clone, Debug)]
pub struct WorldTerrain {
    /// The terrain entries (world frame, m, degrees; a mesh's or height map's `file` is the
    /// path found from its `<uri>`, absolute when the SDF file's path is).
    pub terrain: TerrainSpec,
    /// Cylinders and spheres of static models (no terrain entry holds them; `tracksim import`
    /// writes each as a mesh).
    pub solids: Vec<WorldSolid>,
    /// The shapes and `<include>`s left out, each with its element and line and why.
    pub left_out: Vec<SpecIssue>,
}

fn open(path: &Path) -> Result<String, Vec<SpecIssue>> {
    file::read_text(path, "sdf")
}

/// The terrain of the SDF file `path`'s first `<world>`: every `<static>` model's collision
/// shapes as tracksim terrain entries in the world frame (ground plane, boxes, meshes, height
/// fields; m, degrees). Strict: any shape it cannot convert (a cylinder, a box rolled about
/// its own x axis, an `<include>`, ...) is a problem naming its element and line, and the
/// whole world is refused. Problems are keyed `sdf <element> (FILE line N)`.
pub fn world_terrain(path: &Path) -> Result<TerrainSpec, Vec<SpecIssue>> {
    let w = world_terrain_lenient(path)?;
    if w.left_out.is_empty() && w.solids.is_empty() {
        Ok(w.terrain)
    } else {
        Err(w
            .solids
            .into_iter()
            .map(|s| s.issue)
            .chain(w.left_out)
            .collect())
    }
}

/// As [`world_terrain`], but a shape or `<include>` that cannot be converted is left out and
/// listed instead of refusing the world. `Err` only when the file cannot be read or has no
/// `<world>`.
pub fn world_terrain_lenient(path: &Path) -> Result<WorldTerrain, Vec<SpecIssue>> {
    with_file(path, |ctx| {
        let (terrain, solids, left_out) = world::terrain(ctx)?;
        Ok(WorldTerrain {
            terrain,
            solids,
            left_out,
        })
    })
}

/// `f` of the parsed SDF file `path`.
fn with_file<T>(
    path: &Path,
    f: impl FnOnce(&file::Ctx) -> Result<T, Vec<SpecIssue>>,
) -> Result<T, Vec<SpecIssue>> {
    let text = open(path)?;
    let doc = file::parse(path, &text, "sdf")?;
    f(&file::Ctx {
        path,
        doc: &doc,
        key: "sdf",
    })
}

/// The start pose of the robot model of SDF file `path` (`model`: its name, else chosen as a
/// vehicle file's `sdf_model` default is): the model's `<pose>` in its world, m and rad
/// (translation and rotation of the model frame in the world frame). `None` for a model file
/// whose model has no `<pose>`.
pub fn model_start_pose(
    path: &Path,
    model: Option<&str>,
) -> Result<Option<glam::DAffine3>, Vec<SpecIssue>> {
    with_file(path, |ctx| {
        let m = file::choose_model(ctx, model).map_err(|e| vec![e])?;
        model::start_pose(ctx, m).map_err(|e| vec![e])
    })
}
