//! Collision meshes of a URDF link (`<mesh filename scale>`): the file found (relative to the
//! URDF's folder, `file://`, or `package://PKG/...` under an ancestor folder named PKG), read
//! with a size bound by mesh-loader (STL, OBJ, COLLADA), and reduced to its convex hull (a
//! vehicle part collides as a convex shape: Rapier has no contact between two triangle meshes,
//! and a terrain may be one).
//!
//! Bounds (issue 45), all checked before the data is allocated or handed to parry: the file's
//! size ([`MAX_ROBOT_MESH_BYTES`]), a binary STL's triangle count from its header against
//! [`MAX_MESH_TRIANGLES`] and against the file's length (a header claiming more triangles than
//! the file holds is refused), a COLLADA file's nesting and declared counts
//! (`limits::check_collada`), every vertex after its scale within
//! [`crate::check::MAX_LENGTH_M`], and a hull that has a volume (one point, a line or a plane
//! refused, `hull.rs`). mesh-loader still indexes a COLLADA file's vertices with the file's
//! own indices (an index past them panicked): the call is guarded (`guard.rs`).
//!
//! [`MeshCache`]: a mesh file is read and hulled once per robot load, however many
//! `<collision>`s name it (one 200k-triangle STL named by 200 collisions was read and hulled
//! 200 times, over 20 s).

use glam::DVec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Most triangles in one collision mesh (a 10^8-triangle file is refused before it is read).
pub const MAX_MESH_TRIANGLES: u64 = 2_000_000;

/// Largest mesh file of a robot, bytes: 128 MiB, room for a binary STL of
/// [`MAX_MESH_TRIANGLES`] (100 MB) while a text mesh's parsed vertices stay well within 1 GB.
pub const MAX_ROBOT_MESH_BYTES: u64 = 128 << 20;

/// The file a URDF `filename` names, relative to the URDF's folder `dir`.
fn resolve(dir: &Path, filename: &str) -> Result<PathBuf, String> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, inner) = rest.split_once('/').unwrap_or((rest, ""));
        for a in dir.ancestors() {
            if a.file_name().is_some_and(|n| n == pkg) {
                return Ok(a.join(inner));
            }
            if a.join(pkg).is_dir() {
                return Ok(a.join(pkg).join(inner));
            }
        }
        return Err(format!(
            "package \"{pkg}\" of {filename} was not found: tracksim looks for a folder named \
             {pkg} at or above the URDF's folder (no ROS installation is used); put the URDF \
             inside its package or give the mesh a path relative to the URDF file"
        ));
    }
    let p = filename.strip_prefix("file://").unwrap_or(filename);
    Ok(dir.join(p))
}

/// A binary STL's triangle count from its header, checked against the file's length `len`:
/// `Ok(None)` for an ASCII STL (it begins with `solid` and its header is not a binary one of
/// this length); an error when the header claims more triangles than allowed or than the file
/// holds.
fn stl_header_count(bytes: &[u8], file: &str) -> Result<Option<u64>, String> {
    let len = bytes.len() as u64;
    let Some(head) = bytes.get(..84) else {
        let ascii = bytes.trim_ascii_start().starts_with(b"solid");
        return if ascii {
            Ok(None)
        } else {
            Err(format!(
                "{file}: {len} bytes, too short for a binary STL (84 bytes of header) and not \
                 an ASCII one (`solid ...`); export the mesh again"
            ))
        };
    };
    let n = u64::from(u32::from_le_bytes([head[80], head[81], head[82], head[83]]));
    // mesh-loader accepts a line end after the triangles (some exporters write one).
    if matches!(len.checked_sub(84 + 50 * n), Some(0..=2)) {
        if n > MAX_MESH_TRIANGLES {
            return Err(format!(
                "{file}: {n} triangles, more than the {MAX_MESH_TRIANGLES} a collision mesh may \
                 have; simplify it (a vehicle part collides as its convex hull)"
            ));
        }
        return Ok(Some(n));
    }
    // Not a binary STL of this length: ASCII if it says so (a binary header may begin with
    // "solid" too, but then its count matches its length, above).
    if bytes.trim_ascii_start().starts_with(b"solid") {
        return Ok(None);
    }
    if n > MAX_MESH_TRIANGLES {
        return Err(format!(
            "{file}: {n} triangles, more than the {MAX_MESH_TRIANGLES} a collision mesh may \
             have; simplify it (a vehicle part collides as its convex hull)"
        ));
    }
    Err(format!(
        "{file}: its binary STL header says {n} triangles ({} bytes) but the file has {len} \
         bytes: it is truncated or its header is wrong; export the mesh again",
        84 + 50 * n
    ))
}

