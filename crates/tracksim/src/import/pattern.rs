//! The paper plugin's trajectory and pattern as a tracksim track: the arcs' centres and radii
//! are the pulleys (the straights join them tangentially), `<elements_per_round>` the grouser
//! count (pitch = perimeter / N), each `<element>` a grouser shape used in turn.

use super::continuous_track::{ContinuousTrackPlugin, PatternElement, PluginSegment};
use super::propose::{ProposedPath, ProposedTrack};
use crate::geometry::Pulley;
use crate::spec::{GrouserShapeSpec, GrouserSpec};
use crate::urdf::UrdfRobot;
use glam::DVec3;

/// Two cross-section points at the same height within this, m: a trapezoid's base.
const LEVEL_TOLERANCE_M: f64 = 1e-6;

/// The part of a convex element (its points, element frame: z out of the belt) outside the
/// path, z >= 0: the points there and where the segments between points cross z = 0 (their
/// hull is the clipped element). The whole element when nothing of it is outside.
fn outside_path(pts: &[DVec3]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = pts.iter().copied().filter(|p| p.z >= 0.0).collect();
    if out.len() == pts.len() || pts.iter().all(|p| p.z <= 0.0) {
        return pts.to_vec();
    }
    for (i, p) in pts.iter().enumerate() {
        for q in &pts[i + 1..] {
            if (p.z < 0.0) != (q.z < 0.0) {
                let t = p.z / (p.z - q.z);
                let mut c = *p + (*q - *p) * t;
                c.z = 0.0;
                out.push(c);
            }
        }
    }
    out
}

/// A pattern element as a grouser shape standing on the belt, with what was changed: the
/// plugin places an element about the path (the belt segments' outer face, in the paper's
/// example a box or a trapezoid centred on it, half inside the belt); tracksim's grouser stands
/// on the path, so the part outside it is the grouser.
fn grouser_shape(e: &PatternElement, width: f64) -> (GrouserShapeSpec, String) {
    let across = |w: f64| ((w - width).abs() > 1e-6).then_some(w);
    match e {
        PatternElement::Box([x, y, z]) => (
            GrouserShapeSpec::Box {
                length_m: *x,
                height_m: z / 2.0,
                width_m: across(*y),
                shift_m: 0.0,
            },
            format!(
                "box {x} x {y} x {z} m centred on the path (half inside the belt): a box grouser \
                 {x} m long standing {:.4} m out of the belt",
                z / 2.0
            ),
        ),
        PatternElement::Prism(all) => {
            let clipped = outside_path(all);
            let pts = &clipped;
            let lo = pts.iter().fold(DVec3::splat(f64::MAX), |a, p| a.min(*p));
            let hi = pts.iter().fold(DVec3::splat(f64::MIN), |a, p| a.max(*p));
            let xs_at = |z: f64| -> Vec<f64> {
                pts.iter()
                    .filter(|p| (p.z - z).abs() < LEVEL_TOLERANCE_M)
                    .map(|p| p.x)
                    .collect()
            };
            let span = |v: &[f64]| {
                v.iter().copied().fold(f64::MIN, f64::max)
                    - v.iter().copied().fold(f64::MAX, f64::min)
            };
            let (bottom, top) = (xs_at(lo.z), xs_at(hi.z));
            let levels = pts.iter().all(|p| {
                (p.z - lo.z).abs() < LEVEL_TOLERANCE_M || (p.z - hi.z).abs() < LEVEL_TOLERANCE_M
            });
            let h = hi.z - lo.z;
            let whole_lo = all.iter().map(|p| p.z).fold(f64::MAX, f64::min);
            let note = format!(
                "element {:.4} m along, {:.4} m across, at z {:.4}..{:.4} m about the path; its \
                 part outside the belt, {h:.4} m high, stands on the path",
                hi.x - lo.x,
                hi.y - lo.y,
                whole_lo,
                hi.z
            );
            if levels && !bottom.is_empty() && !top.is_empty() {
                return (
                    GrouserShapeSpec::Trapezoid {
                        bottom_m: span(&bottom),
                        top_m: span(&top),
                        height_m: h,
                        width_m: across(hi.y - lo.y),
                        shift_m: 0.0,
                    },
                    format!(
                        "{note}: a trapezoid {:.4}/{:.4} m x {h:.4} m",
                        span(&bottom),
                        span(&top)
                    ),
                );
            }
            let points_m = pts.iter().map(|p| [p.x, p.y, p.z - lo.z]).collect();
            (
                GrouserShapeSpec::Convex { points_m },
                format!("{note}: the convex hull of its points"),
            )
        }
    }
}

