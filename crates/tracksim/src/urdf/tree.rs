//! The joint tree of a URDF robot, walked from its root link: each link's frame in the chassis
//! frame (arms at angle 0) and the body it belongs to. A URDF is a tree: a link with two
//! parent joints, a loop of joints, links not connected to the root, joints naming links that
//! do not exist, and joint types tracksim cannot simulate are refused with the element named.

use super::Owner;
use super::pose::{finite_pose, pose, too_far};
use super::source::{UrdfSource, key};
use super::{ImportedArm, ImportedLink, JointRoles, LinkJoint};
use crate::error::SpecIssue;
use glam::{DAffine3, DVec3};
use std::collections::HashMap;
use urdf_rs::JointType;

/// Checks the names and links of every joint and link; returns the root link's name.
fn root_link(src: &UrdfSource, issues: &mut Vec<SpecIssue>) -> Option<String> {
    let r = &src.robot;
    let mut seen = HashMap::new();
    for l in &r.links {
        if seen.insert(l.name.as_str(), ()).is_some() {
            issues.push(SpecIssue::new(
                key(&src.link(&l.name)),
                "a second link with this name; link names must be unique",
            ));
        }
    }
    let mut parent_of: HashMap<&str, &str> = HashMap::new();
    let mut joint_names = HashMap::new();
    for j in &r.joints {
        let at = key(&src.joint(&j.name));
        if joint_names.insert(j.name.as_str(), ()).is_some() {
            issues.push(SpecIssue::new(
                &at,
                "a second joint with this name; joint names must be unique",
            ));
        }
        for (what, l) in [("parent", &j.parent.link), ("child", &j.child.link)] {
            if !seen.contains_key(l.as_str()) {
                issues.push(SpecIssue::new(
                    &at,
                    format!(
                        "its <{what} link=\"{}\"> is not a link of the URDF",
                        crate::check::echoed(l)
                    ),
                ));
            }
        }
        if let Some(first) = parent_of.insert(j.child.link.as_str(), j.name.as_str()) {
            issues.push(SpecIssue::new(
                &at,
                format!(
                    "link \"{}\" is already the child of joint \"{first}\": a link has one \
                     parent in URDF (closed chains of joints cannot be described)",
                    crate::check::echoed(&j.child.link)
                ),
            ));
        }
    }
    if !issues.is_empty() {
        return None;
    }
    let roots: Vec<&str> = r
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|l| !parent_of.contains_key(l))
        .collect();
    match roots.as_slice() {
        [one] => Some(one.to_string()),
        [] if !r.links.is_empty() => {
            // Every link has a parent joint: walking up from any link must come back.
            let parent_link: HashMap<&str, &str> = r
                .joints
                .iter()
                .map(|j| (j.name.as_str(), j.parent.link.as_str()))
                .collect();
            let mut cycle: Vec<&str> = Vec::new();
            let mut link = r.links[0].name.as_str();
            while let Some(&j) = parent_of.get(link) {
                if let Some(at) = cycle.iter().position(|&c| c == j) {
                    cycle.drain(..at);
                    break;
                }
                cycle.push(j);
                link = parent_link.get(j).copied().unwrap_or(link);
            }
            let first = cycle.first().copied().unwrap_or_default();
            issues.push(SpecIssue::new(
                key(&src.joint(first)),
                format!(
                    "the joints {} form a loop: every link is the child of a joint, so there is \
                     no root link (the chassis); remove one of them",
                    cycle
                        .iter()
                        .map(|j| format!("\"{}\"", crate::check::echoed(j)))
                        .collect::<Vec<_>>()
                        .join(" <- ")
                ),
            ));
            None
        }
        [] => {
            issues.push(SpecIssue::new("urdf", "the URDF has no <link>"));
            None
        }
        many => {
            issues.push(SpecIssue::new(
                "urdf",
                format!(
                    "{} links are not the child of any joint ({}); a robot has one root link \
                     (the chassis): join the others to it",
                    many.len(),
                    many.join(", ")
                ),
            ));
            None
        }
    }
}

/// The joint names of `roles` that are not joints of the robot, refused with the list.
fn check_roles(src: &UrdfSource, roles: &JointRoles, issues: &mut Vec<SpecIssue>) {
    let names: Vec<&str> = src.robot.joints.iter().map(|j| j.name.as_str()).collect();
    let lists = [
        ("rigid_joints", Some(&roles.rigid)),
        ("flipper_joints", roles.flippers.as_ref()),
    ];
    for (k, list) in lists {
        for (i, j) in list.into_iter().flatten().enumerate() {
            if !names.contains(&j.as_str()) {
                issues.push(SpecIssue::new(
                    format!("{k}[{i}]"),
                    crate::check::unknown_name("joint", j, &names),
                ));
            } else if k == "flipper_joints" && roles.is_rigid(j) {
                issues.push(SpecIssue::new(
                    format!("{k}[{i}]"),
                    format!("joint \"{j}\" is also in `rigid_joints`: name it in one list"),
                ));
            }
        }
    }
}

