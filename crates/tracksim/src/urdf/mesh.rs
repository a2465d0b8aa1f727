//! Collision meshes of a URDF link (`<mesh filename scale>`): the file found (relative to the
//! URDF's folder, `file://`, or `package://PKG/...` under an ancestor folder named PKG), read
//! with a size bound by mesh-loader (STL, OBJ, COLLADA), and reduced to its convex hull (a
//! vehicle part collides as a convex shape: Rapier has no contact between two triangle meshes,
//! and a terrain may be one).

use std::path::{Path, PathBuf};

/// Most triangles in one collision mesh (a 10^8-triangle file is refused before it is read).
pub const MAX_MESH_TRIANGLES: u64 = 2_000_000;

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

/// A binary STL's triangle count from its header, when the file is binary STL.
fn stl_header_count(path: &Path, len: u64) -> Option<u64> {
    use std::io::Read;
    let mut head = [0u8; 84];
    let mut f = std::fs::File::open(path).ok()?;
    f.read_exact(&mut head).ok()?;
    if head.starts_with(b"solid") && !head[..80].contains(&0) {
        return None;
    }
    let n = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
    (84 + 50 * n == len || n > MAX_MESH_TRIANGLES).then_some(n)
}

/// The vertices of mesh `filename` (URDF folder `dir`), scaled, in the mesh's frame, m.
pub(super) fn mesh_points(
    dir: &Path,
    filename: &str,
    scale: [f64; 3],
) -> Result<Vec<glam::DVec3>, String> {
    let path = resolve(dir, filename)?;
    let max = crate::files::MAX_MESH_BYTES;
    crate::files::check_regular(&path, max).map_err(|e| format!("cannot use the mesh: {e}"))?;
    let len = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let is_stl = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("stl"));
    if is_stl
        && let Some(n) = stl_header_count(&path, len)
        && n > MAX_MESH_TRIANGLES
    {
        return Err(format!(
            "{}: {n} triangles, more than the {MAX_MESH_TRIANGLES} a collision mesh may have; \
             simplify it (a vehicle part collides as its convex hull)",
            path.display()
        ));
    }
    let bytes =
        crate::files::read_bounded(&path, max).map_err(|e| format!("cannot read the mesh: {e}"))?;
    let side_files = |p: &Path| {
        crate::files::read_bounded(p, max).map_err(|e| std::io::Error::other(e.to_string()))
    };
    let scene = mesh_loader::Loader::default()
        .load_from_slice_with_reader(&bytes, &path, side_files)
        .map_err(|e| format!("{}: cannot read the mesh: {e}", path.display()))?;
    let triangles: u64 = scene.meshes.iter().map(|m| m.faces.len() as u64).sum();
    if triangles > MAX_MESH_TRIANGLES {
        return Err(format!(
            "{}: {triangles} triangles, more than the {MAX_MESH_TRIANGLES} a collision mesh may \
             have; simplify it",
            path.display()
        ));
    }
    let s = glam::DVec3::from_array(scale);
    let pts: Vec<glam::DVec3> = scene
        .meshes
        .iter()
        .flat_map(|m| m.vertices.iter())
        .map(|v| glam::DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64) * s)
        .collect();
    if pts.len() < 4 || triangles == 0 {
        return Err(format!("{}: the mesh has no triangles", path.display()));
    }
    if let Some(i) = pts.iter().position(|p| !p.is_finite()) {
        return Err(format!("{}: vertex {i} is not finite", path.display()));
    }
    Ok(pts)
}
