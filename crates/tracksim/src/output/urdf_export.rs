//! `/robot_description` (issue 42): the robot model a ROS tool (RViz's RobotModel, Foxglove's
//! URDF layer, `robot_state_publisher`) draws. A vehicle read from a URDF file (`urdf = ...`)
//! is described by that file's own text ([`robot_description`]); a tracksim (TOML) vehicle by
//! a URDF generated from its compiled model ([`vehicle_urdf`]):
//! - `base_link`: the chassis's collision shapes as visuals and collisions (a convex hull as
//!   its bounding box: URDF has no convex primitive);
//! - per flipper a link `<flipper>_flipper_link` (the frame `/tf` moves) on a revolute joint
//!   named as the flipper (the name `/joint_states` gives it), origin at the pivot, its axis
//!   and its limits (continuous without limits);
//! - per track a link `<track>_track_link` fixed to its parent (the chassis or its flipper's
//!   link) with its path's outline as thin boxes (one per 1/24 of the loop, belt width by belt
//!   thickness);
//! - per sensor (encoders aside) its frame as a fixed link on its mount, a camera's optical
//!   frame below it, as `/tf_static` has them.
//!
//! Names and numbers are escaped for XML attributes with `quick-xml`'s escaping.

use super::ros_messages::{BASE_FRAME, flipper_frame, optical_rotation};
use super::ros_sensors::{link_frame, message_frame};
use crate::model::{CollisionShape, Mount, Parent, Scenario, SensorKind, VehicleModel};
use glam::{DQuat, DVec3, EulerRot};
use std::fmt::Write;

/// Boxes per track outline.
const TRACK_BOXES: usize = 24;

/// The frame of track `name`'s link in the generated URDF.
pub fn track_frame(name: &str) -> String {
    format!("{name}_track_link")
}

fn esc(s: &str) -> String {
    quick_xml::escape::escape(s).into_owned()
}

fn xyz(v: DVec3) -> String {
    format!("{} {} {}", v.x, v.y, v.z)
}

fn rpy(q: DQuat) -> String {
    let (yaw, pitch, roll) = q.normalize().to_euler(EulerRot::ZYX);
    format!("{roll} {pitch} {yaw}")
}

/// `<visual>` and `<collision>` of one primitive at `at`, `rot` (link frame).
fn primitive(out: &mut String, geometry: &str, at: DVec3, rot: DQuat, colour: Option<&str>) {
    let origin = format!("<origin xyz=\"{}\" rpy=\"{}\"/>", xyz(at), rpy(rot));
    let material = colour.map_or(String::new(), |c| {
        format!("<material name=\"{c}\"><color rgba=\"{c}\"/></material>")
    });
    let _ = writeln!(
        out,
        "    <visual>{origin}<geometry>{geometry}</geometry>{material}</visual>"
    );
    let _ = writeln!(
        out,
        "    <collision>{origin}<geometry>{geometry}</geometry></collision>"
    );
}

/// A collision shape, shifted by `-offset` (the link's origin in the shape's frame).
fn shape(out: &mut String, s: &CollisionShape, offset: DVec3, colour: &str) {
    let c = Some(colour);
    match s {
        CollisionShape::Box { half, centre } => primitive(
            out,
            &format!("<box size=\"{}\"/>", xyz(*half * 2.0)),
            *centre - offset,
            DQuat::IDENTITY,
            c,
        ),
        CollisionShape::Convex(points) => {
            if points.is_empty() {
                return;
            }
            let lo = points
                .iter()
                .fold(DVec3::splat(f64::INFINITY), |a, p| a.min(*p));
            let hi = points
                .iter()
                .fold(DVec3::splat(f64::NEG_INFINITY), |a, p| a.max(*p));
            primitive(
                out,
                &format!("<box size=\"{}\"/>", xyz(hi - lo)),
                0.5 * (lo + hi) - offset,
                DQuat::IDENTITY,
                c,
            );
        }
        CollisionShape::Sphere { radius, centre } => primitive(
            out,
            &format!("<sphere radius=\"{radius}\"/>"),
            *centre - offset,
            DQuat::IDENTITY,
            c,
        ),
        CollisionShape::Cylinder {
            radius,
            half_length,
            centre,
            rotation,
        } => primitive(
            out,
            &format!(
                "<cylinder radius=\"{radius}\" length=\"{}\"/>",
                2.0 * half_length
            ),
            *centre - offset,
            *rotation,
            c,
        ),
        CollisionShape::Compound(parts) => {
            for p in parts {
                shape(out, p, offset, colour);
            }
        }
    }
}

fn joint(
    out: &mut String,
    name: &str,
    kind: &str,
    parent: &str,
    child: &str,
    at: DVec3,
    rot: DQuat,
) {
    let _ = writeln!(
        out,
        "  <joint name=\"{}\" type=\"{kind}\"><parent link=\"{}\"/><child link=\"{}\"/><origin xyz=\"{}\" rpy=\"{}\"/></joint>",
        esc(name),
        esc(parent),
        esc(child),
        xyz(at),
        rpy(rot)
    );
}