/// How joint `j` (frame `frame` of its child at angle 0) joins its child to a parent owned by
/// `parent_owner`: its kind, whether it is an arm, and the child frame (a locked or rigid
/// revolute joint turns it to its angle).
fn role(
    src: &UrdfSource,
    j: &urdf_rs::Joint,
    roles: &JointRoles,
    frame: &mut DAffine3,
    warnings: &mut Vec<String>,
) -> Result<(LinkJoint, bool), ()> {
    let named = roles.named_flipper(&j.name);
    // A continuous joint (or SDF's revolute without limits) whose link reaches off its axis is
    // an arm that turns freely, never a wheel merged into its parent (issue 60: Absolem's four
    // flippers, on SDF's +-1e16 "no limit", were merged into the main tracks as one rigid loop).
    if j.joint_type == JointType::Continuous
        && named.is_none()
        && !roles.is_rigid(&j.name)
        && let Some(off) = off_axis(src, j)
    {
        warnings.push(format!(
            "joint \"{}\" turns without limits (continuous, or an SDF revolute joint with \
                 no limit) and its link \"{}\" has collision shapes {off:.3} m off its axis: an \
                 arm that turns freely (a flipper), not a wheel merged into its parent; list it \
                 in `rigid_joints` to keep it rigid",
            j.name, j.child.link
        ));
        return Ok((LinkJoint::Revolute, true));
    }
    Ok(match j.joint_type {
        JointType::Fixed => (LinkJoint::Fixed, false),
        // A revolute joint locked at one angle (gz-sim's `<limit lower="a" upper="a">`) is
        // rigid: fixed at that angle.
        JointType::Revolute if locked(j) => {
            let axis = DVec3::from_array(j.axis.xyz.0);
            if let Some(a) = axis.try_normalize() {
                *frame *= DAffine3::from_axis_angle(a, j.limit.lower);
            }
            (LinkJoint::Fixed, false)
        }
        // Kept rigid by the vehicle file (any type), or a revolute joint not among its named
        // flippers: fixed at angle 0.
        _ if roles.is_rigid(&j.name) => (LinkJoint::Fixed, false),
        JointType::Revolute if named == Some(false) => (LinkJoint::Fixed, false),
        JointType::Continuous
            if named == Some(true)
                || named.is_none() && roles.track_links.contains(&j.child.link) =>
        {
            (LinkJoint::Revolute, true)
        }
        JointType::Continuous => (LinkJoint::Continuous, false),
        JointType::Revolute => (LinkJoint::Revolute, true),
        _ => return Err(()),
    })
}

/// Walks the joint tree from the root: every link with its owner and frame, and the arms.
pub(super) fn walk(
    src: &UrdfSource,
    roles: &JointRoles,
    meshes: &mut super::mesh::MeshCache,
    issues: &mut Vec<SpecIssue>,
    warnings: &mut Vec<String>,
) -> (Vec<ImportedLink>, Vec<ImportedArm>) {
    check_roles(src, roles, issues);
    let Some(root) = root_link(src, issues) else {
        return (Vec::new(), Vec::new());
    };
    if !issues.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut links = vec![ImportedLink {
        name: root.clone(),
        joint: None,
        kind: LinkJoint::Root,
        owner: Owner::Chassis,
        pose: DAffine3::IDENTITY,
        mass: 0.0,
        shapes: Vec::new(),
    }];
    let mut arms: Vec<ImportedArm> = Vec::new();
    let mut next = 0;
    while next < links.len() {
        let (parent_name, parent_owner, parent_pose) = {
            let p = &links[next];
            (p.name.clone(), p.owner, p.pose)
        };
        next += 1;
        for j in src
            .robot
            .joints
            .iter()
            .filter(|j| j.parent.link == parent_name)
        {
            let at = key(&src.joint(&j.name));
            if !finite_pose(&j.origin) {
                issues.push(SpecIssue::new(
                    &at,
                    "its <origin> has a number that is not finite",
                ));
                continue;
            }
            let mut frame = parent_pose * pose(&j.origin);
            if let Some(m) = too_far(frame) {
                issues.push(SpecIssue::new(&at, m));
                continue;
            }
            let (kind, owner) = match role(src, j, roles, &mut frame, warnings) {
                Ok((kind, false)) => (kind, parent_owner),
                Ok((kind, true)) => {
                    if let Owner::Arm(i) = parent_owner {
                        issues.push(SpecIssue::new(
                            &at,
                            format!(
                                "a revolute joint on arm \"{}\": tracksim's arms hang on the \
                                 chassis; make this joint fixed (or list it in `rigid_joints`)",
                                arms[i].joint
                            ),
                        ));
                        continue;
                    }
                    match arm(src, j, frame, issues) {
                        Some(a) => arms.push(a),
                        None => continue,
                    }
                    (kind, Owner::Arm(arms.len() - 1))
                }
                Err(()) => {
                    issues.push(SpecIssue::new(
                        &at,
                        format!(
                            "type \"{}\" is not simulated: tracksim has a chassis with \
                             revolute arms (fixed joints are merged, continuous ones are \
                             wheels inside a track); make it fixed or revolute, or list it in \
                             `rigid_joints`",
                            format!("{:?}", j.joint_type).to_ascii_lowercase()
                        ),
                    ));
                    continue;
                }
            };
            links.push(ImportedLink {
                name: j.child.link.clone(),
                joint: Some(j.name.clone()),
                kind,
                owner,
                pose: frame,
                mass: 0.0,
                shapes: Vec::new(),
            });
        }
    }
    if links.len() < src.robot.links.len() && issues.is_empty() {
        let missing: Vec<&str> = src
            .robot
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|n| !links.iter().any(|k| k.name == *n))
            .collect();
        issues.push(SpecIssue::new(
            "urdf",
            format!(
                "links {} are not reached from the root link \"{root}\": their joints form a \
                 loop",
                missing.join(", ")
            ),
        ));
    }
    for l in &mut links {
        super::inertial::link_mass(src, l, issues, warnings);
        super::shapes::link_shapes(src, l, meshes, issues);
        super::inertial::far_com(src, l, warnings);
    }
    (links, arms)
}

