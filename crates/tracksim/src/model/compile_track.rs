//! Compiling one track of a [`VehicleSpec`](crate::spec::VehicleSpec), in named stages run in
//! this order: parents (`resolve_parent`), belt (`belt`), grousers (`grousers`,
//! `grouser_shape`), path (`track_path`), omitted segments (`included_segments`), then the
//! mirror image. Problems are reported with their key paths, in that order.

use super::compliance::compile_compliance;
use super::mounts::Mounts;
use super::{GrouserModel, GrouserShape, Parent, TrackModel};
use crate::check::{Checker, v3};
use crate::error::SpecIssue;
use crate::geometry::{GrouserLayout, PathError, Pulley, Segment, TrackPath};
use crate::spec::{GrouserShapeSpec, GrouserSpec, PathSpec, SegmentSpec, TrackSpec};
use glam::{DAffine3, DQuat, DVec3};
use rapier3d::prelude::CoefficientCombineRule;

fn path_issue(key: &str, e: &PathError) -> SpecIssue {
    let key = match e {
        PathError::NotFinite { segment }
        | PathError::NonPositiveLength { segment, .. }
        | PathError::ZeroVector { segment, .. }
        | PathError::NonPositiveRadius { segment, .. }
        | PathError::BadArcAngle { segment, .. }
        | PathError::Gap { segment, .. }
        | PathError::Kink { segment, .. }
        | PathError::NotPlanar { segment } => format!("{key}.segments[{segment}]"),
        PathError::BadPulley { pulley, .. }
        | PathError::PulleysOverlap { pulley, .. }
        | PathError::PulleyNotWrapped { pulley, .. } => {
            format!("{key}.pulleys[{pulley}]")
        }
        _ => key.to_string(),
    };
    SpecIssue::new(key, e.to_string())
}

fn combine_rule(s: &str) -> Option<CoefficientCombineRule> {
    Some(match s {
        "min" => CoefficientCombineRule::Min,
        "average" => CoefficientCombineRule::Average,
        "multiply" => CoefficientCombineRule::Multiply,
        "max" => CoefficientCombineRule::Max,
        _ => return None,
    })
}

/// The radius sprocket commands (`sprocket_rad_s`) and a motor's torque act at, m: the file's
/// `sprocket_pitch_radius_m`, or for a lugged wheel its rolling radius (the path circle: the
/// rim plus `rim_inset`), so that a command of w rad/s turns the wheel at w rad/s whatever
/// the lugs (issue 23.6). A wheel whose file states another radius contradicts itself and is
/// refused.
fn command_radius(c: &mut Checker, k: &str, t: &TrackSpec, rim_inset: f64) -> Option<f64> {
    let Some(w) = &t.path.wheel else {
        return t.sprocket_pitch_radius_m;
    };
    let rolling = w.radius_m + rim_inset;
    if let Some(r) = t.sprocket_pitch_radius_m
        && (r - rolling).abs() > 1e-6 * rolling
    {
        c.push(
            format!("{k}.sprocket_pitch_radius_m"),
            format!(
                "a wheel's commands act at its rolling radius, derived from the rim and the lugs \
                 ({rolling:.4} m here), so that sprocket_rad_s turns the wheel at that rate; got \
                 {r} m: remove the key"
            ),
        );
    }
    Some(rolling)
}

