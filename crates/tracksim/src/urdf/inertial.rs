//! Each link's `<inertial>`: mass and inertia checked (mass > 0; inertia positive definite and
//! obeying the triangle inequality, as every real body's does), moved into the chassis frame,
//! and merged per body (the chassis with its fixed and continuous links, each arm with its
//! own) with the parallel-axis theorem.

use super::Owner;
use super::pose::{finite_pose, pose};
use super::source::{UrdfSource, key};
use super::{ImportedLink, LinkJoint, MassPart};
use crate::error::SpecIssue;
use glam::{DMat3, DVec3};

fn tensor(i: &urdf_rs::Inertia) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(i.ixx, i.ixy, i.ixz),
        DVec3::new(i.ixy, i.iyy, i.iyz),
        DVec3::new(i.ixz, i.iyz, i.izz),
    )
}

/// Checks the `<inertial>` of link `l` (if it has one) and sets its mass. A link merged into
/// its parent (fixed or continuous joint) with an all-zero `<inertia>` is taken as a point
/// mass, with a line in `warnings`.
pub(super) fn link_mass(
    src: &UrdfSource,
    l: &mut ImportedLink,
    issues: &mut Vec<SpecIssue>,
    warnings: &mut Vec<String>,
) {
    if !src.with_inertial.contains(&l.name) {
        return;
    }
    let Some(u) = src.robot.links.iter().find(|k| k.name == l.name) else {
        return;
    };
    let at = key(&format!("{} <inertial>", src.link(&l.name)));
    let m = u.inertial.mass.value;
    let (lo, hi) = crate::check::unit_range("kg");
    if !(m.is_finite() && m >= lo && m <= hi) {
        issues.push(SpecIssue::new(
            &at,
            format!(
                "<mass value=\"{}\"> must be a mass in [{lo}, {hi}] kg; a link without mass has \
                 no <inertial>",
                crate::check::num(m)
            ),
        ));
    }
    if !finite_pose(&u.inertial.origin) {
        issues.push(SpecIssue::new(
            &at,
            "its <origin> has a number that is not finite",
        ));
    }
    let i = &u.inertial.inertia;
    let t = tensor(i);
    let d = [i.ixx, i.iyy, i.izz];
    let minor2 = i.ixx * i.iyy - i.ixy * i.ixy;
    let all = [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz];
    let merged = matches!(l.kind, LinkJoint::Fixed | LinkJoint::Continuous);
    if all.iter().any(|v| !v.is_finite()) {
        issues.push(SpecIssue::new(
            &at,
            "<inertia> has a number that is not finite",
        ));
    } else if merged && all.iter().all(|v| *v == 0.0) {
        warnings.push(format!(
            "{} <inertial>: <inertia> is all zero; taken as a point mass of {} kg merged into \
             its parent (give its inertia if it is a large part)",
            src.link(&l.name),
            crate::check::num(m)
        ));
    } else if !(i.ixx > 0.0 && minor2 > 0.0 && t.determinant() > 0.0) {
        issues.push(SpecIssue::new(
            &at,
            format!(
                "<inertia ixx=\"{}\" iyy=\"{}\" izz=\"{}\" ...> is not positive definite: a \
                 body's moments of inertia are > 0, kg m^2 (zero or negative inertia cannot be \
                 simulated)",
                crate::check::num(i.ixx),
                crate::check::num(i.iyy),
                crate::check::num(i.izz)
            ),
        ));
    } else {
        for k in 0..3 {
            let (a, b, c) = (d[k], d[(k + 1) % 3], d[(k + 2) % 3]);
            if b + c < a * (1.0 - 1e-6) {
                issues.push(SpecIssue::new(
                    &at,
                    format!(
                        "<inertia> breaks the triangle inequality ({} > {} + {} kg m^2): no \
                         real body has these moments; check ixx, iyy, izz",
                        crate::check::num(a),
                        crate::check::num(b),
                        crate::check::num(c)
                    ),
                ));
                break;
            }
        }
    }
    l.mass = m;
}

/// The mass properties of `owner`'s links merged, in the chassis frame; a body without mass
/// is a problem in `issues`.
pub(super) fn merged(
    src: &UrdfSource,
    links: &[ImportedLink],
    owner: Owner,
    issues: &mut Vec<SpecIssue>,
) -> MassPart {
    let mut parts = Vec::new();
    for l in links.iter().filter(|l| l.owner == owner && l.mass > 0.0) {
        let Some(u) = src.robot.links.iter().find(|k| k.name == l.name) else {
            continue;
        };
        let frame = l.pose * pose(&u.inertial.origin);
        let r = frame.matrix3;
        parts.push(MassPart {
            mass: l.mass,
            com: frame.translation,
            inertia: r * tensor(&u.inertial.inertia) * r.transpose(),
        });
    }
    match parts.as_slice() {
        [] => {
            let first = links.iter().find(|l| l.owner == owner);
            let what = first.map_or("urdf".to_string(), |l| key(&src.link(&l.name)));
            issues.push(SpecIssue::new(
                what,
                "this body has no mass: give the link (or a link fixed to it) an <inertial> \
                 with a positive mass",
            ));
            MassPart {
                mass: 1.0,
                com: DVec3::ZERO,
                inertia: DMat3::IDENTITY,
            }
        }
        // One link: its own numbers, not re-derived through sums (no rounding).
        [one] => *one,
        many => {
            let mass: f64 = many.iter().map(|p| p.mass).sum();
            let com = many.iter().map(|p| p.com * p.mass).sum::<DVec3>() / mass;
            let mut inertia = DMat3::ZERO;
            for p in many {
                let d = p.com - com;
                let shift = DMat3::from_diagonal(DVec3::splat(d.length_squared()))
                    - DMat3::from_cols(d * d.x, d * d.y, d * d.z);
                inertia += p.inertia + shift * p.mass;
            }
            if inertia.determinant() <= 0.0 {
                let first = links.iter().find(|l| l.owner == owner);
                let what = first.map_or("urdf".to_string(), |l| key(&src.link(&l.name)));
                issues.push(SpecIssue::new(
                    what,
                    "this body's merged inertia is not positive definite (its links are point \
                     masses on one line): give its links their <inertia>",
                ));
            }
            MassPart { mass, com, inertia }
        }
    }
}

/// A line in `warnings` for link `l` whose centre of mass (m, chassis frame) lies far outside
/// its collision shapes' box (by more than 0.1 m and their size), or, without shapes, over
/// 1 m from its frame: usually an `<inertial><origin>` in the wrong frame or units.
pub(super) fn far_com(src: &UrdfSource, l: &ImportedLink, warnings: &mut Vec<String>) {
    if l.mass <= 0.0 {
        return;
    }
    let Some(u) = src.robot.links.iter().find(|k| k.name == l.name) else {
        return;
    };
    let com = (l.pose * pose(&u.inertial.origin)).translation;
    let (lo, hi, size) = match l
        .shapes
        .iter()
        .map(|s| s.bounds())
        .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    {
        Some((lo, hi)) => (lo, hi, (hi - lo).length().max(0.1)),
        None => (l.pose.translation, l.pose.translation, 1.0),
    };
    let outside = (com - com.clamp(lo, hi)).length();
    if outside > size {
        warnings.push(format!(
            "{} <inertial>: the centre of mass is {:.3} m outside the link's {} (check the \
             <origin>'s frame and units)",
            src.link(&l.name),
            outside,
            if l.shapes.is_empty() {
                "frame"
            } else {
                "collision shapes"
            }
        ));
    }
}
