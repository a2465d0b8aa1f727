//! A belt wrapped around pulleys ([`Pulley`], [`TrackPath::from_pulleys`]): the loop in a
//! canonical order (from the rearmost pulley), the pulleys it does not wrap named.

use super::{JOIN_TOLERANCE_M, PathError, Segment, TANGENT_TOLERANCE_RAD, TrackPath};
use glam::DVec3;
use std::f64::consts::TAU;

/// A pulley around which the belt wraps, in the track frame's x-z plane, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulley {
    /// Centre, x (forward), m.
    pub x: f64,
    /// Centre, z (up), m.
    pub z: f64,
    /// Radius of the belt's outer surface around this pulley (where grouser footprints lie), m.
    pub radius: f64,
}

/// The pulleys of a loop (`order`: clockwise, at least 3) that the belt does not wrap, given
/// the arc `wraps[k]` on pulley `order[k + 1]` (rad, in [0, 2 pi)): an arc within
/// [`TANGENT_TOLERANCE_RAD`] of none or of a full turn (the belt runs straight past the pulley,
/// or bends backwards by that little), then, when the arcs do not add up to one turn, the
/// pulleys with the largest arcs (each a backward bend wrapped to nearly a full turn), one
/// per extra turn.
fn unwrapped_pulleys(pulleys: &[Pulley], order: &[usize], wraps: &[f64]) -> Vec<PathError> {
    let n = order.len();
    if n < 3 {
        return Vec::new();
    }
    let error = |k: usize| {
        let (i, j, l) = (order[k], order[(k + 1) % n], order[(k + 2) % n]);
        let (a, b, c) = (pulleys[i], pulleys[j], pulleys[l]);
        let (ux, uz) = (c.x - a.x, c.z - a.z);
        let len = ux.hypot(uz);
        let off = ((b.x - a.x) * uz - (b.z - a.z) * ux).abs() / len.max(1e-300);
        let t = ((b.x - a.x) * ux + (b.z - a.z) * uz) / (len * len).max(1e-300);
        PathError::PulleyNotWrapped {
            pulley: j,
            before: i,
            after: l,
            collinear: off <= JOIN_TOLERANCE_M && (0.0..=1.0).contains(&t),
        }
    };
    let flat: Vec<PathError> = (0..n)
        .filter(|k| wraps[*k] < TANGENT_TOLERANCE_RAD || wraps[*k] > TAU - TANGENT_TOLERANCE_RAD)
        .map(error)
        .collect();
    if !flat.is_empty() {
        return flat;
    }
    let total: f64 = wraps.iter().sum();
    let extra = ((total - TAU) / TAU).round();
    if (total - TAU).abs() <= TANGENT_TOLERANCE_RAD * n as f64 || extra < 1.0 {
        return Vec::new();
    }
    let mut by_size: Vec<usize> = (0..n).collect();
    by_size.sort_by(|a, b| wraps[*b].total_cmp(&wraps[*a]));
    let mut worst: Vec<usize> = by_size.into_iter().take(extra as usize).collect();
    worst.sort_by_key(|k| order[(k + 1) % n]);
    worst.into_iter().map(error).collect()
}

