//! OBJ meshes: bytes to vertices and triangles (pure; only `v` and `f` lines are read).

use super::{RawMesh, parse_f64};
use glam::DVec3;

/// Reads the vertices (`v`) and faces (`f`, polygons fanned into triangles) of an OBJ file.
pub(in crate::terrain) fn parse_obj(bytes: &[u8]) -> Result<RawMesh, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "is not a text (OBJ) file".to_string())?;
    let mut verts = Vec::new();
    let mut tris = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        let mut toks = line.split_whitespace();
        let at = |e: String| format!("line {}: {e}", ln + 1);
        match toks.next() {
            Some("v") => {
                let x = parse_f64(toks.next(), "vertex x").map_err(at)?;
                let y = parse_f64(toks.next(), "vertex y").map_err(at)?;
                let z = parse_f64(toks.next(), "vertex z").map_err(at)?;
                verts.push(DVec3::new(x, y, z));
            }
            Some("f") => {
                let mut idx = Vec::new();
                for t in toks {
                    let first = t.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| at(format!("face index {t:?} is not a number")))?;
                    let n = verts.len() as i64;
                    let j = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || j < 0 || j >= n {
                        return Err(at(format!(
                            "face index {i} refers to no vertex ({n} defined so far)"
                        )));
                    }
                    idx.push(j as u32);
                }
                if idx.len() < 3 {
                    return Err(at("a face needs at least 3 vertices".into()));
                }
                for w in 1..idx.len() - 1 {
                    tris.push([idx[0], idx[w], idx[w + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok((verts, tris))
}
