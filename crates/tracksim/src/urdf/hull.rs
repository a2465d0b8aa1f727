//! A mesh's convex hull (a vehicle part collides as its hull): the points checked for a volume
//! first (not all at one point, on a line or in a plane: parry's hull panicked on such input),
//! then hulled by parry behind a guard (`guard.rs`), its vertex count held to the TOML convex
//! shapes' bound ([`crate::check::MAX_HULL_POINTS`]).

use glam::DVec3;

/// Why `points` have no convex hull with a volume (all at one point, on a line, or in a
/// plane), or `None`: checked before parry is called, which can panic on such input. The
/// tolerance is relative to the points' extent (f32 rounding, 1e-5 of it) and at least
/// [`crate::check::MIN_LENGTH_M`].
fn degenerate(points: &[DVec3]) -> Option<&'static str> {
    let far = |from: &dyn Fn(DVec3) -> f64| {
        points
            .iter()
            .copied()
            .map(|p| (from(p), p))
            .fold((0.0, DVec3::ZERO), |a, b| if b.0 > a.0 { b } else { a })
    };
    let p0 = *points.first()?;
    let (d1, p1) = far(&|p| (p - p0).length());
    let tol = (1e-5 * d1).max(crate::check::MIN_LENGTH_M);
    if points.len() < 4 || d1 < tol {
        return Some("all its vertices are at one point");
    }
    let u = (p1 - p0) / d1;
    let (d2, p2) = far(&|p| (p - p0).reject_from_normalized(u).length());
    if d2 < tol {
        return Some("its vertices are on one line");
    }
    let n = u.cross(p2 - p0).normalize();
    let (d3, _) = far(&|p| (p - p0).dot(n).abs());
    (d3 < tol).then_some("its vertices are in one plane (flat)")
}

/// The convex hull's vertices of `points` (f32, as Rapier builds it), m; refused with `what`
/// (the file) named when the points have no hull with a volume.
pub(super) fn checked_hull(points: &[DVec3], what: &str) -> Result<Vec<DVec3>, String> {
    if let Some(why) = degenerate(points) {
        return Err(format!(
            "{what}: {why}, so it has no convex hull with a volume; a collision mesh must \
             enclose a volume (check the file and its <mesh scale>)"
        ));
    }
    let p: Vec<rapier3d::prelude::Vector> = points.iter().map(|v| crate::check::f(*v)).collect();
    // Guarded: parry can still panic on inputs near the degenerate ones checked above.
    let hull = super::guard::guarded(&format!("{what}: the convex hull"), || {
        rapier3d::parry::transformation::try_convex_hull(&p)
    })?;
    let max = crate::check::MAX_HULL_POINTS;
    match hull {
        Ok((verts, _)) if verts.len() > max => Err(format!(
            "{what}: its convex hull has {} vertices, more than the {max} of a convex shape \
             (the TOML files' bound); simplify the collision mesh (e.g. decimate it)",
            verts.len()
        )),
        Ok((verts, faces)) if !faces.is_empty() => Ok(verts
            .iter()
            .map(|v| DVec3::new(v.x as f64, v.y as f64, v.z as f64))
            .collect()),
        _ => Err(format!(
            "{what}: its points are coplanar or too close together: it has no convex hull"
        )),
    }
}
