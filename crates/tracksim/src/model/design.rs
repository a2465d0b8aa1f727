//! What a designer needs to see before running (issue 11.3), from the compiled vehicle alone:
//! per track the loop length, grouser pitch, grouser length and the gap between grousers; the
//! ground clearance and approach angle of the chassis; and warnings (not errors) about what is probably a mistake:
//! overlapping grousers, a body reaching past the tracks, a centre of mass outside the tracks'
//! footprint. `tracksim check` prints it.

use super::{GrouserShape, Parent, TrackModel, VehicleModel};
use crate::geometry::Segment;
use glam::DVec3;
use serde::Serialize;

/// One track's layout, m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackDesign {
    /// Track name.
    pub name: String,
    /// Loop length L, m.
    pub loop_length_m: f64,
    /// Number of grousers N (0 without).
    pub grousers: usize,
    /// Grouser pitch L / N, m (None without grousers).
    pub pitch_m: Option<f64>,
    /// Longest grouser footprint along the belt, m.
    pub grouser_length_m: Option<f64>,
    /// Pitch minus grouser length: free belt between grousers, m (negative: they overlap).
    pub gap_m: Option<f64>,
}

/// The design figures of a vehicle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignReport {
    /// Every track.
    pub tracks: Vec<TrackDesign>,
    /// Height of the chassis's lowest point above the lowest point of the tracks on it (grouser
    /// tips included), m, in the body frame at rest.
    pub ground_clearance_m: Option<f64>,
    /// Approach angle, deg: the steepest ramp the body-mounted tracks meet before the chassis
    /// does (SAE J1100's definition with the tracks as the tyres: the largest angle of a plane
    /// tangent to the front of the tracks' side profile, grouser tips included, that no corner
    /// of the chassis crosses); 90 when the chassis never meets a ramp first. Flippers are
    /// not counted (their angle changes it).
    pub approach_angle_deg: Option<f64>,
    /// Probable mistakes, in words.
    pub warnings: Vec<String>,
}

/// Longest extent along the belt (x of the footprint frame) of a grouser shape, m.
fn grouser_length(s: &GrouserShape) -> f64 {
    match s {
        GrouserShape::Box { half, .. } => 2.0 * half.x,
        GrouserShape::Convex(pts) => {
            let (lo, hi) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                (lo.min(p.x), hi.max(p.x))
            });
            hi - lo
        }
    }
}

/// Points of a loop, parent frame, every 1 cm or so.
fn loop_points(t: &TrackModel) -> Vec<DVec3> {
    let l = t.path.length();
    let n = ((l / 0.01).ceil() as usize).clamp(16, 10_000);
    (0..n)
        .map(|i| t.path.frame_at(l * i as f64 / n as f64).origin)
        .collect()
}

fn track_design(t: &TrackModel, warnings: &mut Vec<String>) -> TrackDesign {
    let l = t.path.length();
    let n = t.grousers.as_ref().map(|g| g.layout.count).unwrap_or(0);
    let pitch = (n > 0).then(|| l / n as f64);
    let length = t
        .grousers
        .as_ref()
        .map(|g| g.shapes.iter().map(grouser_length).fold(0.0, f64::max));
    let gap = pitch.zip(length).map(|(p, g)| p - g);
    if let (Some(gap), Some(p), Some(g)) = (gap, pitch, length)
        && gap <= 0.0
    {
        warnings.push(format!(
            "track {}: its {n} grousers overlap: pitch {:.1} mm is not more than the grouser length {:.1} mm (fewer grousers?)",
            t.name,
            p * 1000.0,
            g * 1000.0
        ));
    }
    TrackDesign {
        name: t.name.clone(),
        loop_length_m: l,
        grousers: n,
        pitch_m: pitch,
        grouser_length_m: length,
        gap_m: gap,
    }
}

