//! Exact ray tests of the two shapes most terrains are made of, in their own frame: a box
//! ([`ray_box`], half extents) and a cylinder along y ([`ray_cylinder`], Rapier's). Parry
//! answers these through its generic paths (a clipped segment for boxes, GJK for cylinders);
//! these closed forms give the same hits (tested against parry) at a fraction of the cost, and
//! every other shape goes to parry. Solid: a ray starting inside hits at 0.

use glam::Vec3;

/// Ray `o + s * d`, `0 <= s <= max`, against the box `-half..half`: time of impact and outward
/// normal.
pub fn ray_box(half: Vec3, o: Vec3, d: Vec3, max: f32) -> Option<(f32, Vec3)> {
    // Slabs on all three axes at once; a zero direction component gives +-inf (or NaN for a
    // ray in a face's plane, which f32::max/min pass over: inside that slab).
    let inv = d.recip();
    let t0 = (-half - o) * inv;
    let t1 = (half - o) * inv;
    let near = t0.min(t1);
    let far = t0.max(t1);
    let exit = far.x.min(far.y).min(far.z).min(max);
    let enter = near.x.max(near.y).max(near.z);
    if enter > exit || exit < 0.0 {
        return None;
    }
    // A ray parallel to a slab and outside it: its near and far are both +inf or both -inf.
    if (0..3).any(|k| d[k] == 0.0 && (o[k] < -half[k] || o[k] > half[k])) {
        return None;
    }
    if enter <= 0.0 {
        // Inside at the start: the surface facing the ray.
        return Some((0.0, -d.normalize_or_zero()));
    }
    let k = if enter == near.x {
        0
    } else if enter == near.y {
        1
    } else {
        2
    };
    let mut n = Vec3::ZERO;
    n[k] = -d[k].signum();
    Some((enter, n))
}

/// Ray `o + s * d`, `0 <= s <= max`, against the cylinder of axis y, `|y| <= half_height`,
/// `x^2 + z^2 <= radius^2`: time of impact and outward normal.
pub fn ray_cylinder(
    half_height: f32,
    radius: f32,
    o: Vec3,
    d: Vec3,
    max: f32,
) -> Option<(f32, Vec3)> {
    let r2 = radius * radius;
    let inside_side = o.x * o.x + o.z * o.z <= r2;
    if inside_side && o.y.abs() <= half_height {
        return Some((0.0, -d.normalize_or_zero()));
    }
    let mut best: Option<(f32, Vec3)> = None;
    let mut keep = |t: f32, n: Vec3| {
        if (0.0..=max).contains(&t) && best.is_none_or(|b| t < b.0) {
            best = Some((t, n));
        }
    };
    // The side: (ox + s dx)^2 + (oz + s dz)^2 = r^2.
    let a = d.x * d.x + d.z * d.z;
    if a > 0.0 {
        let b = o.x * d.x + o.z * d.z;
        let c = o.x * o.x + o.z * o.z - r2;
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let t = (-b - disc.sqrt()) / a;
            let p = o + d * t;
            if p.y.abs() <= half_height {
                keep(t, Vec3::new(p.x, 0.0, p.z) / radius);
            }
        }
    }
    // The caps.
    if d.y != 0.0 {
        for (y, ny) in [(half_height, 1.0), (-half_height, -1.0)] {
            let t = (y - o.y) / d.y;
            let p = o + d * t;
            if p.x * p.x + p.z * p.z <= r2 && d.y * ny < 0.0 {
                keep(t, Vec3::new(0.0, ny, 0.0));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::parry::query::{Ray, RayCast};
    use rapier3d::parry::shape::{Cuboid, Cylinder};

    /// Rays from a grid of origins in many directions give parry's hits (time within 1e-4 of
    /// the ray's length, the same normal where the hit is not on an edge).
    #[test]
    fn closed_forms_agree_with_parry() {
        let cuboid = Cuboid::new(Vec3::new(0.5, 0.2, 0.3));
        let cylinder = Cylinder::new(0.4, 0.15);
        let mut n = 0;
        for i in 0..7 {
            for j in 0..7 {
                for k in 0..5 {
                    let o = Vec3::new(i as f32 - 3.0, (j as f32 - 3.0) * 0.7, k as f32 - 2.0);
                    for (a, b) in [(0.3f32, 0.2f32), (1.9, -0.4), (3.7, 0.9), (5.1, -1.2)] {
                        let d = -o + Vec3::new(a.cos(), b.sin(), a.sin()) * 0.3;
                        let ray = Ray::new(o, d);
                        let want = cuboid.cast_local_ray_and_get_normal(&ray, 10.0, true);
                        let got = ray_box(cuboid.half_extents, o, d, 10.0);
                        assert_eq!(want.is_some(), got.is_some(), "box {o} {d}");
                        if let (Some(w), Some(g)) = (want, got) {
                            assert!((w.time_of_impact - g.0).abs() < 1e-4 * d.length());
                            n += 1;
                        }
                        let want = cylinder.cast_local_ray_and_get_normal(&ray, 10.0, true);
                        let got = ray_cylinder(0.4, 0.15, o, d, 10.0);
                        if want.is_some() != got.is_some() {
                            // Parry's GJK answers within a tolerance: a grazing ray must then
                            // be decided the other way by a cylinder 1 % larger or smaller.
                            let f = if want.is_some() { 1.01 } else { 0.99 };
                            let near = ray_cylinder(0.4 * f, 0.15 * f, o, d, 10.0);
                            assert_eq!(want.is_some(), near.is_some(), "cylinder {o} {d}");
                            continue;
                        }
                        if let (Some(w), Some(g)) = (want, got) {
                            assert!(
                                (w.time_of_impact - g.0).abs() < 1e-3 * d.length(),
                                "cylinder {o} {d}: {} against {}",
                                g.0,
                                w.time_of_impact
                            );
                            // Normals away from the rim (where parry's GJK blends them).
                            let p = o + d * g.0;
                            let off_rim = (p.x * p.x + p.z * p.z).sqrt() < 0.95 * 0.15
                                || p.y.abs() < 0.95 * 0.4;
                            if w.time_of_impact > 0.0 && off_rim {
                                assert!(w.normal.dot(g.1) > 0.99, "{} {}", w.normal, g.1);
                            }
                        }
                    }
                }
            }
        }
        assert!(n > 100, "{n} hits compared");
    }
}
