//! `[terrain]` compiled ([`compile_terrain`]): each kind handed to its own file, then the
//! pieces put in their one order and the whole checked.

use super::checks::{MAX_TERRAIN_SHAPES, MAX_TERRAIN_VERTICES};
use super::terrain_model::TerrainModel;
use super::{
    boxes, gap, ground, heightfield, hurdle, incline, mesh, ramps, rough, staircase, stepfield,
};
use crate::check::Checker;
use crate::error::SpecIssue;
use crate::render::{Rgb, palette};
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
        let default = match g.soil {
            Some(_) => palette::SOIL,
            None => palette::GROUND,
        };
        terrain.ground_color = color(&mut c, "terrain.ground", &g.color, default);
    }
    let t = &mut terrain;
    for (i, s) in spec.boxes.iter().enumerate() {
        let k = format!("terrain.boxes[{i}]");
        entry(&mut c, t, &k, &s.color, palette::BOX, |c, t| {
            boxes::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.staircases.iter().enumerate() {
        let k = format!("terrain.staircases[{i}]");
        entry(&mut c, t, &k, &s.color, palette::STAIRCASE, |c, t| {
            staircase::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.inclines.iter().enumerate() {
        let k = format!("terrain.inclines[{i}]");
        entry(&mut c, t, &k, &s.color, palette::INCLINE, |c, t| {
            incline::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.heightfields.iter().enumerate() {
        let k = format!("terrain.heightfields[{i}]");
        entry(&mut c, t, &k, &s.color, palette::HEIGHTFIELD, |c, t| {
            t.heightfields
                .extend(heightfield::compile(c, &k, s, base_dir))
        });
    }
    for (i, s) in spec.rough.iter().enumerate() {
        let k = format!("terrain.rough[{i}]");
        entry(&mut c, t, &k, &s.color, palette::ROUGH, |c, t| {
            t.heightfields.extend(rough::compile(c, &k, s))
        });
    }
    for (i, s) in spec.meshes.iter().enumerate() {
        let k = format!("terrain.meshes[{i}]");
        entry(&mut c, t, &k, &s.color, palette::MESH, |c, t| {
            t.meshes.extend(mesh::compile(c, &k, s, base_dir))
        });
    }
    let obstacle = palette::TEST_OBSTACLE;
    for (i, s) in spec.stepfields.iter().enumerate() {
        let k = format!("terrain.stepfields[{i}]");
        entry(&mut c, t, &k, &s.color, obstacle, |c, t| {
            stepfield::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.pitch_roll_ramps.iter().enumerate() {
        let k = format!("terrain.pitch_roll_ramps[{i}]");
        entry(&mut c, t, &k, &s.color, obstacle, |c, t| {
            ramps::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.hurdles.iter().enumerate() {
        let k = format!("terrain.hurdles[{i}]");
        entry(&mut c, t, &k, &s.color, obstacle, |c, t| {
            hurdle::compile(c, &k, s, t)
        });
    }
    for (i, s) in spec.gaps.iter().enumerate() {
        let k = format!("terrain.gaps[{i}]");
        entry(&mut c, t, &k, &s.color, obstacle, |c, t| {
            gap::compile(c, &k, s, t)
        });
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

/// Compiles one terrain entry at key `k` and paints the pieces it added (`given`: its
/// `color` key; `default`: its kind's colour).
fn entry(
    c: &mut Checker,
    t: &mut TerrainModel,
    k: &str,
    given: &Option<String>,
    default: Rgb,
    compile: impl FnOnce(&mut Checker, &mut TerrainModel),
) {
    let since = Counts::of(t);
    compile(c, t);
    let chosen = color(c, k, given, default);
    since.paint(t, given.is_some(), chosen);
}

/// Reads an entry's `color` key (`k.color`): its colour, or `default` when absent or wrong
/// (reported).
fn color(c: &mut Checker, k: &str, given: &Option<String>, default: Rgb) -> Rgb {
    let Some(v) = given else { return default };
    Rgb::parse(v).unwrap_or_else(|| {
        c.push(
            format!("{k}.color"),
            format!(
                "{v:?} is not a colour: write \"#rrggbb\", six hexadecimal digits after a '#' \
                 (e.g. \"#b8b0a2\")"
            ),
        );
        default
    })
}

/// How many pieces of each kind the terrain held before an entry was compiled.
#[derive(Clone, Copy)]
struct Counts {
    boxes: usize,
    cylinders: usize,
    heightfields: usize,
    meshes: usize,
}

impl Counts {
    fn of(t: &TerrainModel) -> Counts {
        Counts {
            boxes: t.boxes.len(),
            cylinders: t.cylinders.len(),
            heightfields: t.heightfields.len(),
            meshes: t.meshes.len(),
        }
    }

    /// Gives the pieces the entry added colour `chosen`: stair nosings keep
    /// [`palette::NOSING`] and boxes with soil [`palette::SOIL`] unless the entry `given` its
    /// own colour.
    fn paint(self, t: &mut TerrainModel, given: bool, chosen: Rgb) {
        for b in &mut t.boxes[self.boxes..] {
            b.color = if !given && b.soil.is_some() {
                palette::SOIL
            } else {
                chosen
            };
        }
        for cy in &mut t.cylinders[self.cylinders..] {
            cy.color = if given { chosen } else { palette::NOSING };
        }
        for h in &mut t.heightfields[self.heightfields..] {
            h.color = chosen;
        }
        for m in &mut t.meshes[self.meshes..] {
            m.color = chosen;
        }
    }
}
