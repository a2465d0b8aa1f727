//! A `<collision><geometry>` read: box, cylinder (along its z axis, as URDF's), sphere,
//! capsule, mesh, plane, heightmap, empty. Mesh and heightmap files are found from their
//! `<uri>`: relative to the SDF file, `file://`, `package://` (as for URDF), or
//! `model://NAME/...` under the nearest ancestor folder named NAME (or holding a NAME
//! folder). Web addresses (Fuel, `https://fuel.gazebosim.org/...`) are refused: nothing is
//! downloaded at run time.

use super::file::{Ctx, Node, child, number_of, numbers, text};
use crate::error::SpecIssue;
use glam::DVec3;
use std::path::{Path, PathBuf};

/// One collision geometry, in its collision frame.
#[derive(Clone, Debug)]
pub(super) enum Shape {
    /// Full sizes, m.
    Box([f64; 3]),
    /// Radius and length along z, m.
    Cylinder { radius: f64, length: f64 },
    /// Radius, m.
    Sphere(f64),
    /// Radius and length of the straight part along z, m.
    Capsule { radius: f64, length: f64 },
    /// A mesh file (as a URDF `filename`: resolved path, or `package://`) and its scale.
    Mesh { file: String, scale: [f64; 3] },
    /// An infinite plane through the origin with this normal.
    Plane(DVec3),
    /// A height map image, its size (x, y, height range; m) and centre (m).
    Heightmap {
        file: PathBuf,
        size: [f64; 3],
        pos: [f64; 3],
    },
    /// `<empty/>`: no shape.
    Empty,
}

/// The file a `<uri>` names (SDF file folder `dir`), as a URDF mesh `filename`.
pub(super) fn resolve_uri(dir: &Path, uri: &str) -> Result<String, String> {
    let lower = uri.to_ascii_lowercase();
    if lower.starts_with("http://") || lower.starts_with("https://") {
        return Err(format!(
            "{uri} is a web address (a Fuel model): tracksim downloads nothing at run time; \
             download the model once and name its file (relative to the SDF file)"
        ));
    }
    if let Some(rest) = uri.strip_prefix("model://") {
        let (name, inner) = rest.split_once('/').unwrap_or((rest, ""));
        for a in dir.ancestors() {
            if a.file_name().is_some_and(|n| n == name) {
                return Ok(a.join(inner).to_string_lossy().into_owned());
            }
            if a.join(name).is_dir() {
                return Ok(a.join(name).join(inner).to_string_lossy().into_owned());
            }
        }
        return Err(format!(
            "model \"{name}\" of {uri} was not found: tracksim looks for a folder named {name} \
             at or above the SDF file's folder (GZ_SIM_RESOURCE_PATH is not searched)"
        ));
    }
    if uri.starts_with("package://") {
        return Ok(uri.to_string());
    }
    let p = uri.strip_prefix("file://").unwrap_or(uri);
    Ok(dir.join(p).to_string_lossy().into_owned())
}

fn positive(ctx: &Ctx, n: Node, v: &[f64]) -> Result<(), SpecIssue> {
    if v.iter().all(|x| *x > 0.0) {
        Ok(())
    } else {
        Err(ctx.issue(n, format!("must be lengths > 0, m; got {v:?}")))
    }
}

fn uri_of(ctx: &Ctx, n: Node) -> Result<String, SpecIssue> {
    let u = child(n, "uri").ok_or_else(|| ctx.issue(n, "has no <uri>"))?;
    resolve_uri(&ctx.dir(), text(u)).map_err(|m| ctx.issue(u, m))
}

/// Reads the `<geometry>` element `g`.
pub(super) fn shape(ctx: &Ctx, g: Node) -> Result<Shape, SpecIssue> {
    let Some(s) = g.children().find(|c| c.is_element()) else {
        return Err(ctx.issue(g, "is empty: it needs a box, cylinder, sphere, mesh, ..."));
    };
    match s.tag_name().name() {
        "box" => {
            let n = child(s, "size").ok_or_else(|| ctx.issue(s, "has no <size>"))?;
            let v = numbers(ctx, n, &[3])?;
            positive(ctx, n, &v)?;
            Ok(Shape::Box([v[0], v[1], v[2]]))
        }
        "cylinder" | "capsule" => {
            let radius = number_of(ctx, s, "radius", 0.5)?;
            let length = number_of(ctx, s, "length", 1.0)?;
            positive(ctx, s, &[radius, length])?;
            Ok(if s.has_tag_name("cylinder") {
                Shape::Cylinder { radius, length }
            } else {
                Shape::Capsule { radius, length }
            })
        }
        "sphere" => {
            let radius = number_of(ctx, s, "radius", 1.0)?;
            positive(ctx, s, &[radius])?;
            Ok(Shape::Sphere(radius))
        }
        "mesh" => {
            if let Some(sub) = child(s, "submesh") {
                return Err(ctx.issue(
                    sub,
                    "a <submesh> is not read: export that part of the mesh as its own file",
                ));
            }
            let scale = match child(s, "scale") {
                Some(n) => {
                    let v = numbers(ctx, n, &[3])?;
                    [v[0], v[1], v[2]]
                }
                None => [1.0; 3],
            };
            Ok(Shape::Mesh {
                file: uri_of(ctx, s)?,
                scale,
            })
        }
        "plane" => {
            let normal = match child(s, "normal") {
                Some(n) => {
                    let v = numbers(ctx, n, &[3])?;
                    DVec3::new(v[0], v[1], v[2])
                        .try_normalize()
                        .ok_or_else(|| ctx.issue(n, "the normal is zero"))?
                }
                None => DVec3::Z,
            };
            Ok(Shape::Plane(normal))
        }
        "heightmap" => {
            let file = PathBuf::from(uri_of(ctx, s)?);
            let three = |tag: &str, default: [f64; 3]| -> Result<[f64; 3], SpecIssue> {
                match child(s, tag) {
                    Some(n) => numbers(ctx, n, &[3]).map(|v| [v[0], v[1], v[2]]),
                    None => Ok(default),
                }
            };
            let size = three("size", [1.0; 3])?;
            positive(ctx, s, &size)?;
            Ok(Shape::Heightmap {
                file,
                size,
                pos: three("pos", [0.0; 3])?,
            })
        }
        "empty" => Ok(Shape::Empty),
        other => Err(ctx.issue(
            s,
            format!(
                "<{other}> is not read (tracksim reads box, cylinder, sphere, capsule, mesh, \
                 plane, heightmap): replace it with a mesh"
            ),
        )),
    }
}
