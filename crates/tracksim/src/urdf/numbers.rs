//! Every number of a robot file held to what the f32 engine represents, with the bounds of the
//! TOML checker ([`crate::check::unit_range`]): positions at most
//! [`crate::check::MAX_LENGTH_M`] in magnitude, angles (rad) and axis components at most
//! [`crate::check::MAX_PLAIN`], moments of inertia between 1e-12 and 1e6 kg m^2, torques at
//! most 1e7 N m, friction 0 or 1e-6 to 1e4; NaN and infinities refused (an infinite joint
//! limit is URDF's "unbounded" and kept). Checked on the [`UrdfSource`] before the tree is
//! walked, so a URDF and an SDF model (converted into the same source) are held to one set of
//! bounds, and nothing downstream sees a number the engine cannot hold. Mesh vertices are
//! checked after their scale in `mesh.rs`.

use super::source::{UrdfSource, key};
use crate::check::{MAX_LENGTH_M, MAX_PLAIN, num, unit_range};
use crate::error::SpecIssue;
use urdf_rs::JointType;

/// `[a, b, c]` for a message.
fn list(v: &[f64]) -> String {
    v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(" ")
}

/// A problem with `v` (finite, magnitude at most `max` `unit`, which begins with a space when
/// not empty), or `None`.
fn bounded(v: &[f64], max: f64, unit: &str) -> Option<String> {
    if v.iter().any(|x| !x.is_finite()) {
        Some(format!(
            "\"{}\" has a number that is not finite; give finite numbers{unit}",
            list(v)
        ))
    } else if v.iter().any(|x| x.abs() > max) {
        Some(format!(
            "\"{}\" is beyond {max:e}{unit} in magnitude, more than the f32 engine represents \
             (tracksim's bound for every file); check the units and the number",
            list(v)
        ))
    } else {
        None
    }
}

/// Checks an `<origin>` (`at`: the element, e.g. `<joint name="j"> (f line 3) <origin`).
fn origin(at: &str, o: &urdf_rs::Pose, issues: &mut Vec<SpecIssue>) {
    if let Some(m) = bounded(&o.xyz.0, MAX_LENGTH_M, " m") {
        issues.push(SpecIssue::new(key(&format!("{at} <origin xyz>")), m));
    }
    if let Some(m) = bounded(&o.rpy.0, MAX_PLAIN, " rad") {
        issues.push(SpecIssue::new(key(&format!("{at} <origin rpy>")), m));
    }
}

/// Checks one link's `<inertial>` and `<collision>` numbers.
fn link(src: &UrdfSource, l: &urdf_rs::Link, issues: &mut Vec<SpecIssue>) {
    let at = src.link(&l.name);
    if src.with_inertial.contains(&l.name) {
        let at = format!("{at} <inertial>");
        origin(&at, &l.inertial.origin, issues);
        let i = &l.inertial.inertia;
        let (lo, hi) = unit_range("kg m^2");
        let all = [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz];
        if let Some(m) = bounded(&all, hi, " kg m^2") {
            issues.push(SpecIssue::new(key(&format!("{at} <inertia>")), m));
        } else if all.iter().any(|v| *v != 0.0) {
            for (tag, v) in [("ixx", i.ixx), ("iyy", i.iyy), ("izz", i.izz)] {
                // Zero and negative moments are the positive-definite check's (`inertial.rs`).
                if v > 0.0 && v < lo {
                    issues.push(SpecIssue::new(
                        key(&format!("{at} <inertia {tag}>")),
                        format!(
                            "{} kg m^2 is below {lo:e}, zero to the f32 engine; give the \
                             link's moment of inertia (or an all-zero <inertia> on a link \
                             fixed to another, a point mass)",
                            num(v)
                        ),
                    ));
                }
            }
        }
    }
    for (k, c) in l.collision.iter().enumerate() {
        let at = format!("{at} <collision> {}", k + 1);
        origin(&at, &c.origin, issues);
        if let urdf_rs::Geometry::Mesh { scale: Some(s), .. } = &c.geometry {
            let bad = bounded(&s.0, MAX_PLAIN, "").or_else(|| {
                s.0.contains(&0.0)
                    .then(|| format!("\"{}\" has a zero factor: the mesh is flat", list(&s.0)))
            });
            if let Some(m) = bad {
                issues.push(SpecIssue::new(key(&format!("{at} <mesh scale>")), m));
            }
        }
    }
}