/// Checks track `t` (key path `k`) and appends it, then its mirror image if it has one, to
/// `tracks`; appends nothing when its path cannot be built.
pub(super) fn compile_track(
    c: &mut Checker,
    mounts: &Mounts,
    k: &str,
    t: &TrackSpec,
    tracks: &mut Vec<TrackModel>,
) {
    c.column_name(&format!("{k}.name"), &t.name);
    if let Some(m) = &t.mirror {
        c.column_name(&format!("{k}.mirror"), m);
    }
    let (parent, mirror_parent, frame) = resolve_parents(c, mounts, k, t);
    if (t.mirror_parent.is_some() || t.mirror_link.is_some()) && t.mirror.is_none() {
        let key = if t.mirror_link.is_some() {
            "mirror_link"
        } else {
            "mirror_parent"
        };
        c.push(format!("{k}.{key}"), "only used together with `mirror`");
    }
    let combine = belt(c, k, t);
    let mut grousers = match &t.grousers {
        None => None,
        Some(g) => grousers(c, k, t.width_m, g),
    };
    let Some((path, rim_inset)) = track_path(c, &format!("{k}.path"), &t.path, &mut grousers)
    else {
        return;
    };
    let Some(path) = placed(c, k, t, path, frame) else {
        return;
    };
    let sprocket_radius = command_radius(c, k, t, rim_inset);
    let n = path.segments().len();
    let included = included_segments(c, k, &t.omit_segments, n);
    let touching = touching_segments(c, k, t, &included, n);
    let model = TrackModel {
        name: t.name.clone(),
        parent,
        path,
        width: t.width_m,
        belt_thickness: t.belt_thickness_m,
        rim_inset,
        belt_mass: t.belt_mass_kg,
        friction: t.friction,
        combine,
        sprocket_radius,
        included,
        touching,
        grousers,
        compliance: t
            .compliance
            .as_ref()
            .map(|s| compile_compliance(c, &format!("{k}.compliance"), s))
            .unwrap_or_default(),
        motor: t
            .motor
            .as_ref()
            .and_then(|m| super::compile_motor(c, &format!("{k}.motor"), m, sprocket_radius)),
    };
    if let Some(m) = &t.mirror {
        let mut mirrored = model.clone();
        mirrored.name = m.clone();
        mirrored.parent = mirror_parent;
        mirrored.path = model.path.mirrored_y();
        tracks.push(model);
        tracks.push(mirrored);
    } else {
        tracks.push(model);
    }
}

/// Parent stage: what the track and its mirror image hang on, and the frame its path is
/// given in (the chassis frame, or for a URDF robot its link's frame). A vehicle file names
/// `"body"` or a flipper (`parent`, `mirror_parent`); a URDF robot names links (`link`,
/// `mirror_link`). Unknown names are reported and fall back to the body.
fn resolve_parents(
    c: &mut Checker,
    mounts: &Mounts,
    k: &str,
    t: &TrackSpec,
) -> (Parent, Parent, DAffine3) {
    if !mounts.is_urdf() {
        for (key, given) in [("link", &t.link), ("mirror_link", &t.mirror_link)] {
            if given.is_some() {
                c.push(
                    format!("{k}.{key}"),
                    "names a URDF link: only used with the vehicle's `urdf`; a vehicle file's \
                     track names its `parent` (\"body\" or a flipper)",
                );
            }
        }
        let (parent, _) = mounts.resolve(c, &format!("{k}.parent"), "parent", &t.parent);
        let mirror = match &t.mirror_parent {
            Some(p) => {
                mounts
                    .resolve(c, &format!("{k}.mirror_parent"), "parent", p)
                    .0
            }
            None => parent,
        };
        return (parent, mirror, DAffine3::IDENTITY);
    }
    if t.parent != "body" || t.mirror_parent.is_some() {
        let key = if t.parent != "body" {
            "parent"
        } else {
            "mirror_parent"
        };
        c.push(
            format!("{k}.{key}"),
            "a URDF robot's track names the link that carries it: use `link` (and \
             `mirror_link`)",
        );
    }
    let Some(link) = &t.link else {
        c.push(
            format!("{k}.link"),
            "missing: with `urdf`, every track names the URDF link that carries it (its path \
             and grousers are in that link's frame)",
        );
        return (Parent::Body, Parent::Body, DAffine3::IDENTITY);
    };
    let (parent, frame) = mounts.resolve(c, &format!("{k}.link"), "link", link);
    let mirror = match &t.mirror_link {
        Some(l) => mounts.resolve(c, &format!("{k}.mirror_link"), "link", l).0,
        None => parent,
    };
    (parent, mirror, frame)
}

/// Placement stage: the path moved from its link's frame into the chassis frame; it must still
/// turn about +y (the link's frame may turn only about y).
fn placed(
    c: &mut Checker,
    k: &str,
    t: &TrackSpec,
    path: TrackPath,
    frame: DAffine3,
) -> Option<TrackPath> {
    if frame == DAffine3::IDENTITY {
        return Some(path);
    }
    let moved = path.moved(DQuat::from_mat3(&frame.matrix3), frame.translation);
    if moved.axis().dot(DVec3::Y) < 1.0 - 1e-9 {
        c.push(
            format!("{k}.link"),
            format!(
                "link \"{}\" is turned so that the track would not run in the chassis's x-z \
                 plane (its loop axis becomes {:.3?}); a track's link may be turned only about y",
                t.link.as_deref().unwrap_or_default(),
                moved.axis().to_array()
            ),
        );
        return None;
    }
    Some(moved)
}

