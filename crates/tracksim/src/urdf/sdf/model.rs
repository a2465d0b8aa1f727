//! An SDF `<model>` converted into the robot a URDF file gives ([`UrdfSource`]): links with
//! their `<inertial>` and `<collision>` elements, joints with their origin, axis and limits,
//! line numbers for messages, the tracked-vehicle plugin and `<mu>` friction. Everything
//! downstream (the tree walk, the checks, the compile, `check`'s report) is the URDF path's.
//!
//! Frames. URDF puts a link's frame where its parent joint is, and a joint's axis through the
//! child's origin; SDF places links and joints freely (`pose.rs`). The conversion keeps each
//! link's own SDF frame (a track's path in the vehicle file is in that frame) except the root
//! link's, which is the model frame (the vehicle is built in the model frame): a URDF
//! origin is the child link's frame in its parent's, every `<inertial>` and `<collision>`
//! pose is re-expressed in its link's frame, and an axis is turned from the frame it is
//! expressed in into the child link's frame. A joint whose `<pose>` is only a rotation of the
//! child's frame is exact this way; one that moves the axis off the child's origin is exact
//! for fixed and continuous joints and joints locked at 0 (the place of their axis does not
//! matter), and refused for a flipper (its pivot would move).

use super::file::{Ctx, Node, child, children, choose_model, number_of, numbers, text};
use super::geometry::{Shape, shape};
use super::pose::{Frames, MODEL, pose_of};
use crate::error::SpecIssue;
use crate::urdf::gazebo::{GazeboExtensions, is_tracked_vehicle, read_plugin};
use crate::urdf::source::UrdfSource;
use glam::{DAffine3, DQuat, DVec3, EulerRot};
use std::collections::{HashMap, HashSet};
use std::path::Path;
use urdf_rs::{JointType, Vec3};

/// SDFormat's "no limit" (the default `<lower>` and `<upper>` are -1e16 and 1e16), rad.
const UNLIMITED: f64 = 1e16;

/// A transform as a URDF `<origin>` (xyz, rpy about the fixed axes).
fn to_pose(x: DAffine3) -> urdf_rs::Pose {
    let (y, p, r) = DQuat::from_mat3(&x.matrix3).to_euler(EulerRot::ZYX);
    urdf_rs::Pose {
        xyz: Vec3(x.translation.to_array()),
        rpy: Vec3([r, p, y]),
    }
}

/// Reads the robot `<model>` of the parsed SDF file `doc` (`wanted`: the vehicle file's
/// `sdf_model`) as the robot a URDF file gives.
pub(in crate::urdf) fn read_model(
    path: &Path,
    doc: &roxmltree::Document,
    wanted: Option<&str>,
) -> Result<UrdfSource, Vec<SpecIssue>> {
    let ctx = Ctx {
        path,
        doc,
        key: "urdf",
    };
    let m = choose_model(&ctx, wanted).map_err(|e| vec![e])?;
    let mut issues = Vec::new();
    old_version(&ctx, &mut issues);
    refuse_parts(&ctx, m, &mut issues);
    if !issues.is_empty() {
        return Err(issues);
    }
    let frames = Frames::read(&ctx, m, &mut issues);
    let child_links: HashSet<&str> = children(m, "joint")
        .filter_map(|j| child(j, "child").map(text))
        .collect();
    let roots: Vec<&str> = children(m, "link")
        .filter_map(|l| l.attribute("name"))
        .filter(|n| !child_links.contains(n))
        .collect();
    let mut frame_of = HashMap::new();
    let mut src = UrdfSource {
        path: path.to_path_buf(),
        robot: urdf_rs::Robot {
            name: m.attribute("name").unwrap_or_default().to_string(),
            version: None,
            links: Vec::new(),
            joints: Vec::new(),
            materials: Vec::new(),
        },
        link_lines: HashMap::new(),
        joint_lines: HashMap::new(),
        with_inertial: HashSet::new(),
        gazebo: GazeboExtensions::default(),
        start_pose: start_pose(&ctx, m).map_err(|e| vec![e])?,
    };
    for l in children(m, "link") {
        let name = l.attribute("name").unwrap_or_default();
        let f = match frames.resolve(name) {
            Ok(_) if roots == [name] => DAffine3::IDENTITY,
            Ok(x) => x,
            Err(e) => {
                issues.push(ctx.issue(l, e));
                continue;
            }
        };
        frame_of.insert(name.to_string(), f);
        src.link_lines.insert(name.to_string(), ctx.line(l));
        src.with_inertial.insert(name.to_string());
        if let Some(link) = link(&ctx, &frames, l, f, &mut src.gazebo, &mut issues) {
            src.robot.links.push(link);
        }
    }
    for j in children(m, "joint") {
        let name = j.attribute("name").unwrap_or_default();
        src.joint_lines.insert(name.to_string(), ctx.line(j));
        if let Some(joint) = joint(&ctx, &frames, j, &frame_of, &mut issues) {
            src.robot.joints.push(joint);
        }
    }
    for p in children(m, "plugin").filter(|p| is_tracked_vehicle(*p)) {
        let line = |n: Node| ctx.line(n);
        let mut plugin = read_plugin(p, &line, &mut src.gazebo.unreadable);
        plugin.file = ctx.file();
        src.gazebo.plugin = Some(plugin);
    }
    if issues.is_empty() {
        Ok(src)
    } else {
        Err(issues)
    }
}