/// Checks one joint's origin, axis, limits and effort.
fn joint(src: &UrdfSource, j: &urdf_rs::Joint, issues: &mut Vec<SpecIssue>) {
    let at = src.joint(&j.name);
    origin(&at, &j.origin, issues);
    let turns = matches!(j.joint_type, JointType::Revolute | JointType::Continuous);
    let axis = &j.axis.xyz.0;
    if let Some(m) = bounded(axis, MAX_PLAIN, "") {
        issues.push(SpecIssue::new(key(&format!("{at} <axis xyz>")), m));
    } else if turns && glam::DVec3::from_array(*axis).length() < 1e-9 {
        issues.push(SpecIssue::new(
            key(&format!("{at} <axis xyz>")),
            format!(
                "\"{}\" is a zero vector: a turning joint needs the direction of its axis, \
                 e.g. \"0 1 0\"",
                list(axis)
            ),
        ));
    }
    if !turns {
        return;
    }
    let l = &j.limit;
    if j.joint_type == JointType::Revolute {
        for (tag, v) in [("lower", l.lower), ("upper", l.upper)] {
            // An infinite limit is "unbounded" (checked with the arm in `tree.rs`).
            if v.is_nan() || (v.is_finite() && v.abs() > MAX_PLAIN) {
                issues.push(SpecIssue::new(
                    key(&format!("{at} <limit {tag}>")),
                    format!(
                        "{} rad is not an angle the f32 engine holds (at most {MAX_PLAIN:e} in \
                         magnitude); give the limit in rad, or make the joint continuous",
                        num(v)
                    ),
                ));
            }
        }
    }
    let (lo, hi) = unit_range("N m");
    if l.effort > 0.0 && l.effort < lo {
        issues.push(SpecIssue::new(
            key(&format!("{at} <limit effort>")),
            format!(
                "{} N m is below {lo:e} N m, zero to the f32 engine; give the motor's torque in \
                 N m",
                num(l.effort)
            ),
        ));
    }
    if l.effort.is_finite() && l.effort > hi {
        issues.push(SpecIssue::new(
            key(&format!("{at} <limit effort>")),
            format!(
                "{} N m is beyond {hi:e} N m, more than the f32 engine's bound; give the \
                 motor's torque in N m",
                num(l.effort)
            ),
        ));
    }
}

/// Checks every number of `src` (links, joints, Gazebo friction and plugin lengths).
pub(super) fn check(src: &UrdfSource, issues: &mut Vec<SpecIssue>) {
    for l in &src.robot.links {
        link(src, l, issues);
    }
    for j in &src.robot.joints {
        joint(src, j, issues);
    }
    let (lo, hi) = unit_range("");
    let mut friction: Vec<(&String, &f64)> = src.gazebo.friction.iter().collect();
    friction.sort_by(|a, b| a.0.cmp(b.0));
    for (link, mu) in friction {
        if !(mu.is_finite() && (*mu == 0.0 || (lo..=hi).contains(mu))) {
            issues.push(SpecIssue::new(
                key(&format!(
                    "<gazebo reference=\"{}\"><mu1> ({})",
                    crate::check::echoed(link),
                    src.file_name()
                )),
                format!(
                    "{} is not a friction coefficient: give 0 or a number from {lo:e} to {hi:e} \
                     (e.g. 0.6)",
                    num(*mu)
                ),
            ));
        }
    }
    if let Some(p) = &src.gazebo.plugin {
        for (tag, v) in [
            ("tracks_separation", p.tracks_separation),
            ("tracks_height", p.tracks_height),
        ] {
            if let Some(m) = v.and_then(|v| bounded(&[v], MAX_LENGTH_M, " m")) {
                issues.push(SpecIssue::new(key(&p.at(tag)), m));
            }
        }
    }
}