/// Belt stage: checks width, thickness, mass, friction and sprocket radius; returns the
/// friction combine rule (`min` when unknown).
fn belt(c: &mut Checker, k: &str, t: &TrackSpec) -> CoefficientCombineRule {
    c.positive(&format!("{k}.width_m"), t.width_m, "m");
    c.positive(&format!("{k}.belt_thickness_m"), t.belt_thickness_m, "m");
    c.positive(&format!("{k}.belt_mass_kg"), t.belt_mass_kg, "kg");
    c.non_negative(&format!("{k}.friction"), t.friction, "");
    let combine = combine_rule(&t.friction_combine).unwrap_or_else(|| {
        c.push(
            format!("{k}.friction_combine"),
            format!(
                "unknown rule \"{}\"; use \"min\", \"average\", \"multiply\" or \"max\"",
                t.friction_combine
            ),
        );
        CoefficientCombineRule::Min
    });
    if let Some(r) = t.sprocket_pitch_radius_m {
        c.positive(&format!("{k}.sprocket_pitch_radius_m"), r, "m");
    }
    combine
}

/// Most grousers on one track (a grouser is a collider; the paper's PackBot has 40).
pub const MAX_GROUSERS: usize = 10_000;

/// Grouser stage: checks the `[grousers]` table of the track at `k` (belt width `track_width`
/// m) and compiles it; `None` for a count of 0.
fn grousers(c: &mut Checker, k: &str, track_width: f64, g: &GrouserSpec) -> Option<GrouserModel> {
    let gk = format!("{k}.grousers");
    if g.count == 0 {
        c.push(
            format!("{gk}.count"),
            "must be >= 1 (remove the [grousers] table for a track without grousers)",
        );
    } else if g.count > MAX_GROUSERS {
        c.push(
            format!("{gk}.count"),
            format!("must be at most {MAX_GROUSERS} per track, got {}", g.count),
        );
    }
    c.finite(&format!("{gk}.offset_m"), &[g.offset_m]);
    if g.shapes.is_empty() {
        c.push(format!("{gk}.shapes"), "needs at least one shape");
    }
    if g.count > 0 && !g.shapes.is_empty() && !g.count.is_multiple_of(g.shapes.len()) {
        c.push(
            format!("{gk}.count"),
            format!(
                "{} grousers cannot repeat {} shapes evenly; use a multiple of {}",
                g.count,
                g.shapes.len(),
                g.shapes.len()
            ),
        );
    }
    let mut shapes = Vec::new();
    let mut height: f64 = 0.0;
    for (j, s) in g.shapes.iter().enumerate() {
        let sk = format!("{gk}.shapes[{j}]");
        let shape = grouser_shape(c, &sk, s, track_width, &mut height);
        shapes.push(shape);
    }
    (g.count > 0).then_some(GrouserModel {
        layout: GrouserLayout {
            count: g.count,
            offset: g.offset_m,
        },
        shapes,
        height,
    })
}