/// SDFormat before 1.5 (a joint axis in the model frame) is refused: `gz sdf -p` upgrades it.
fn old_version(ctx: &Ctx, issues: &mut Vec<SpecIssue>) {
    let root = ctx.doc.root_element();
    let v = root.attribute("version").unwrap_or_default();
    let mut parts = v.split('.').map(|p| p.trim().parse::<u32>().ok());
    if let (Some(Some(major)), Some(Some(minor))) = (parts.next(), parts.next())
        && (major, minor) < (1, 5)
    {
        issues.push(ctx.issue(
            root,
            format!(
                "version {v}: SDFormat before 1.5 puts joint axes in the model frame; upgrade \
                 it with `gz sdf -p {}` (tracksim reads 1.5 to 1.9)",
                ctx.file()
            ),
        ));
    }
}

/// The parts of a model tracksim does not read: `<include>`, nested `<model>`s, links and
/// joints without a name.
fn refuse_parts(ctx: &Ctx, m: Node, issues: &mut Vec<SpecIssue>) {
    for n in children(m, "include") {
        issues.push(ctx.issue(
            n,
            format!(
                "an <include> is not read: expand it, e.g. `gz sdf -p {} > expanded.sdf`, and \
                 name the result",
                ctx.file()
            ),
        ));
    }
    for n in children(m, "model") {
        issues.push(ctx.issue(
            n,
            "a nested <model> is not read: tracksim reads one model's links and joints; merge \
             it into its parent model",
        ));
    }
    for n in children(m, "link").chain(children(m, "joint")) {
        if n.attribute("name").is_none_or(|v| v.trim().is_empty()) {
            issues.push(ctx.issue(n, "has no name"));
        }
    }
    for j in children(m, "joint") {
        for tag in ["parent", "child"] {
            if child(j, tag).is_none_or(|c| text(c).is_empty()) {
                issues.push(ctx.issue(j, format!("has no <{tag}> link")));
            }
        }
    }
}

/// The model's pose in its world (the robot's start pose): `Some` in a world (the identity
/// without a `<pose>`), or for a model file's model with a `<pose>`.
pub(super) fn start_pose(ctx: &Ctx, m: Node) -> Result<Option<DAffine3>, SpecIssue> {
    let in_world = m.parent_element().is_some_and(|p| p.has_tag_name("world"));
    let p = pose_of(ctx, m)?;
    if let Some(r) = &p.relative_to
        && r != "world"
    {
        return Err(ctx.issue(
            m,
            format!(
                "its <pose relative_to=\"{}\">: a robot's pose is read in the world frame only",
                crate::check::echoed(r)
            ),
        ));
    }
    Ok((in_world || child(m, "pose").is_some()).then_some(p.x))
}

