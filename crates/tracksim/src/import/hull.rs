//! The convex hull of circles in a plane (pulleys in a track link's x-z plane): which circles
//! the belt wraps, in order around the loop.

use crate::geometry::Pulley;

/// Points sampled on each circle's rim: enough that two circles' tangent points are found
/// (a circle wholly inside the hull of the others contributes none).
const RIM_SAMPLES: usize = 720;

/// Andrew's monotone chain: the hull's vertices (counter-clockwise), each with its tag.
fn hull_2d(mut pts: Vec<(f64, f64, usize)>) -> Vec<(f64, f64, usize)> {
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: (f64, f64, usize), a: (f64, f64, usize), b: (f64, f64, usize)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut lower: Vec<(f64, f64, usize)> = Vec::new();
    for p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], *p) <= 0.0 {
            lower.pop();
        }
        lower.push(*p);
    }
    let mut upper: Vec<(f64, f64, usize)> = Vec::new();
    for p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], *p) <= 0.0 {
            upper.pop();
        }
        upper.push(*p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// The circles on the convex hull of `circles`, in order around it (counter-clockwise in the
/// x-z picture; tracksim's pulley paths take either sense). Circles inside the hull are left
/// out; duplicates (same centre and radius within 0.1 mm) count once.
pub fn circles_on_hull(circles: &[Pulley]) -> Vec<Pulley> {
    let mut unique: Vec<Pulley> = Vec::new();
    for c in circles {
        let same = |u: &Pulley| {
            (u.x - c.x).abs() < 1e-4
                && (u.z - c.z).abs() < 1e-4
                && (u.radius - c.radius).abs() < 1e-4
        };
        if !unique.iter().any(same) {
            unique.push(*c);
        }
    }
    if unique.len() < 2 {
        return unique;
    }
    let pts = unique
        .iter()
        .enumerate()
        .flat_map(|(i, c)| {
            (0..RIM_SAMPLES).map(move |k| {
                let a = std::f64::consts::TAU * k as f64 / RIM_SAMPLES as f64;
                (c.x + c.radius * a.cos(), c.z + c.radius * a.sin(), i)
            })
        })
        .collect();
    let mut order: Vec<usize> = Vec::new();
    for (_, _, i) in hull_2d(pts) {
        if order.last() != Some(&i) {
            order.push(i);
        }
    }
    while order.len() > 1 && order.first() == order.last() {
        order.pop();
    }
    // A circle met twice on the hull (possible only for degenerate sampling) counts once.
    let mut seen = std::collections::BTreeSet::new();
    order.retain(|i| seen.insert(*i));
    order.into_iter().map(|i| unique[i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_circle_inside_is_left_out_and_the_order_goes_round() {
        let p = |x, z, r| Pulley { x, z, radius: r };
        let got = circles_on_hull(&[p(0.0, 0.0, 0.1), p(0.5, 0.0, 0.1), p(0.25, 0.0, 0.05)]);
        assert_eq!(got.len(), 2);
        let tri = circles_on_hull(&[p(0.0, 0.0, 0.1), p(0.5, 0.0, 0.1), p(0.25, 0.4, 0.05)]);
        assert_eq!(tri.len(), 3);
    }
}
