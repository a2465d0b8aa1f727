//! `[terrain]` compiled ([`compile_terrain`]): each kind handed to its own file, then the
//! pieces put in their one order and the whole checked.

use super::checks::{MAX_TERRAIN_SHAPES, MAX_TERRAIN_VERTICES};
use super::terrain_model::TerrainModel;
use super::{
    boxes, gap, ground, heightfield, hurdle, incline, mesh, ramps, rough, staircase, stepfield,
};
use crate::check::Checker;
use crate::error::SpecIssue;
use crate::spec::TerrainSpec;
use std::path::Path;

/// Compiles `[terrain]`; problems are appended to `issues` with their key paths. Files named
/// in the terrain are relative to `base_dir` (the scenario file's folder).
pub fn compile_terrain(
    spec: &TerrainSpec,
    base_dir: &Path,
    issues: &mut Vec<SpecIssue>,
) -> TerrainModel {
    let mut c = Checker::default();
    let mut terrain = TerrainModel::default();
    if let Some(g) = &spec.ground {
        terrain.ground = Some(ground::compile(&mut c, g));
        if let Some(s) = &g.soil {
            terrain.ground_soil = terrain.add_soil(&mut c, "terrain.ground.soil", s);
        }
    }
    for (i, s) in spec.boxes.iter().enumerate() {
        boxes::compile(&mut c, &format!("terrain.boxes[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.staircases.iter().enumerate() {
        staircase::compile(&mut c, &format!("terrain.staircases[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.inclines.iter().enumerate() {
        incline::compile(&mut c, &format!("terrain.inclines[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.heightfields.iter().enumerate() {
        let k = format!("terrain.heightfields[{i}]");
        if let Some(h) = heightfield::compile(&mut c, &k, s, base_dir) {
            terrain.heightfields.push(h);
        }
    }
    for (i, s) in spec.rough.iter().enumerate() {
        if let Some(h) = rough::compile(&mut c, &format!("terrain.rough[{i}]"), s) {
            terrain.heightfields.push(h);
        }
    }
    for (i, s) in spec.meshes.iter().enumerate() {
        if let Some(m) = mesh::compile(&mut c, &format!("terrain.meshes[{i}]"), s, base_dir) {
            terrain.meshes.push(m);
        }
    }
    for (i, s) in spec.stepfields.iter().enumerate() {
        stepfield::compile(&mut c, &format!("terrain.stepfields[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.pitch_roll_ramps.iter().enumerate() {
        let k = format!("terrain.pitch_roll_ramps[{i}]");
        ramps::compile(&mut c, &k, s, &mut terrain);
    }
    for (i, s) in spec.hurdles.iter().enumerate() {
        hurdle::compile(&mut c, &format!("terrain.hurdles[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.gaps.iter().enumerate() {
        gap::compile(&mut c, &format!("terrain.gaps[{i}]"), s, &mut terrain);
    }
    terrain.canonicalize();
    check_not_empty(&mut c, &terrain);
    check_total(&mut c, &terrain);
    issues.extend(c.issues);
    terrain
}

/// Reports a terrain beyond the limits of the whole: shapes and grid vertices.
fn check_total(c: &mut Checker, terrain: &TerrainModel) {
    let shapes = terrain.boxes.len() + terrain.cylinders.len();
    if shapes > MAX_TERRAIN_SHAPES {
        c.push(
            "terrain",
            format!(
                "{shapes} boxes and cylinders in all, more than the limit of \
                 {MAX_TERRAIN_SHAPES}: use fewer or larger ones, or a height field"
            ),
        );
    }
    let vertices: usize = terrain
        .heightfields
        .iter()
        .map(|h| h.rows * h.cols)
        .sum::<usize>()
        + terrain
            .meshes
            .iter()
            .map(|m| m.vertices.len())
            .sum::<usize>();
    if vertices > MAX_TERRAIN_VERTICES {
        c.push(
            "terrain",
            format!(
                "{vertices} height-field and mesh vertices in all, more than the limit of \
                 {MAX_TERRAIN_VERTICES}: downsample them"
            ),
        );
    }
}

/// Reports a terrain with nothing to drive on (only when nothing else is wrong).
fn check_not_empty(c: &mut Checker, terrain: &TerrainModel) {
    let empty = terrain.ground.is_none()
        && terrain.boxes.is_empty()
        && terrain.cylinders.is_empty()
        && terrain.heightfields.is_empty()
        && terrain.meshes.is_empty();
    if empty && c.issues.is_empty() {
        c.push(
            "terrain",
            "nothing to drive on: add [terrain.ground] (flat ground), [[terrain.boxes]], \
             [[terrain.staircases]], [[terrain.inclines]], [[terrain.heightfields]], \
             [[terrain.rough]], [[terrain.meshes]] or a test obstacle ([[terrain.stepfields]], \
             [[terrain.pitch_roll_ramps]], [[terrain.hurdles]], [[terrain.gaps]])",
        );
    }
}
