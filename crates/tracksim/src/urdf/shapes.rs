//! A link's `<collision>` elements as tracksim collision shapes in the chassis frame: boxes
//! (kept as boxes when axis-aligned, else as the hull of their corners), cylinders, spheres,
//! and meshes as their convex hull. Capsules (URDF 1.2) are refused with what to use instead.

use super::ImportedLink;
use super::mesh::MeshCache;
use super::pose::{finite_pose, pose};
use super::source::{UrdfSource, key};
use crate::error::SpecIssue;
use crate::geometry::CollisionShape;
use glam::{DAffine3, DMat3, DQuat, DVec3};

fn positive(v: f64) -> bool {
    let (lo, hi) = crate::check::unit_range("m");
    v.is_finite() && v >= lo && v <= hi
}

/// One `<collision>` geometry at `frame` (chassis frame).
fn shape(
    dir: &std::path::Path,
    g: &urdf_rs::Geometry,
    frame: DAffine3,
    meshes: &mut MeshCache,
) -> Result<CollisionShape, String> {
    match g {
        urdf_rs::Geometry::Box { size } => {
            if !size.iter().all(|v| positive(*v)) {
                return Err(format!(
                    "<box size> must be three lengths > 0, m; got {:?}",
                    size.0
                ));
            }
            let half = DVec3::from_array(size.0) * 0.5;
            if frame.matrix3 == DMat3::IDENTITY {
                return Ok(CollisionShape::Box {
                    half,
                    centre: frame.translation,
                });
            }
            let corners: Vec<DVec3> = (0..8)
                .map(|k| {
                    let s = DVec3::new(
                        if k & 1 == 0 { -1.0 } else { 1.0 },
                        if k & 2 == 0 { -1.0 } else { 1.0 },
                        if k & 4 == 0 { -1.0 } else { 1.0 },
                    );
                    frame.transform_point3(half * s)
                })
                .collect();
            Ok(CollisionShape::Convex(corners))
        }
        urdf_rs::Geometry::Cylinder { radius, length } => {
            if !(positive(*radius) && positive(*length)) {
                return Err(format!(
                    "<cylinder radius=\"{radius}\" length=\"{length}\"> must have both > 0, m"
                ));
            }
            Ok(CollisionShape::Cylinder {
                radius: *radius,
                half_length: length / 2.0,
                centre: frame.translation,
                rotation: DQuat::from_mat3(&frame.matrix3),
            })
        }
        urdf_rs::Geometry::Sphere { radius } => {
            if !positive(*radius) {
                return Err(format!("<sphere radius=\"{radius}\"> must be > 0, m"));
            }
            Ok(CollisionShape::Sphere {
                radius: *radius,
                centre: frame.translation,
            })
        }
        urdf_rs::Geometry::Capsule { .. } => {
            Err("<capsule> is not supported; use a cylinder with two spheres, or a mesh".into())
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map_or([1.0; 3], |s| s.0);
            if !scale.iter().all(|v| v.is_finite() && *v != 0.0) {
                return Err(format!(
                    "<mesh scale> must be finite and non-zero; got {scale:?}"
                ));
            }
            let hull = meshes.hull(dir, filename, scale)?;
            // A rigid motion keeps a hull a hull: its vertices are placed, not hulled again.
            let placed: Vec<DVec3> = hull.iter().map(|p| frame.transform_point3(*p)).collect();
            Ok(CollisionShape::Convex(placed))
        }
    }
}

/// Reads the collision shapes of link `l` (frames already known).
pub(super) fn link_shapes(
    src: &UrdfSource,
    l: &mut ImportedLink,
    meshes: &mut MeshCache,
    issues: &mut Vec<SpecIssue>,
) {
    let Some(u) = src.robot.links.iter().find(|k| k.name == l.name) else {
        return;
    };
    let dir = src.path.parent().unwrap_or(std::path::Path::new("."));
    for (i, c) in u.collision.iter().enumerate() {
        let at = key(&format!("{} <collision> {}", src.link(&l.name), i + 1));
        if !finite_pose(&c.origin) {
            issues.push(SpecIssue::new(
                &at,
                "its <origin> has a number that is not finite",
            ));
            continue;
        }
        let frame = l.pose * pose(&c.origin);
        if let Some(m) = super::pose::too_far(frame) {
            issues.push(SpecIssue::new(&at, m));
            continue;
        }
        match shape(dir, &c.geometry, frame, meshes) {
            Ok(s) => l.shapes.push(s),
            Err(m) => issues.push(SpecIssue::new(&at, m)),
        }
    }
}