/// Checks one grouser shape (key path `sk`; width defaults to `track_width` m), compiles it in
/// its footprint frame and raises `height` to its outward extent, m.
fn grouser_shape(
    c: &mut Checker,
    sk: &str,
    s: &GrouserShapeSpec,
    track_width: f64,
    height: &mut f64,
) -> GrouserShape {
    match s {
        GrouserShapeSpec::Box {
            length_m,
            height_m,
            width_m,
            shift_m,
        } => {
            let w = width_m.unwrap_or(track_width);
            c.positive(&format!("{sk}.length_m"), *length_m, "m");
            c.positive(&format!("{sk}.height_m"), *height_m, "m");
            c.positive(&format!("{sk}.width_m"), w, "m");
            c.finite(&format!("{sk}.shift_m"), &[*shift_m]);
            *height = height.max(*height_m);
            GrouserShape::Box {
                half: DVec3::new(*length_m, w, *height_m) * 0.5,
                centre: DVec3::new(*shift_m, 0.0, height_m * 0.5),
            }
        }
        GrouserShapeSpec::Trapezoid {
            bottom_m,
            top_m,
            height_m,
            width_m,
            shift_m,
        } => {
            let w = width_m.unwrap_or(track_width);
            c.positive(&format!("{sk}.bottom_m"), *bottom_m, "m");
            c.positive(&format!("{sk}.top_m"), *top_m, "m");
            c.positive(&format!("{sk}.height_m"), *height_m, "m");
            c.positive(&format!("{sk}.width_m"), w, "m");
            c.finite(&format!("{sk}.shift_m"), &[*shift_m]);
            *height = height.max(*height_m);
            let mut pts = Vec::new();
            for y in [-w / 2.0, w / 2.0] {
                for (x, z) in [
                    (-bottom_m / 2.0, 0.0),
                    (bottom_m / 2.0, 0.0),
                    (-top_m / 2.0, *height_m),
                    (top_m / 2.0, *height_m),
                ] {
                    pts.push(DVec3::new(x + shift_m, y, z));
                }
            }
            GrouserShape::Convex(pts)
        }
        GrouserShapeSpec::Convex { points_m } => {
            let pts = c.points(&format!("{sk}.points_m"), points_m);
            *height = pts.iter().map(|p| p.z).fold(*height, f64::max);
            GrouserShape::Convex(pts)
        }
    }
}

/// Path stage: builds the loop at key path `pk` from pulleys, explicit segments or a wheel and
/// checks that it turns about +y; `None` when it cannot be built (the problems are reported).
/// Returns the rim inset of a wheel (0 otherwise), whose lugs in `grousers` it moves onto the
/// rolling circle.
fn track_path(
    c: &mut Checker,
    pk: &str,
    p: &PathSpec,
    grousers: &mut Option<GrouserModel>,
) -> Option<(TrackPath, f64)> {
    if p.spatial && p.segments.is_none() {
        c.push(
            format!("{pk}.spatial"),
            "only used with `segments` (pulleys and wheels lie in a plane)",
        );
    }
    if let Some(w) = &p.wheel {
        if p.pulleys.is_some() || p.segments.is_some() {
            c.push(
                pk.to_string(),
                "give exactly one of `pulleys`, `segments` or `wheel`",
            );
            return None;
        }
        return wheel_path(c, pk, p.plane_y_m.unwrap_or(0.0), w, grousers);
    }
    let path = match (&p.pulleys, &p.segments) {
        (Some(q), None) => {
            let y = p.plane_y_m.unwrap_or(0.0);
            c.finite(&format!("{pk}.plane_y_m"), &[y]);
            let n = c.issues.len();
            for (j, q) in q.iter().enumerate() {
                c.finite(&format!("{pk}.pulleys[{j}].x_m"), &[q.x_m]);
                c.finite(&format!("{pk}.pulleys[{j}].z_m"), &[q.z_m]);
                c.positive(&format!("{pk}.pulleys[{j}].radius_m"), q.radius_m, "m");
            }
            if c.issues.len() != n {
                return None;
            }
            let pulleys: Vec<Pulley> = q
                .iter()
                .map(|q| Pulley {
                    x: q.x_m,
                    z: q.z_m,
                    radius: q.radius_m,
                })
                .collect();
            TrackPath::from_pulleys(&pulleys, y)
        }
        (None, Some(s)) => {
            if p.plane_y_m.is_some() {
                c.push(
                    format!("{pk}.plane_y_m"),
                    "only used with pulleys; explicit segments carry their own y",
                );
            }
            let n = c.issues.len();
            for (j, seg) in s.iter().enumerate() {
                let sk = format!("{pk}.segments[{j}]");
                match seg {
                    SegmentSpec::Straight {
                        start_m, length_m, ..
                    } => {
                        c.finite(&format!("{sk}.start_m"), start_m);
                        c.positive(&format!("{sk}.length_m"), *length_m, "m");
                    }
                    SegmentSpec::Arc {
                        start_m,
                        centre_m,
                        angle_deg,
                        ..
                    } => {
                        c.finite(&format!("{sk}.start_m"), start_m);
                        c.finite(&format!("{sk}.centre_m"), centre_m);
                        c.finite(&format!("{sk}.angle_deg"), &[*angle_deg]);
                    }
                }
            }
            if c.issues.len() != n {
                return None;
            }
            let segs = s.iter().map(segment).collect();
            if p.spatial {
                TrackPath::spatial(segs)
            } else {
                TrackPath::new(segs)
            }
        }
        _ => {
            c.push(
                pk.to_string(),
                "give exactly one of `pulleys` (list of {x_m, z_m, radius_m}), `segments` or `wheel` ({x_m, z_m, radius_m})",
            );
            return None;
        }
    };
    let path = match path {
        Ok(p) => p,
        Err(errs) => {
            for e in &errs {
                c.issues.push(path_issue(pk, e));
            }
            return None;
        }
    };
    if path.is_planar() && path.axis().dot(DVec3::Y) < 1.0 - 1e-6 {
        c.push(
            pk.to_string(),
            "the loop must lie in an x-z plane and turn about +y (lower run moving backwards for a positive belt speed); reverse the segment order",
        );
    }
    Some((path, 0.0))
}