/// The design report of `v`.
pub fn design_report(v: &VehicleModel) -> DesignReport {
    let mut warnings = Vec::new();
    let tracks = v
        .tracks
        .iter()
        .map(|t| track_design(t, &mut warnings))
        .collect();
    let on_body: Vec<&TrackModel> = v
        .tracks
        .iter()
        .filter(|t| t.parent == Parent::Body)
        .collect();
    let (lo, hi) = v.body.shape.bounds();
    let mut ground_clearance = None;
    let mut approach = None;
    if !on_body.is_empty() {
        let pts: Vec<(DVec3, f64)> = on_body
            .iter()
            .flat_map(|t| {
                let g = t.grousers.as_ref().map(|g| g.height).unwrap_or(0.0);
                loop_points(t).into_iter().map(move |p| (p, g))
            })
            .collect();
        let bottom = pts.iter().map(|(p, g)| p.z - g).fold(f64::MAX, f64::min);
        ground_clearance = Some(lo.z - bottom);
        approach = Some(approach_angle(&pts, lo, hi).to_degrees());
        let front = pts.iter().map(|(p, g)| p.x + g).fold(f64::MIN, f64::max);
        let rear = pts.iter().map(|(p, g)| p.x - g).fold(f64::MAX, f64::min);
        if hi.x > front + 1e-6 {
            warnings.push(format!(
                "the body reaches {:.1} mm past the front of the tracks: it meets a step before they do",
                (hi.x - front) * 1000.0
            ));
        }
        if lo.x < rear - 1e-6 {
            warnings.push(format!(
                "the body reaches {:.1} mm past the rear of the tracks",
                (rear - lo.x) * 1000.0
            ));
        }
        if lo.z < bottom - 1e-6 {
            warnings.push(format!(
                "the body hangs {:.1} mm below the bottoms of its tracks (grouser tips): it rests \
                 on the ground, not on its tracks (raise the body or lower the pulleys)",
                (bottom - lo.z) * 1000.0
            ));
        }
        for t in &on_body {
            track_inside_body(t, lo, hi, &mut warnings);
        }
        com_inside_footprint(v, &on_body, &mut warnings);
    }
    DesignReport {
        tracks,
        ground_clearance_m: ground_clearance,
        approach_angle_deg: approach,
        warnings,
    }
}

/// Approach angle, rad, of the track profile `pts` (loop points and grouser heights, body
/// frame) against the chassis box `lo..hi`: bisection on the angle `a` of a plane rising
/// forward, tangent to the tracks' profile from below the front; the chassis meets the ramp
/// first when one of its (x, z) corners lies beyond that plane.
/// Warns when the belt of track `t` (on the chassis) runs through the chassis's box
/// `lo`..`hi`: its band (plane y +- width / 2) overlaps the body's width and part of its loop
/// lies inside the body's side view. Colliders of one vehicle never collide, so such a belt
/// runs through the body silently (issue 23.7). A body filling the space inside a loop, as
/// Quince's does, is not warned about.
fn track_inside_body(t: &TrackModel, lo: DVec3, hi: DVec3, warnings: &mut Vec<String>) {
    let pts = loop_points(t);
    let (y_lo, y_hi) = pts.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.y - t.width / 2.0), b.max(p.y + t.width / 2.0))
    });
    let overlap_y = y_hi.min(hi.y) - y_lo.max(lo.y);
    let inside = pts
        .iter()
        .filter(|p| p.x > lo.x && p.x < hi.x && p.z > lo.z && p.z < hi.z)
        .count();
    if overlap_y > 1e-6 && inside > 0 {
        warnings.push(format!(
            "track {} runs inside the body: its belt (y {:.3} to {:.3} m) overlaps the body's \
             width (y {:.3} to {:.3} m) by {:.1} mm and {:.0} % of its loop lies within the \
             body's side view (one vehicle's parts do not collide: move the track outwards)",
            t.name,
            y_lo,
            y_hi,
            lo.y,
            hi.y,
            overlap_y * 1000.0,
            100.0 * inside as f64 / pts.len() as f64
        ));
    }
}

fn approach_angle(pts: &[(DVec3, f64)], lo: DVec3, hi: DVec3) -> f64 {
    let n = pts.len().max(1) as f64;
    let (cx, cz) = pts
        .iter()
        .fold((0.0, 0.0), |(x, z), (p, _)| (x + p.x / n, z + p.z / n));
    // Each loop point pushed out by its grouser height, away from the profile's centre.
    let profile: Vec<(f64, f64)> = pts
        .iter()
        .map(|(p, g)| {
            let (dx, dz) = (p.x - cx, p.z - cz);
            let r = dx.hypot(dz).max(1e-12);
            (p.x + g * dx / r, p.z + g * dz / r)
        })
        .collect();
    let corners = [(lo.x, lo.z), (lo.x, hi.z), (hi.x, lo.z), (hi.x, hi.z)];
    // Signed height above the plane of angle `a` (normal (-sin a, cos a)).
    let h = |a: f64, (x, z): (f64, f64)| z * a.cos() - x * a.sin();
    let crosses = |a: f64| {
        let plane = profile.iter().map(|&p| h(a, p)).fold(f64::MAX, f64::min);
        corners.iter().any(|&c| h(a, c) < plane - 1e-9)
    };
    let (mut ok, mut bad) = (0.0, std::f64::consts::FRAC_PI_2);
    if !crosses(bad) {
        return bad;
    }
    for _ in 0..50 {
        let mid = 0.5 * (ok + bad);
        if crosses(mid) { bad = mid } else { ok = mid }
    }
    ok
}