/// A mesh file's hull vertices (scaled, mesh frame, m), or why it was refused.
type Hull = Result<std::rc::Rc<Vec<DVec3>>, String>;

/// The meshes read during one robot load: each file (canonical path and scale) read and
/// hulled once, its hull's vertices (or its problem) kept for every other collision naming it.
#[derive(Default)]
pub(super) struct MeshCache {
    /// By canonical path and the scale's bits.
    hulls: HashMap<(PathBuf, [u64; 3]), Hull>,
    /// How many mesh files were read.
    pub reads: usize,
}

impl MeshCache {
    /// The convex hull's vertices of mesh `filename` (URDF folder `dir`), scaled, in the
    /// mesh's frame, m: read and hulled on the first call for a file and scale.
    pub fn hull(&mut self, dir: &Path, filename: &str, scale: [f64; 3]) -> Hull {
        let path = resolve(dir, filename)?;
        let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        let k = (canonical, scale.map(f64::to_bits));
        if let Some(r) = self.hulls.get(&k) {
            // A refusal is told once, at the first collision naming the file.
            return r.clone().map_err(|_| {
                format!(
                    "{}: refused at its first <collision> (above)",
                    path.file_name().unwrap_or_default().to_string_lossy()
                )
            });
        }
        self.reads += 1;
        let r = mesh_points(&path, scale)
            .and_then(|pts| super::hull::checked_hull(&pts, &display(&path)))
            .map(std::rc::Rc::new);
        self.hulls.insert(k, r.clone());
        r
    }
}

fn display(path: &Path) -> String {
    path.display().to_string()
}

/// The vertices of the mesh file `path`, scaled, in the mesh's frame, m, each checked.
fn mesh_points(path: &Path, scale: [f64; 3]) -> Result<Vec<DVec3>, String> {
    let file = display(path);
    let max = MAX_ROBOT_MESH_BYTES;
    crate::files::check_regular(path, max).map_err(|e| format!("cannot use the mesh: {e}"))?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let bytes =
        crate::files::read_bounded(path, max).map_err(|e| format!("cannot read the mesh: {e}"))?;
    match ext.as_str() {
        "stl" => {
            stl_header_count(&bytes, &file)?;
        }
        "dae" => super::limits::check_collada(path, &bytes)?,
        "obj" => {
            // Faces counted before parsing (each is at least one triangle).
            let faces = bytes
                .split(|b| *b == b'\n')
                .filter(|l| l.trim_ascii_start().starts_with(b"f "))
                .count() as u64;
            if faces > MAX_MESH_TRIANGLES {
                return Err(format!(
                    "{file}: {faces} faces, more than the {MAX_MESH_TRIANGLES} triangles a \
                     collision mesh may have; simplify it"
                ));
            }
        }
        _ => {}
    }
    let side_files = |p: &Path| {
        crate::files::read_bounded(p, max).map_err(|e| std::io::Error::other(e.to_string()))
    };
    // Guarded: mesh-loader indexes a COLLADA file's vertices with the file's own indices.
    let scene = super::guard::guarded(&format!("{file}: reading the mesh"), || {
        mesh_loader::Loader::default().load_from_slice_with_reader(&bytes, path, side_files)
    })?
    .map_err(|e| format!("{file}: cannot read the mesh: {e}"))?;
    drop(bytes);
    let triangles: u64 = scene.meshes.iter().map(|m| m.faces.len() as u64).sum();
    if triangles > MAX_MESH_TRIANGLES {
        return Err(format!(
            "{file}: {triangles} triangles, more than the {MAX_MESH_TRIANGLES} a collision mesh \
             may have; simplify it"
        ));
    }
    if triangles == 0 {
        return Err(format!("{file}: the mesh has no triangles"));
    }
    let s = DVec3::from_array(scale);
    let max_m = crate::check::MAX_LENGTH_M;
    let mut pts = Vec::new();
    for (i, v) in scene
        .meshes
        .iter()
        .flat_map(|m| m.vertices.iter())
        .enumerate()
    {
        let raw = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        let p = raw * s;
        if !p.is_finite() || p.abs().max_element() > max_m {
            return Err(format!(
                "{file}: vertex {i} at [{}, {}, {}] (after the scale) is beyond {max_m:e} m, \
                 more than the f32 engine represents; check the mesh's units and the <mesh \
                 scale>",
                crate::check::num(p.x),
                crate::check::num(p.y),
                crate::check::num(p.z)
            ));
        }
        pts.push(p);
    }
    Ok(pts)
}
