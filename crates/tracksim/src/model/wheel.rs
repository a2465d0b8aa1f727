//! A lugged wheel (paper Fig. 8): a rim circle with lugs (grousers) standing on it, compiled
//! to the paper's form, one full-circle segment link rolled back by one lug pitch.
//!
//! The track path of a wheel is its *rolling circle*, not its rim: on flat ground a lugged
//! wheel rolls on the tips of its lugs like a polygon, and advances per revolution by the
//! perimeter of the convex hull of its outline. The path is the circle of that perimeter
//! (radius [`rolling_radius`]), so a belt speed `v` turns the wheel at `v / r_roll` and it
//! rolls at `v`; the lugs are moved inwards by the difference so they stand on the rim, and
//! the rim's collider is the path circle less that inset (`TrackModel::rim_inset`).

use super::{GrouserModel, GrouserShape};
use glam::DVec2;
use std::f64::consts::TAU;

/// Directions of the quadrature of the support function in [`rolling_radius`]. The support
/// function of a polygon is continuous and piecewise sinusoidal, so the midpoint rule's error
/// is below `r (2 pi / n)^2` = 2.4e-6 r: 0.24 um for a 0.1 m wheel.
const SUPPORT_DIRECTIONS: usize = 4096;

/// The outline points of lug shape `s` in its footprint frame's x (along) and z (out), m.
fn outline(s: &GrouserShape) -> Vec<DVec2> {
    match s {
        GrouserShape::Box { half, centre } => [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
            .iter()
            .map(|(sx, sz)| DVec2::new(centre.x + sx * half.x, centre.z + sz * half.z))
            .collect(),
        GrouserShape::Convex(p) => p.iter().map(|p| DVec2::new(p.x, p.z)).collect(),
    }
}

/// Rolling radius of a wheel of rim radius `rim` m with the lugs of `g` standing on the rim
/// (footprint z = 0 on the rim), m: the perimeter of the convex hull of the wheel's outline
/// over 2 pi, which is the mean of its support function over all directions (Cauchy's
/// formula). Without lugs it is the rim radius.
pub fn rolling_radius(rim: f64, g: Option<&GrouserModel>) -> f64 {
    // No lugs, or none to lay out (`grousers.shapes = []`, `count = 0`: refused by the
    // track's checks with their keys, which run beside this; issue 65: it divided by zero).
    let Some(g) = g.filter(|g| !g.shapes.is_empty() && g.layout.count > 0) else {
        return rim;
    };
    let pitch = TAU / g.layout.count as f64;
    // Every lug's outline in the wheel plane (any fixed in-plane basis and the layout's offset,
    // a rotation of the whole pattern: the hull's perimeter depends on neither).
    let mut pts = Vec::new();
    for k in 0..g.layout.count {
        let a = k as f64 * pitch;
        let radial = DVec2::new(a.cos(), a.sin());
        let tangent = DVec2::new(-a.sin(), a.cos());
        for p in outline(&g.shapes[k % g.shapes.len()]) {
            pts.push(radial * (rim + p.y) + tangent * p.x);
        }
    }
    let n = SUPPORT_DIRECTIONS;
    let sum: f64 = (0..n)
        .map(|i| {
            let t = TAU * (i as f64 + 0.5) / n as f64;
            let u = DVec2::new(t.cos(), t.sin());
            pts.iter().map(|p| p.dot(u)).fold(rim, f64::max)
        })
        .sum();
    sum / n as f64
}

/// Moves the lugs of `g` inwards by `inset` m: from standing on the rim to their place in the
/// footprint frame of the rolling circle.
pub(super) fn inset_lugs(g: &mut GrouserModel, inset: f64) {
    for s in &mut g.shapes {
        match s {
            GrouserShape::Box { centre, .. } => centre.z -= inset,
            GrouserShape::Convex(p) => p.iter_mut().for_each(|q| q.z -= inset),
        }
    }
    g.height -= inset;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GrouserLayout;
    use glam::DVec3;

    /// Thin plates (zero thickness in the limit) on a rim: the outline is the regular N-gon of
    /// the tips, whose perimeter is 2 N R sin(pi / N).
    #[test]
    fn plates_roll_on_the_polygon_of_their_tips() {
        let (rim, h, n) = (0.1, 0.03, 12);
        let g = GrouserModel {
            layout: GrouserLayout {
                count: n,
                offset: 0.0,
            },
            shapes: vec![GrouserShape::Box {
                half: DVec3::new(1e-9, 0.05, h / 2.0),
                centre: DVec3::new(0.0, 0.0, h / 2.0),
            }],
            height: h,
        };
        let big = rim + h;
        let want = n as f64 * 2.0 * big * (std::f64::consts::PI / n as f64).sin() / TAU;
        let got = rolling_radius(rim, Some(&g));
        // Quadrature error bound of SUPPORT_DIRECTIONS (module doc): 2.4e-6 r.
        assert!((got - want).abs() < 2.4e-6 * big, "{got} vs {want}");
        assert_eq!(rolling_radius(rim, None), rim);
    }
}