/// The URDF of vehicle `v` (see the module).
pub fn vehicle_urdf(v: &VehicleModel) -> String {
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<robot name=\"{}\">", esc(&v.name));
    let _ = writeln!(out, "  <link name=\"{BASE_FRAME}\">");
    shape(&mut out, &v.body.shape, DVec3::ZERO, "0.35 0.38 0.33 1");
    out.push_str("  </link>\n");
    for f in &v.flippers {
        let link = flipper_frame(&f.name);
        let _ = writeln!(out, "  <link name=\"{}\">", esc(&link));
        if let Some(s) = &f.shape {
            shape(&mut out, s, f.pivot, "0.25 0.25 0.25 1");
        }
        out.push_str("  </link>\n");
        let axis = f.axis.normalize_or_zero();
        let (kind, limit) = match f.limits {
            Some([lo, hi]) => (
                "revolute",
                format!(
                    "<limit lower=\"{lo}\" upper=\"{hi}\" effort=\"{}\" velocity=\"10\"/>",
                    f.max_torque.max(0.0)
                ),
            ),
            None => ("continuous", String::new()),
        };
        let _ = writeln!(
            out,
            "  <joint name=\"{}\" type=\"{kind}\"><parent link=\"{BASE_FRAME}\"/><child link=\"{}\"/><origin xyz=\"{}\" rpy=\"0 0 0\"/><axis xyz=\"{}\"/>{limit}</joint>",
            esc(&f.name),
            esc(&link),
            xyz(f.pivot),
            xyz(axis)
        );
    }
    for t in &v.tracks {
        let (parent, offset) = match t.parent {
            Parent::Body => (BASE_FRAME.to_string(), DVec3::ZERO),
            Parent::Flipper(i) => (flipper_frame(&v.flippers[i].name), v.flippers[i].pivot),
        };
        let link = track_frame(&t.name);
        let _ = writeln!(out, "  <link name=\"{}\">", esc(&link));
        let len = t.path.length();
        for k in 0..TRACK_BOXES {
            let (s0, s1) = (
                len * k as f64 / TRACK_BOXES as f64,
                len * (k + 1) as f64 / TRACK_BOXES as f64,
            );
            let (a, b) = (t.path.frame_at(s0).origin, t.path.frame_at(s1).origin);
            let mid = t.path.frame_at(0.5 * (s0 + s1));
            let size = DVec3::new(
                a.distance(b).max(1e-4),
                t.width.max(1e-4),
                t.belt_thickness.max(1e-3),
            );
            primitive(
                &mut out,
                &format!("<box size=\"{}\"/>", xyz(size)),
                0.5 * (a + b) - offset,
                mid.rotation(),
                Some("0.1 0.1 0.1 1"),
            );
        }
        out.push_str("  </link>\n");
        joint(
            &mut out,
            &format!("{}_track", t.name),
            "fixed",
            &parent,
            &link,
            DVec3::ZERO,
            DQuat::IDENTITY,
        );
    }
    for m in &v.sensors {
        if matches!(m.kind, SensorKind::Encoders(_)) {
            continue;
        }
        let (parent, at) = match m.mount {
            Mount::Body => (BASE_FRAME.to_string(), m.position),
            Mount::Flipper(i) => {
                let f = &v.flippers[i];
                (flipper_frame(&f.name), m.position - f.pivot)
            }
        };
        let link = link_frame(m);
        let _ = writeln!(out, "  <link name=\"{}\"/>", esc(&link));
        joint(
            &mut out,
            &format!("{}_joint", link.replace('/', "_")),
            "fixed",
            &parent,
            &link,
            at,
            m.rotation,
        );
        if matches!(
            m.kind,
            SensorKind::DepthCamera(_) | SensorKind::RgbCamera(_)
        ) {
            let optical = message_frame(m);
            let _ = writeln!(out, "  <link name=\"{}\"/>", esc(&optical));
            joint(
                &mut out,
                &format!("{}_joint", optical.replace('/', "_")),
                "fixed",
                &link,
                &optical,
                DVec3::ZERO,
                optical_rotation(),
            );
        }
    }
    out.push_str("</robot>\n");
    out
}

/// The robot description of `sc`'s vehicle: the URDF file's own text for a vehicle read from
/// one (if it can still be read), else the URDF generated from the model ([`vehicle_urdf`]).
/// `/robot_description` is always URDF (issue 61): a vehicle read from an SDF file (its root
/// element `<sdf>`, which RViz's RobotModel, `robot_state_publisher` and Foxglove's URDF layer
/// cannot draw) and a xacro file (not a URDF yet) are described by the generated URDF.
pub fn robot_description(sc: &Scenario) -> String {
    sc.vehicle
        .urdf
        .as_ref()
        .and_then(|u| std::fs::read_to_string(&u.file).ok())
        .filter(|t| is_urdf(t))
        .unwrap_or_else(|| vehicle_urdf(&sc.vehicle))
}

/// Whether `text` is a URDF a ROS tool reads as it is: its root element is `<robot>` and it
/// uses no xacro.
fn is_urdf(text: &str) -> bool {
    !text.contains("xmlns:xacro")
        && roxmltree::Document::parse(text).is_ok_and(|d| d.root_element().has_tag_name("robot"))
}