/// One `<link>` (its frame `f` in the model frame) as a URDF link; its friction in `gazebo`.
fn link(
    ctx: &Ctx,
    frames: &Frames,
    l: Node,
    f: DAffine3,
    gazebo: &mut GazeboExtensions,
    issues: &mut Vec<SpecIssue>,
) -> Option<urdf_rs::Link> {
    let name = l.attribute("name")?;
    let inv = f.inverse();
    let place = |n: Node| -> Result<DAffine3, SpecIssue> {
        let raw = pose_of(ctx, n)?;
        frames.place(&raw, name).map_err(|m| ctx.issue(n, m))
    };
    let n = issues.len();
    let inertial = match inertial(ctx, l, &place) {
        Ok((x, mass, inertia)) => urdf_rs::Inertial {
            origin: to_pose(inv * x),
            mass: urdf_rs::Mass { value: mass },
            inertia,
        },
        Err(e) => {
            issues.push(e);
            urdf_rs::Inertial::default()
        }
    };
    let mut collision = Vec::new();
    for c in children(l, "collision") {
        if let Some(mu) = child(c, "surface")
            .and_then(|s| child(s, "friction"))
            .and_then(|s| child(s, "ode"))
            .and_then(|s| child(s, "mu"))
        {
            match numbers(ctx, mu, &[1]) {
                Ok(v) => {
                    gazebo.friction.entry(name.to_string()).or_insert(v[0]);
                }
                Err(e) => issues.push(e),
            }
        }
        match collision_of(ctx, c, &place) {
            Ok(Some((x, geometry))) => collision.push(urdf_rs::Collision {
                name: c.attribute("name").map(String::from),
                origin: to_pose(inv * x),
                geometry,
            }),
            Ok(None) => {}
            Err(e) => issues.push(e),
        }
    }
    (issues.len() == n).then(|| urdf_rs::Link {
        name: name.to_string(),
        inertial,
        visual: Vec::new(),
        collision,
    })
}

/// A link's `<inertial>` (SDF's default without one: 1 kg, unit inertia, at the link's
/// origin): its frame in the model frame, mass (kg), inertia (kg m^2).
fn inertial(
    ctx: &Ctx,
    l: Node,
    place: &dyn Fn(Node) -> Result<DAffine3, SpecIssue>,
) -> Result<(DAffine3, f64, urdf_rs::Inertia), SpecIssue> {
    let Some(i) = child(l, "inertial") else {
        let ones = urdf_rs::Inertia {
            ixx: 1.0,
            iyy: 1.0,
            izz: 1.0,
            ..Default::default()
        };
        return Ok((place(l)?, 1.0, ones));
    };
    let x = place(i)?;
    let mass = number_of(ctx, i, "mass", 1.0)?;
    let t = child(i, "inertia");
    let get = |tag: &str, d: f64| t.map_or(Ok(d), |t| number_of(ctx, t, tag, d));
    let inertia = urdf_rs::Inertia {
        ixx: get("ixx", 1.0)?,
        ixy: get("ixy", 0.0)?,
        ixz: get("ixz", 0.0)?,
        iyy: get("iyy", 1.0)?,
        iyz: get("iyz", 0.0)?,
        izz: get("izz", 1.0)?,
    };
    Ok((x, mass, inertia))
}

/// A `<collision>`: its frame in the model frame and geometry (`None`: a plane or empty
/// geometry, which a robot link does not use).
fn collision_of(
    ctx: &Ctx,
    c: Node,
    place: &dyn Fn(Node) -> Result<DAffine3, SpecIssue>,
) -> Result<Option<(DAffine3, urdf_rs::Geometry)>, SpecIssue> {
    let x = place(c)?;
    let g = child(c, "geometry").ok_or_else(|| ctx.issue(c, "has no <geometry>"))?;
    let geometry = match shape(ctx, g)? {
        Shape::Box(s) => urdf_rs::Geometry::Box { size: Vec3(s) },
        Shape::Cylinder { radius, length } => urdf_rs::Geometry::Cylinder { radius, length },
        Shape::Capsule { radius, length } => urdf_rs::Geometry::Capsule { radius, length },
        Shape::Sphere(radius) => urdf_rs::Geometry::Sphere { radius },
        Shape::Mesh { file, scale } => urdf_rs::Geometry::Mesh {
            filename: file,
            scale: Some(Vec3(scale)),
        },
        Shape::Plane(_) | Shape::Empty => return Ok(None),
        Shape::Heightmap { .. } => {
            return Err(ctx.issue(
                c,
                "a <heightmap> on a robot's link is not read (it is terrain: a static model)",
            ));
        }
    };
    Ok(Some((x, geometry)))
}

/// A joint's type, axis (in the frame it is expressed in) and limits as read.
struct Axis {
    xyz: DVec3,
    frame: DAffine3,
    lower: f64,
    upper: f64,
    effort: f64,
    limited: bool,
}

