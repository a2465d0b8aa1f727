//! Terrain file parsers, apart from the physics: pure functions from a file's bytes to plain
//! data (grey values, vertices and triangles). No file access, no Rapier, no terrain models.
//!
//! - `png.rs`: greyscale PNG height maps;
//! - `stl.rs`: STL meshes (binary or ASCII);
//! - `obj.rs`: OBJ meshes.

pub(super) mod obj;
pub(super) mod png;
pub(super) mod stl;

use glam::DVec3;

/// Triangles as read from a mesh file: vertices and index triples.
pub(super) type RawMesh = (Vec<DVec3>, Vec<[u32; 3]>);

/// Parses the number token `tok`, naming it `what` in the error message.
fn parse_f64(tok: Option<&str>, what: &str) -> Result<f64, String> {
    let t = tok.ok_or_else(|| format!("missing {what}"))?;
    t.parse::<f64>()
        .map_err(|_| format!("{what} {t:?} is not a number"))
}