impl TrackPath {
    /// Builds the belt that wraps the given pulleys on their outside, in the plane y = `plane_y`
    /// of the track frame. Pulleys may be listed in either sense around the loop; the loop is
    /// always traversed so that a positive belt speed moves the lower run backwards (-x), i.e.
    /// drives the vehicle forwards, turning about +y. Segment 0 is the straight leaving the
    /// rearmost pulley (smallest x, then smallest z), followed by the arc on the next pulley in
    /// that sense, and so on: rotating or reversing the list gives the same path.
    pub fn from_pulleys(pulleys: &[Pulley], plane_y: f64) -> Result<Self, Vec<PathError>> {
        let n = pulleys.len();
        if n < 2 {
            return Err(vec![PathError::TooFewPulleys(n)]);
        }
        let mut errors: Vec<PathError> = pulleys
            .iter()
            .enumerate()
            .filter(|(_, p)| {
                !(p.radius > 0.0 && p.radius.is_finite() && p.x.is_finite() && p.z.is_finite())
            })
            .map(|(i, p)| PathError::BadPulley {
                pulley: i,
                radius: p.radius,
            })
            .collect();
        if !errors.is_empty() {
            return Err(errors);
        }
        // One pulley inside another (or the same centre), wherever they are in the list.
        for i in 0..n {
            for j in i + 1..n {
                let (a, b) = (pulleys[i], pulleys[j]);
                let dist = (b.x - a.x).hypot(b.z - a.z);
                if dist <= (a.radius - b.radius).abs() + 1e-9 {
                    errors.push(PathError::PulleysOverlap {
                        pulley: i,
                        next: j,
                        distance: dist,
                    });
                }
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // Order the pulleys clockwise in the (x right, z up) picture, which is positive rotation
        // about +y. Keep the user's indices for messages.
        let mut order: Vec<usize> = (0..n).collect();
        let area2: f64 = (0..n)
            .map(|i| {
                let (a, b) = (pulleys[i], pulleys[(i + 1) % n]);
                a.x * b.z - b.x * a.z
            })
            .sum();
        if area2 > 0.0 {
            order.reverse();
        }
        // Start at the rearmost pulley (smallest x, then smallest z), whatever the list's first
        // entry: the loop, its segments' order and the grousers' places (grouser 0 at the loop
        // start) then depend on the pulleys only, never on the order they are listed in.
        let first = (0..n)
            .min_by(|&a, &b| {
                let (pa, pb) = (pulleys[order[a]], pulleys[order[b]]);
                pa.x.total_cmp(&pb.x).then(pa.z.total_cmp(&pb.z))
            })
            .unwrap_or(0);
        order.rotate_left(first);
        // Outer tangent between consecutive pulleys: normal n with n.(c2 - c1) = r1 - r2.
        let mut normals = Vec::with_capacity(n);
        let mut errors = Vec::new();
        for k in 0..n {
            let (i, j) = (order[k], order[(k + 1) % n]);
            let (p1, p2) = (pulleys[i], pulleys[j]);
            let d = (p2.x - p1.x, p2.z - p1.z);
            let dist = (d.0 * d.0 + d.1 * d.1).sqrt();
            let dr = p1.radius - p2.radius;
            if dist <= dr.abs() + 1e-9 {
                errors.push(PathError::PulleysOverlap {
                    pulley: i,
                    next: j,
                    distance: dist,
                });
                normals.push((0.0, 0.0));
                continue;
            }
            let u = (d.0 / dist, d.1 / dist);
            let left = (-u.1, u.0);
            let sa = dr / dist;
            let ca = (1.0 - sa * sa).sqrt();
            normals.push((ca * left.0 + sa * u.0, ca * left.1 + sa * u.1));
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // The arc on pulley order[k + 1], from normal k to the next straight's normal,
        // clockwise in (x, z) = positive about +y.
        let wraps: Vec<f64> = (0..n)
            .map(|k| {
                let (nk, nn) = (normals[k], normals[(k + 1) % n]);
                let cross = nk.0 * nn.1 - nk.1 * nn.0;
                let dot = nk.0 * nn.0 + nk.1 * nn.1;
                let theta = -cross.atan2(dot);
                if theta < 0.0 { theta + TAU } else { theta }
            })
            .collect();
        let errors = unwrapped_pulleys(pulleys, &order, &wraps);
        if !errors.is_empty() {
            return Err(errors);
        }
        let p3 = |x: f64, z: f64| DVec3::new(x, plane_y, z);
        let mut segments = Vec::with_capacity(2 * n);
        for k in 0..n {
            let (i, j) = (order[k], order[(k + 1) % n]);
            let (p1, p2) = (pulleys[i], pulleys[j]);
            let nk = normals[k];
            let a = p3(p1.x + p1.radius * nk.0, p1.z + p1.radius * nk.1);
            let b = p3(p2.x + p2.radius * nk.0, p2.z + p2.radius * nk.1);
            segments.push(Segment::Straight {
                start: a,
                direction: (b - a).normalize(),
                length: (b - a).length(),
            });
            let theta = wraps[k];
            if theta > 1e-9 {
                segments.push(Segment::Arc {
                    start: b,
                    centre: p3(p2.x, p2.z),
                    axis: DVec3::Y,
                    angle: theta,
                });
            }
        }
        TrackPath::new(segments)
    }

    /// A full circle of `radius` m about the axis +y through (`x`, `plane_y`, `z`) (a wheel's
    /// rolling circle), starting at its lowest point, traversed so that a positive belt speed
    /// moves the bottom backwards (-x), i.e. rolls forwards.
    pub fn circle(x: f64, z: f64, radius: f64, plane_y: f64) -> Result<Self, Vec<PathError>> {
        if !(radius > 0.0 && radius.is_finite() && x.is_finite() && z.is_finite()) {
            return Err(vec![PathError::BadPulley { pulley: 0, radius }]);
        }
        let centre = DVec3::new(x, plane_y, z);
        TrackPath::new(vec![Segment::Arc {
            start: centre - DVec3::Z * radius,
            centre,
            axis: DVec3::Y,
            angle: TAU,
        }])
    }
}