/// A revolute joint on the chassis as an arm: its pivot, axis (frame `frame`), limits and
/// effort, checked.
fn arm(
    src: &UrdfSource,
    j: &urdf_rs::Joint,
    frame: DAffine3,
    issues: &mut Vec<SpecIssue>,
) -> Option<ImportedArm> {
    let at = key(&src.joint(&j.name));
    let n = issues.len();
    let axis = DVec3::from_array(j.axis.xyz.0);
    if !axis.is_finite() || axis.length() < 1e-9 {
        issues.push(SpecIssue::new(
            &at,
            "its <axis xyz> must be a non-zero, finite vector",
        ));
    }
    let l = &j.limit;
    let continuous = j.joint_type == JointType::Continuous;
    if !continuous
        && (!(l.lower.is_finite() || l.lower == f64::NEG_INFINITY)
            || !(l.upper.is_finite() || l.upper == f64::INFINITY)
            || l.lower >= l.upper)
    {
        issues.push(SpecIssue::new(
            &at,
            format!(
                "its <limit lower=\"{}\" upper=\"{}\"> must have lower < upper, rad (a URDF \
                 revolute joint needs both; an unbounded one is `continuous`)",
                l.lower, l.upper
            ),
        ));
    }
    if !(l.effort.is_finite() && l.effort >= 0.0) {
        issues.push(SpecIssue::new(
            &at,
            format!(
                "its <limit effort=\"{}\"> must be a torque >= 0, N m",
                l.effort
            ),
        ));
    }
    if issues.len() != n {
        return None;
    }
    let limits =
        (!continuous && l.lower.is_finite() && l.upper.is_finite()).then_some([l.lower, l.upper]);
    Some(ImportedArm {
        joint: j.name.clone(),
        link: j.child.link.clone(),
        pivot: frame.translation,
        axis: (frame.matrix3 * axis).normalize(),
        limits,
        effort: l.effort,
    })
}

/// How far the collision shapes of joint `j`'s child link sit off the joint's axis, m, when one
/// does: a shape whose centre is more than 1 mm from the axis line, or a cylinder centred on it
/// whose own axis is not the joint's. A wheel's, sprocket's or idler's shapes (a coaxial
/// cylinder, a sphere, a box or mesh centred on the axis) spin in place: `None`.
fn off_axis(src: &UrdfSource, j: &urdf_rs::Joint) -> Option<f64> {
    const ON_AXIS_M: f64 = 1e-3;
    let axis = DVec3::from_array(j.axis.xyz.0).try_normalize()?;
    let link = src.robot.links.iter().find(|l| l.name == j.child.link)?;
    let mut worst: Option<f64> = None;
    for c in &link.collision {
        let p = pose(&c.origin);
        let centre = p.translation;
        // Distance of the shape's centre from the axis line through the link's origin.
        let d = (centre - axis * centre.dot(axis)).length();
        let tilted = match &c.geometry {
            urdf_rs::Geometry::Cylinder { .. } | urdf_rs::Geometry::Capsule { .. } => {
                (p.matrix3 * DVec3::Z).cross(axis).length() > 1e-3
            }
            _ => false,
        };
        if d > ON_AXIS_M || tilted {
            worst = Some(worst.map_or(d, |w: f64| w.max(d)));
        }
    }
    worst
}

/// A revolute joint whose limits are one finite angle: locked there.
fn locked(j: &urdf_rs::Joint) -> bool {
    j.limit.lower.is_finite() && j.limit.lower == j.limit.upper
}