/// The pulleys of the plugin's arcs (centre x, z and radius in the track link's frame).
fn pulleys(p: &ContinuousTrackPlugin, to_link: glam::DAffine3) -> Vec<(Pulley, f64)> {
    p.segments
        .iter()
        .filter_map(|s| match s {
            PluginSegment::Arc { centre, radius, .. } => {
                let c = to_link.transform_point3(*centre);
                Some((
                    Pulley {
                        x: c.x,
                        z: c.z,
                        radius: *radius,
                    },
                    c.y,
                ))
            }
            PluginSegment::Straight { .. } => None,
        })
        .collect()
}

/// One line per trajectory segment: what it is and where.
fn segment_lines(p: &ContinuousTrackPlugin) -> Vec<String> {
    p.segments
        .iter()
        .map(|s| match s {
            PluginSegment::Straight {
                joint,
                length,
                direction,
                ..
            } => format!(
                "segment {joint}: prismatic, a straight of {length:.4} m along {:.3?}",
                direction.to_array()
            ),
            PluginSegment::Arc {
                joint,
                centre,
                radius,
                angle,
                pitch_diameter,
            } => format!(
                "segment {joint}: revolute, an arc of radius {radius:.4} m (segment link origin \
                 to joint) about x {:.4}, z {:.4} m{}{}",
                centre.x,
                centre.z,
                angle.map_or(String::new(), |a| format!(", {:.1} deg", a.to_degrees())),
                pitch_diameter.map_or(String::new(), |d| format!(", pitch_diameter {d} m"))
            ),
        })
        .collect()
}

/// Where the arcs' `<pitch_diameter>` disagrees with their geometry by over 1 % (one line for
/// the arcs that say the same).
fn pitch_notes(p: &ContinuousTrackPlugin) -> Vec<String> {
    let mut by: Vec<(f64, f64, Vec<&str>)> = Vec::new();
    for s in &p.segments {
        if let PluginSegment::Arc {
            joint,
            radius,
            pitch_diameter: Some(d),
            ..
        } = s
            && ((d / 2.0 - radius) / radius).abs() > 0.01
        {
            match by
                .iter_mut()
                .find(|e| e.0 == *d && (e.1 - radius).abs() < 1e-9)
            {
                Some(e) => e.2.push(joint),
                None => by.push((*d, *radius, vec![joint])),
            }
        }
    }
    by.into_iter()
        .map(|(d, r, joints)| {
            format!(
                "segment(s) {}: pitch_diameter {d} m (radius {:.4} m) disagrees with the geometry, \
                 radius {r:.4} m: the geometry is used",
                joints.join(", "),
                d / 2.0
            )
        })
        .collect()
}

