//! STL meshes, binary or ASCII: bytes to vertices and triangles (pure).

use super::{RawMesh, parse_f64};
use glam::DVec3;

/// Reads an STL file, binary or ASCII.
pub(in crate::terrain) fn parse_stl(bytes: &[u8]) -> Result<RawMesh, String> {
    let binary_len = |b: &[u8]| {
        (b.len() >= 84).then(|| 84 + 50 * u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as u64)
    };
    let is_binary = binary_len(bytes) == Some(bytes.len() as u64);
    let mut verts = Vec::new();
    if is_binary {
        let n = (bytes.len() - 84) / 50;
        for t in 0..n {
            let rec = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
            for v in 0..3 {
                let o = 12 + 12 * v;
                let c = |i: usize| {
                    f32::from_le_bytes([
                        rec[o + 4 * i],
                        rec[o + 4 * i + 1],
                        rec[o + 4 * i + 2],
                        rec[o + 4 * i + 3],
                    ]) as f64
                };
                verts.push(DVec3::new(c(0), c(1), c(2)));
            }
        }
    } else {
        let text = std::str::from_utf8(bytes).map_err(|_| {
            "is neither a binary STL (its size does not match its triangle count) nor an ASCII \
             STL (not text)"
                .to_string()
        })?;
        if !text.trim_start().starts_with("solid") {
            return Err(
                "is neither a binary STL (its size does not match its triangle count) nor an \
                 ASCII STL (it does not start with `solid`)"
                    .into(),
            );
        }
        let mut toks = text.split_whitespace();
        while let Some(t) = toks.next() {
            if t == "vertex" {
                let x = parse_f64(toks.next(), "vertex x")?;
                let y = parse_f64(toks.next(), "vertex y")?;
                let z = parse_f64(toks.next(), "vertex z")?;
                verts.push(DVec3::new(x, y, z));
            }
        }
        if verts.len() % 3 != 0 {
            return Err(format!(
                "has {} vertices, not a multiple of 3: every facet needs 3 vertices",
                verts.len()
            ));
        }
    }
    let tris = (0..verts.len() as u32 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    Ok((verts, tris))
}
