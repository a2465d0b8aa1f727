//! `[[terrain.meshes]]`: triangle meshes read from STL or OBJ files, and [`MeshModel`], their
//! compiled form (vertices in the world).

use super::parse::RawMesh;
use super::parse::obj::parse_obj;
use super::parse::stl::parse_stl;
use crate::check::{Checker, v3};
use crate::render::Rgb;
use crate::spec::{MeshSpec, UpAxis};
use glam::{DQuat, DVec3};
use std::path::{Path, PathBuf};

/// A triangle mesh, compiled: vertices already transformed into the world, m.
#[derive(Clone, Debug)]
pub struct MeshModel {
    /// Vertices in world coordinates, m.
    pub vertices: Vec<DVec3>,
    /// Triangles (indices into `vertices`), degenerate ones removed.
    pub triangles: Vec<[u32; 3]>,
    /// Friction coefficient.
    pub friction: f64,
    /// Colour in camera images.
    pub color: crate::render::Rgb,
    /// The file it was read from.
    pub source: PathBuf,
}

/// Checks one mesh (key `k`, file relative to `base_dir`), reads it and moves it into place.
pub(super) fn compile(
    c: &mut Checker,
    k: &str,
    s: &MeshSpec,
    base_dir: &Path,
) -> Option<MeshModel> {
    let n = c.issues.len();
    c.positive(&format!("{k}.scale"), s.scale, "");
    c.finite(&format!("{k}.translation_m"), &s.translation_m);
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let path = base_dir.join(&s.file);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let parser: fn(&[u8]) -> Result<RawMesh, String> = match ext.as_deref() {
        Some("stl") => parse_stl,
        Some("obj") => parse_obj,
        _ => {
            c.push(
                format!("{k}.file"),
                format!(
                    "{}: unsupported mesh format; give an .stl (binary or ASCII) or .obj file",
                    path.display()
                ),
            );
            return None;
        }
    };
    let bytes = match crate::files::read_bounded(&path, crate::files::MAX_MESH_BYTES) {
        Ok(b) => b,
        Err(e) => {
            c.push(
                format!("{k}.file"),
                format!(
                    "cannot read {e}; give the path of an .stl or .obj file relative to the \
                     scenario's folder"
                ),
            );
            return None;
        }
    };
    let (verts, tris) = match parser(&bytes) {
        Ok(m) => m,
        Err(e) => {
            c.push(
                format!("{k}.file"),
                format!("{} {e}; fix or re-export the mesh", path.display()),
            );
            return None;
        }
    };
    if let Some(i) = verts.iter().position(|v| !v.is_finite()) {
        c.push(
            format!("{k}.file"),
            format!(
                "{}: vertex {i} is not finite ({:?}); fix or re-export the mesh",
                path.display(),
                verts[i]
            ),
        );
    }
    if c.issues.len() != n {
        return None;
    }
    let rot = DQuat::from_rotation_z(s.yaw_deg.to_radians())
        * match s.up_axis {
            UpAxis::Z => DQuat::IDENTITY,
            UpAxis::Y => DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
        };
    let vertices: Vec<DVec3> = verts
        .iter()
        .map(|v| rot * (*v * s.scale) + v3(s.translation_m))
        .collect();
    let triangles: Vec<[u32; 3]> = tris
        .into_iter()
        .filter(|t| {
            let [a, b, cc] = t.map(|i| vertices[i as usize]);
            (b - a).cross(cc - a).length() > 1e-12
        })
        .collect();
    if triangles.is_empty() {
        c.push(
            format!("{k}.file"),
            format!(
                "{} has no triangles (or only degenerate ones): export the surface as a \
                 triangle mesh",
                path.display()
            ),
        );
        return None;
    }
    Some(MeshModel {
        vertices,
        triangles,
        friction: s.friction,
        color: Rgb::default(),
        source: path,
    })
}