/// The `<axis>` of joint `j` (its own frame `joint_frame` in the model frame).
fn axis(ctx: &Ctx, frames: &Frames, j: Node, joint_frame: DAffine3) -> Result<Axis, SpecIssue> {
    let mut out = Axis {
        xyz: DVec3::Z,
        frame: joint_frame,
        lower: -UNLIMITED,
        upper: UNLIMITED,
        effort: -1.0,
        limited: false,
    };
    let Some(a) = child(j, "axis") else {
        return Ok(out);
    };
    if let Some(x) = child(a, "xyz") {
        let v = numbers(ctx, x, &[3])?;
        out.xyz = DVec3::new(v[0], v[1], v[2]);
        out.frame = match x.attribute("expressed_in").map(str::trim) {
            None | Some("") => joint_frame,
            Some(MODEL) => DAffine3::IDENTITY,
            Some(name) => frames.resolve(name).map_err(|m| ctx.issue(x, m))?,
        };
    }
    if child(a, "use_parent_model_frame").is_some_and(|u| matches!(text(u), "1" | "true")) {
        out.frame = DAffine3::IDENTITY;
    }
    if let Some(l) = child(a, "limit") {
        out.lower = number_of(ctx, l, "lower", -UNLIMITED)?;
        out.upper = number_of(ctx, l, "upper", UNLIMITED)?;
        out.effort = number_of(ctx, l, "effort", -1.0)?;
        out.limited = true;
    }
    Ok(out)
}

/// One `<joint>` as a URDF joint (`frame_of`: each link's frame in the model frame).
fn joint(
    ctx: &Ctx,
    frames: &Frames,
    j: Node,
    frame_of: &HashMap<String, DAffine3>,
    issues: &mut Vec<SpecIssue>,
) -> Option<urdf_rs::Joint> {
    let name = j.attribute("name").unwrap_or_default();
    let link_of = |tag: &str| child(j, tag).map(text).unwrap_or_default().to_string();
    let (parent, child_link) = (link_of("parent"), link_of("child"));
    let mut fail = |m: String| {
        issues.push(ctx.issue(j, m));
        None
    };
    if parent == "world" {
        return fail("its parent is the world: a robot is free, not joined to the world".into());
    }
    let mut kind = match j.attribute("type").unwrap_or_default() {
        "fixed" => JointType::Fixed,
        "revolute" => JointType::Revolute,
        "continuous" => JointType::Continuous,
        "prismatic" => JointType::Prismatic,
        "ball" => JointType::Spherical,
        other => {
            return fail(format!(
                "type \"{}\" is not simulated: tracksim has a chassis with revolute arms; make \
                 it fixed or revolute",
                crate::check::echoed(other)
            ));
        }
    };
    let joint_frame = match frames.resolve(name) {
        Ok(x) => x,
        Err(m) => return fail(m),
    };
    let a = match axis(ctx, frames, j, joint_frame) {
        Ok(a) => a,
        Err(e) => {
            issues.push(e);
            return None;
        }
    };
    if kind == JointType::Revolute
        && (!a.limited || (a.lower <= -UNLIMITED && a.upper >= UNLIMITED))
    {
        kind = JointType::Continuous;
    }
    let (fp, fc) = match (frame_of.get(&parent), frame_of.get(&child_link)) {
        (Some(p), Some(c)) => (*p, *c),
        // An unknown link: the tree walk names it.
        _ => (DAffine3::IDENTITY, DAffine3::IDENTITY),
    };
    let sdf_child = frames.resolve(&child_link).unwrap_or(fc);
    let offset = (sdf_child.inverse() * joint_frame).translation;
    let pivot_matters = kind == JointType::Revolute && !(a.lower == 0.0 && a.upper == 0.0);
    if pivot_matters && offset.length() > 1e-9 {
        return fail(format!(
            "its <pose> puts the axis {:.6} m from its child link's origin: tracksim turns a \
             flipper about its link's origin; move the child link's frame onto the axis (and \
             give the joint a zero <pose>)",
            offset.length()
        ));
    }
    let xyz = fc.matrix3.transpose() * (a.frame.matrix3 * a.xyz);
    let bound = |v: f64, inf: f64| if v.abs() >= UNLIMITED { inf } else { v };
    Some(urdf_rs::Joint {
        name: name.to_string(),
        joint_type: kind,
        origin: to_pose(fp.inverse() * fc),
        parent: urdf_rs::LinkName { link: parent },
        child: urdf_rs::LinkName { link: child_link },
        axis: urdf_rs::Axis {
            xyz: Vec3(xyz.to_array()),
        },
        limit: urdf_rs::JointLimit {
            lower: bound(a.lower, f64::NEG_INFINITY),
            upper: bound(a.upper, f64::INFINITY),
            // SDF's -1 is "no limit": the vehicle file gives the torque (`max_torque_nm`).
            effort: a.effort.max(0.0),
            velocity: 0.0,
            acceleration: f64::INFINITY,
            deceleration: f64::INFINITY,
            jerk: f64::INFINITY,
        },
        calibration: None,
        dynamics: None,
        mimic: None,
        safety_controller: None,
    })
}