/// A lugged wheel's path (`{pk}.wheel`): its rolling circle, with the lugs moved onto it.
fn wheel_path(
    c: &mut Checker,
    pk: &str,
    plane_y: f64,
    w: &crate::spec::PulleySpec,
    grousers: &mut Option<GrouserModel>,
) -> Option<(TrackPath, f64)> {
    let wk = format!("{pk}.wheel");
    c.finite(&format!("{pk}.plane_y_m"), &[plane_y]);
    c.finite(&wk, &[w.x_m, w.z_m]);
    c.positive(&format!("{wk}.radius_m"), w.radius_m, "m");
    if !(w.radius_m > 0.0 && w.radius_m.is_finite() && w.x_m.is_finite() && w.z_m.is_finite()) {
        return None;
    }
    let roll = super::rolling_radius(w.radius_m, grousers.as_ref());
    let inset = roll - w.radius_m;
    if let Some(g) = grousers {
        super::wheel::inset_lugs(g, inset);
    }
    match TrackPath::circle(w.x_m, w.z_m, roll, plane_y) {
        Ok(p) => Some((p, inset)),
        Err(errs) => {
            for e in &errs {
                c.push(wk.clone(), e.to_string());
            }
            None
        }
    }
}

/// One explicit segment, angles to radians.
fn segment(s: &SegmentSpec) -> Segment {
    match *s {
        SegmentSpec::Straight {
            start_m,
            direction,
            length_m,
        } => Segment::Straight {
            start: v3(start_m),
            direction: v3(direction),
            length: length_m,
        },
        SegmentSpec::Arc {
            start_m,
            centre_m,
            axis,
            angle_deg,
        } => Segment::Arc {
            start: v3(start_m),
            centre: v3(centre_m),
            axis: v3(axis),
            angle: angle_deg.to_radians(),
        },
    }
}

/// Omitted-segment stage: which of the loop's `n` segments get a link, from `omit`
/// (`{k}.omit_segments`).
fn included_segments(c: &mut Checker, k: &str, omit: &[usize], n: usize) -> Vec<bool> {
    let mut included = vec![true; n];
    for (j, &o) in omit.iter().enumerate() {
        if o >= n {
            c.push(
                format!("{k}.omit_segments[{j}]"),
                format!(
                    "segment {o} does not exist; the loop has segments 0..{}",
                    n - 1
                ),
            );
        } else {
            included[o] = false;
        }
    }
    if included.iter().all(|x| !x) {
        c.push(format!("{k}.omit_segments"), "cannot omit every segment");
    }
    included
}

/// Contact-free stage: which included segments carry colliders, from
/// `{k}.no_contact_segments` (a segment there keeps its link, without colliders).
fn touching_segments(
    c: &mut Checker,
    k: &str,
    t: &TrackSpec,
    included: &[bool],
    n: usize,
) -> Vec<bool> {
    let mut touching = included.to_vec();
    for (j, &o) in t.no_contact_segments.iter().enumerate() {
        let key = format!("{k}.no_contact_segments[{j}]");
        if o >= n {
            c.push(
                key,
                format!(
                    "segment {o} does not exist; the loop has segments 0..{}",
                    n - 1
                ),
            );
        } else if !included[o] {
            c.push(
                key,
                format!(
                    "segment {o} is omitted (`omit_segments`): remove it from one of the two lists"
                ),
            );
        } else {
            touching[o] = false;
        }
    }
    if touching.iter().all(|x| !x) {
        c.push(
            format!("{k}.no_contact_segments"),
            "every segment would be without contact: the track could touch nothing",
        );
    }
    touching
}