/// Warns when the chassis's centre of mass lies outside the footprint of its tracks' lower runs.
fn com_inside_footprint(v: &VehicleModel, on_body: &[&TrackModel], warnings: &mut Vec<String>) {
    let mut x = (f64::MAX, f64::MIN);
    let mut y = (f64::MAX, f64::MIN);
    for t in on_body {
        let lowest = t
            .path
            .segments()
            .iter()
            .filter(|s| matches!(s, Segment::Straight { .. }))
            .min_by(|a, b| a.start().z.total_cmp(&b.start().z));
        if let Some(s) = lowest {
            let (a, b) = (s.start(), s.point_tangent(s.length()).0);
            x = (x.0.min(a.x.min(b.x)), x.1.max(a.x.max(b.x)));
        }
        let c = t.lateral_offset();
        y = (y.0.min(c - t.width / 2.0), y.1.max(c + t.width / 2.0));
    }
    let c = v.body.com;
    if x.0 <= x.1 && (c.x < x.0 || c.x > x.1 || c.y < y.0 || c.y > y.1) {
        warnings.push(format!(
            "the body's centre of mass ({:.3}, {:.3}) m is outside the tracks' footprint x {:.3}..{:.3}, y {:.3}..{:.3} m: it tips over at rest",
            c.x, c.y, x.0, x.1, y.0, y.1
        ));
    }
}

impl DesignReport {
    /// The figures as lines of text (millimetres and degrees for reading), warnings last.
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        for t in &self.tracks {
            let mut l = format!("track {:<16} loop {:.4} m", t.name, t.loop_length_m);
            if let (Some(p), Some(g), Some(gap)) = (t.pitch_m, t.grouser_length_m, t.gap_m) {
                l.push_str(&format!(
                    ", {} grousers: pitch {:.1} mm, grouser {:.1} mm, gap {:.1} mm",
                    t.grousers,
                    p * 1000.0,
                    g * 1000.0,
                    gap * 1000.0
                ));
            }
            out.push(l);
        }
        if let Some(c) = self.ground_clearance_m {
            let how = if c >= 0.0 {
                "body above the track bottoms"
            } else {
                "the body hangs BELOW the track bottoms: see the warning"
            };
            out.push(format!("ground clearance {:.1} mm ({how})", c * 1000.0));
        }
        if let Some(a) = self.approach_angle_deg {
            out.push(format!(
                "approach angle {a:.1} deg (steepest ramp the tracks meet before the body)"
            ));
        }
        out.extend(self.warnings.iter().map(|w| format!("warning: {w}")));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn approach_angle_of_a_flat_run_under_an_overhanging_body() {
        // Tracks: a flat run z = 0 from x = -0.3 to 0.3 m. Chassis corner at x = 0.5, z = 0.1:
        // a ramp from the run's front end (0.3, 0) reaches it at tan a = 0.1 / 0.2.
        let pts: Vec<(DVec3, f64)> = (0..=60)
            .map(|i| (DVec3::new(-0.3 + 0.01 * i as f64, 0.0, 0.0), 0.0))
            .collect();
        let a = approach_angle(&pts, DVec3::new(-0.2, -0.1, 0.1), DVec3::new(0.5, 0.1, 0.3));
        assert!(
            (a.to_degrees() - 0.5f64.atan().to_degrees()).abs() < 1e-6,
            "{}",
            a.to_degrees()
        );
        // A chassis behind the run's front never meets the ramp first.
        let a = approach_angle(&pts, DVec3::new(-0.2, -0.1, 0.1), DVec3::new(0.2, 0.1, 0.3));
        assert_eq!(a, std::f64::consts::FRAC_PI_2);
    }
}