/// The track the plugin describes (`Err`: why it cannot be made).
pub fn from_plugin(p: &ContinuousTrackPlugin, robot: &UrdfRobot) -> Result<ProposedTrack, String> {
    let link = robot.link(&p.parent_link).ok_or_else(|| {
        format!(
            "plugin {} (line {}): its segments hang on \"{}\", which is not a link of the robot",
            p.name, p.line, p.parent_link
        )
    })?;
    let to_link = link.pose.inverse();
    let arcs = pulleys(p, to_link);
    let plane_y = arcs.iter().map(|a| a.1).sum::<f64>() / arcs.len().max(1) as f64;
    let mut guesses = Vec::new();
    let circles: Vec<Pulley> = arcs.iter().map(|a| a.0).collect();
    let on_hull = super::hull::circles_on_hull(&circles);
    let path = match on_hull.as_slice() {
        [] => {
            return Err(format!(
                "plugin {} (line {}): no arc segment",
                p.name, p.line
            ));
        }
        [w] => ProposedPath::Wheel(*w),
        _ => ProposedPath::Pulleys(on_hull.clone()),
    };
    if on_hull.len() < circles.len() {
        guesses.push(format!(
            "{} of the {} arcs lie inside the belt's convex hull or on its straights (or repeat \
             another): the belt runs past them, they are not pulleys of the path",
            circles.len() - on_hull.len(),
            circles.len()
        ));
    }
    let sources = segment_lines(p);
    guesses.extend(pitch_notes(p));
    let width = p.width.unwrap_or(0.1);
    guesses.push(match p.width {
        Some(w) => format!("width: the segment links' collision, {w:.4} m"),
        None => "width: the segments give none; 0.1 m (a GUESS)".into(),
    });
    guesses.push(format!(
        "belt mass: the {} segment links' masses, {:.3} kg",
        p.segments.len(),
        p.belt_mass
    ));
    let mut t = ProposedTrack {
        name: p.name.clone(),
        link: link.name.clone(),
        why: format!(
            "the paper's {} plugin \"{}\" (line {}): its segment joints hang on link {}",
            if p.simple {
                "ContinuousTrackSimple"
            } else {
                "ContinuousTrack"
            },
            p.name,
            p.line,
            link.name
        ),
        path: path.clone(),
        plane_y,
        chassis_y: link.pose.transform_point3(DVec3::new(0.0, plane_y, 0.0)).y,
        width,
        belt_mass: p.belt_mass.max(super::propose::MIN_BELT_MASS_KG),
        friction: p.friction,
        // A wheel's commands act at its rolling radius (tracksim derives it).
        sprocket_pitch_radius: p
            .sprocket_pitch_diameter
            .map(|d| d / 2.0)
            .filter(|_| !matches!(path, ProposedPath::Wheel(_))),
        grousers: None,
        sources,
        guesses,
    };
    let perimeter = t.perimeter().ok_or_else(|| {
        format!(
            "plugin {} (line {}): tracksim refuses its arcs as pulleys",
            p.name, p.line
        )
    })?;
    if let Some(l) = p.trajectory_length()
        && (l - perimeter).abs() > 1e-3
    {
        t.guesses.push(format!(
            "the trajectory's segments add up to {l:.4} m, the pulleys' belt to {perimeter:.4} m: \
             the pulleys are used"
        ));
    }
    grousers(p, &mut t, perimeter);
    Ok(t)
}

/// The pattern as grousers (none without a pattern).
fn grousers(p: &ContinuousTrackPlugin, t: &mut ProposedTrack, perimeter: f64) {
    let (Some(n), false) = (p.elements_per_round, p.elements.is_empty()) else {
        t.guesses.push(format!(
            "grousers: none (the {} plugin has no <pattern>); the belt's friction drives",
            if p.simple {
                "ContinuousTrackSimple"
            } else {
                "ContinuousTrack"
            }
        ));
        return;
    };
    let mut shapes = Vec::new();
    for (k, e) in p.elements.iter().enumerate() {
        let (s, note) = grouser_shape(e, t.width);
        t.guesses
            .push(format!("grouser shape {k} (used in turn): {note}"));
        shapes.push(s);
    }
    t.guesses.push(format!(
        "grousers: {n} a round (elements_per_round), pitch {:.1} mm = perimeter {perimeter:.4} m / {n}",
        perimeter / n as f64 * 1000.0
    ));
    t.grousers = Some(GrouserSpec {
        count: n,
        offset_m: 0.0,
        shapes,
    });
}
