//! Terrains: the compiled form of a scenario's `[terrain]` table ([`crate::spec::TerrainSpec`])
//! and its insertion into a Rapier world. Every surface carries its own friction coefficient
//! (default 0.6). Heights are z-up, x forward, y left (REP 103).
//!
//! A `[terrain]` table may combine, in any number:
//! - `[terrain.ground]`: an infinite flat plane (simulated as a tile kept under the vehicle,
//!   [`GROUND_TILE_HALF_M`]);
//! - `[[terrain.boxes]]`: boxes (steps, walls, bumps);
//! - `[[terrain.staircases]]`, `[[terrain.inclines]]`: stairs and ramps built from boxes;
//! - `[[terrain.heightfields]]`: height maps read from greyscale PNG files (8 or 16 bit);
//! - `[[terrain.rough]]`: repeatable random rough ground (a seeded height field);
//! - `[[terrain.meshes]]`: triangle meshes read from STL (binary or ASCII) or OBJ files;
//! - the standard response-robot test obstacles (NIST / ASTM E54.09), built from boxes:
//!   `[[terrain.stepfields]]`, `[[terrain.pitch_roll_ramps]]`, `[[terrain.hurdles]]`,
//!   `[[terrain.gaps]]`.
//!
//! `terrain_model.rs` holds [`TerrainModel`], `solids.rs` the boxes and cylinders it is built
//! of, and `compile.rs` [`compile_terrain`], which hands each kind to its own
//! file (`ground.rs`, `boxes.rs`, `staircase.rs`, `incline.rs`, `heightfield.rs`, `rough.rs`,
//! `mesh.rs`, `stepfield.rs`, `ramps.rs`, `hurdle.rs`, `gap.rs`). File formats are read by the
//! pure parsers of `parse/`; `insert.rs` puts the model into Rapier and `query.rs` answers
//! extent and height questions. Shared helpers: `frame.rs` (local frames on the floor),
//! `checks.rs` (input checks and size limits), `rng.rs` (the seeded generator),
//! `canonical.rs` (the one order of the pieces, whatever the file's order).
//!
//! Layering: this module depends on [`crate::spec`], the input checker and [`crate::error`],
//! never on the vehicle model, the simulation or the runner.

mod boxes;
mod canonical;
mod checks;
mod compile;
mod frame;
mod gap;
mod ground;
mod heightfield;
mod hurdle;
mod incline;
mod insert;
mod mesh;
mod parse;
mod query;
mod ramps;
mod rng;
mod rough;
pub mod soil;
mod solids;
mod staircase;
mod stepfield;
mod terrain_model;

pub use compile::compile_terrain;
pub use heightfield::HeightFieldModel;
pub use insert::{GROUND_RECENTRE_M, GROUND_TILE_HALF_M, InsertedTerrain};
pub use mesh::MeshModel;
pub use soil::{SoilModel, soil_tag, tagged_soil};
pub use solids::{BoxModel, CylinderModel};
pub use terrain_model::TerrainModel;
