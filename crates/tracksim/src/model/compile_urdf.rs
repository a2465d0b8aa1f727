//! Compiling the chassis and flippers of a vehicle file with `urdf`: the imported robot
//! ([`UrdfRobot`]) becomes the [`BodyModel`] and the [`FlipperModel`]s, with the vehicle file's
//! `[joints.NAME]` control and the tracks bound to links. The collision shapes of a link that
//! carries a track are not used (the belt and grousers are its contact), except the root's;
//! neither are those of wheels on continuous joints. Stages, in order: keys that do not go
//! with `urdf`, the Gazebo plugin's track links, the chassis, the arms, the report.

use super::{BodyModel, CollisionShape, FlipperModel, Parent, UrdfReport};
use crate::urdf::{LinkJoint, LinkLine, Owner, UrdfRobot};

/// The model's name for the body an imported link is part of.
impl From<Owner> for Parent {
    fn from(o: Owner) -> Parent {
        match o {
            Owner::Chassis => Parent::Body,
            Owner::Arm(i) => Parent::Flipper(i),
        }
    }
}
use crate::check::Checker;
use crate::spec::VehicleSpec;
use glam::{DMat3, DVec3};
use std::collections::BTreeSet;

/// What a URDF robot gives the vehicle model.
pub(super) struct UrdfParts {
    /// The chassis.
    pub body: BodyModel,
    /// The arms.
    pub flippers: Vec<FlipperModel>,
    /// `<tracks_separation>` of the Gazebo plugin, m.
    pub tracks_separation: Option<f64>,
    /// What `tracksim check` prints.
    pub report: UrdfReport,
}

/// Diagonal and products [Ixy, Ixz, Iyz] of an inertia tensor.
fn split(i: DMat3) -> (DVec3, DVec3) {
    (
        DVec3::new(i.x_axis.x, i.y_axis.y, i.z_axis.z),
        DVec3::new(i.y_axis.x, i.z_axis.x, i.z_axis.y),
    )
}

/// The names of the links the vehicle file's tracks hang on.
fn track_links(spec: &VehicleSpec) -> BTreeSet<&str> {
    spec.tracks
        .iter()
        .flat_map(|t| [t.link.as_deref(), t.mirror_link.as_deref()])
        .flatten()
        .collect()
}

/// Why link `l`'s collision shapes are not used (`None`: used).
fn dropped(l: &crate::urdf::ImportedLink, tracks: &BTreeSet<&str>) -> Option<&'static str> {
    match l.kind {
        LinkJoint::Continuous => Some("a wheel inside a track (continuous joint)"),
        LinkJoint::Root => None,
        _ if tracks.contains(l.name.as_str()) => {
            Some("the track's belt and grousers touch instead")
        }
        _ => None,
    }
}

/// The used collision shapes of `owner` (one shape alone, several as a compound).
fn owner_shape(robot: &UrdfRobot, owner: Owner, tracks: &BTreeSet<&str>) -> Option<CollisionShape> {
    let mut shapes: Vec<CollisionShape> = robot
        .links
        .iter()
        .filter(|l| l.owner == owner && dropped(l, tracks).is_none())
        .flat_map(|l| l.shapes.iter().cloned())
        .collect();
    match shapes.len() {
        0 => None,
        1 => shapes.pop(),
        _ => Some(CollisionShape::Compound(shapes)),
    }
}

/// Compiles the URDF part of `spec`; problems go to `c`.
pub(super) fn compile_urdf(c: &mut Checker, spec: &VehicleSpec, robot: &UrdfRobot) -> UrdfParts {
    if spec.body.is_some() {
        c.push(
            "body",
            "the chassis comes from the URDF (`urdf`): remove [body]",
        );
    }
    if !spec.flippers.is_empty() {
        c.push(
            "flippers",
            "the flippers are the URDF's revolute joints (`urdf`): remove [[flippers]] and set \
             their control under [joints.NAME]",
        );
    }
    let tracks = track_links(spec);
    plugin_links(c, robot, &tracks);
    let part = robot.mass_part(Owner::Chassis, &mut c.issues);
    let shape = owner_shape(robot, Owner::Chassis, &tracks).unwrap_or_else(|| {
        c.push(
            "urdf",
            format!(
                "the chassis ({}) has no collision shape: give it a <collision>",
                robot.describe_link(&robot.links[0].name)
            ),
        );
        CollisionShape::Box {
            half: DVec3::splat(0.1),
            centre: DVec3::ZERO,
        }
    });
    let friction = spec.body_friction.or(robot.root_friction).unwrap_or(0.6);
    c.non_negative("body_friction", friction, "");
    let (inertia, inertia_products) = split(part.inertia);
    let body = BodyModel {
        mass: part.mass,
        com: part.com,
        inertia,
        inertia_products,
        shape,
        friction,
    };
    let flippers = arms(c, spec, robot, &tracks);
    UrdfParts {
        body,
        report: report(robot, &flippers, spec),
        flippers,
        tracks_separation: robot.plugin.as_ref().and_then(|p| p.tracks_separation),
    }
}

/// Every link the Gazebo plugin names as a track needs a track of the vehicle file.
fn plugin_links(c: &mut Checker, robot: &UrdfRobot, tracks: &BTreeSet<&str>) {
    let Some(p) = &robot.plugin else {
        return;
    };
    for (tag, l) in p.track_links() {
        if !tracks.contains(l) {
            c.push(
                format!("urdf {}", p.at(tag)),
                format!(
                    "the Gazebo plugin names link \"{l}\" as a track; give it a [[tracks]] entry \
                     with `link = \"{l}\"` (its path and grousers in that link's frame)"
                ),
            );
        }
    }
    if let Some(s) = p.tracks_separation {
        c.positive(&format!("urdf {}", p.at("tracks_separation")), s, "m");
    }
}

/// The arms with the vehicle file's `[joints.NAME]` control.
fn arms(
    c: &mut Checker,
    spec: &VehicleSpec,
    robot: &UrdfRobot,
    tracks: &BTreeSet<&str>,
) -> Vec<FlipperModel> {
    let names: Vec<&str> = robot.arms.iter().map(|a| a.joint.as_str()).collect();
    for j in spec.joints.keys() {
        if !names.contains(&j.as_str()) {
            let file = robot.file.file_name().unwrap_or_default().to_string_lossy();
            c.push(
                format!("joints.{j}"),
                format!(
                    "{} (the flipper joints of {file})",
                    crate::check::unknown_name("revolute joint", j, &names)
                ),
            );
        }
    }
    let mut out = Vec::new();
    for (i, a) in robot.arms.iter().enumerate() {
        let k = format!("joints.{}", a.joint);
        c.column_name(
            &format!("urdf {}", robot.describe_joint(&a.joint)),
            &a.joint,
        );
        let ctl = spec.joints.get(&a.joint).cloned().unwrap_or_default();
        let part = robot.mass_part(Owner::Arm(i), &mut c.issues);
        let max_torque = ctl.max_torque_nm.unwrap_or(a.effort);
        if ctl.max_torque_nm.is_none() && a.effort <= 0.0 {
            c.push(
                format!("urdf {}", robot.describe_joint(&a.joint)),
                format!(
                    "its <limit effort> is 0: give the flipper motor's torque limit, N m (or \
                     `[{k}] max_torque_nm`)"
                ),
            );
        } else {
            c.positive(&format!("{k}.max_torque_nm"), max_torque, "N m");
        }
        let stiffness = ctl.stiffness_nm_per_rad.unwrap_or(2000.0);
        let damping = ctl.damping_nms_per_rad.unwrap_or(50.0);
        c.positive(&format!("{k}.stiffness_nm_per_rad"), stiffness, "N m/rad");
        c.non_negative(&format!("{k}.damping_nms_per_rad"), damping, "N m s/rad");
        let start = ctl.initial_angle_deg.unwrap_or(0.0);
        c.finite(&format!("{k}.initial_angle_deg"), &[start]);
        if let Some([lo, hi]) = a.limits
            && !(lo..=hi).contains(&start.to_radians())
        {
            c.push(
                format!("{k}.initial_angle_deg"),
                format!(
                    "{start} deg is outside the joint's limits [{:.1}, {:.1}] deg ({} <limit>)",
                    lo.to_degrees(),
                    hi.to_degrees(),
                    robot.describe_joint(&a.joint)
                ),
            );
        }
        let (inertia, inertia_products) = split(part.inertia);
        out.push(FlipperModel {
            name: a.joint.clone(),
            pivot: a.pivot,
            axis: a.axis,
            mass: part.mass,
            com: part.com,
            inertia,
            inertia_products,
            limits: a.limits,
            shape: owner_shape(robot, Owner::Arm(i), tracks),
            initial_angle: start.to_radians(),
            max_torque,
            stiffness,
            damping,
        });
    }
    out
}

/// The report of what was imported.
fn report(robot: &UrdfRobot, flippers: &[FlipperModel], spec: &VehicleSpec) -> UrdfReport {
    let tracks = track_links(spec);
    let body_name = |p: Owner| match p {
        Owner::Chassis => "chassis".to_string(),
        Owner::Arm(i) => format!("arm {}", robot.arms[i].joint),
    };
    let links = robot
        .links
        .iter()
        .map(|l| LinkLine {
            name: l.name.clone(),
            joint: l.joint.clone(),
            kind: l.kind,
            body: body_name(l.owner),
            mass: l.mass,
            shapes: l.shapes.len(),
            shapes_dropped: dropped(l, &tracks),
            tracks: spec
                .tracks
                .iter()
                .flat_map(|t| {
                    let mut v = Vec::new();
                    if t.link.as_deref() == Some(l.name.as_str()) {
                        v.push(t.name.clone());
                    }
                    if let Some(m) = &t.mirror
                        && t.mirror_link.as_deref().or(t.link.as_deref()) == Some(l.name.as_str())
                    {
                        v.push(m.clone());
                    }
                    v
                })
                .collect(),
        })
        .collect();
    let arms = flippers
        .iter()
        .map(|f| {
            let limits = f.limits.map_or("no limits".to_string(), |[lo, hi]| {
                format!(
                    "limits [{:.1}, {:.1}] deg",
                    lo.to_degrees(),
                    hi.to_degrees()
                )
            });
            format!(
                "{}: pivot {:.3?} m, axis {:.3?}, {limits}, torque limit {} N m, mass {:.3} kg \
                 (links merged), gains {} N m/rad, {} N m s/rad",
                f.name,
                f.pivot.to_array(),
                f.axis.to_array(),
                f.max_torque,
                f.mass,
                f.stiffness,
                f.damping
            )
        })
        .collect();
    let mut notes = Vec::new();
    if let Some(p) = &robot.plugin {
        notes.push(format!(
            "Gazebo TrackedVehicle plugin ({} line {}): left {:?}, right {:?}, flippers {:?} and \
             {:?}, tracks_separation {}",
            p.file,
            p.line,
            p.left_tracks,
            p.right_tracks,
            p.left_flippers,
            p.right_flippers,
            p.tracks_separation
                .map_or("not given".to_string(), |s| format!("{s} m (odometry)"))
        ));
    }
    notes.extend(robot.warnings.iter().map(|w| format!("warning: {w}")));
    if robot.format == "SDF" {
        notes.push(
            "not used from SDF: <visual>, <sensor>, <dynamics>, velocity limits, plugins other \
             than TrackedVehicle (TrackController: tracksim simulates the belt); meshes collide \
             as their convex hull"
                .into(),
        );
        if let Some(x) = robot.start_pose {
            let t = x.translation;
            notes.push(format!(
                "the model's pose in its world, ({:.3}, {:.3}, {:.3}) m, is not used: the \
                 scenario places the vehicle",
                t.x, t.y, t.z
            ));
        }
    } else {
        notes.push(
            "not used from URDF: <visual>, <dynamics>, <mimic>, <safety_controller>, velocity \
             limits; meshes collide as their convex hull"
                .into(),
        );
    }
    notes.extend(separation_warning(robot, spec));
    UrdfReport {
        file: robot.file.clone(),
        format: robot.format,
        robot: robot.name.clone(),
        links,
        arms,
        notes,
        root: robot
            .links
            .first()
            .map_or(String::new(), |l| l.name.clone()),
        joints: robot.joint_frames(),
    }
}

/// The chassis-frame y of the mid-plane of the vehicle file's track on `link` (a mirror image
/// on it: the image's), m.
fn track_y(robot: &UrdfRobot, spec: &VehicleSpec, link: &str) -> Option<f64> {
    spec.tracks.iter().find_map(|t| {
        let plane = DVec3::new(0.0, t.path.plane_y_m.unwrap_or(0.0), 0.0);
        let y = |l: &str| robot.link(l).map(|k| k.pose.transform_point3(plane).y);
        if t.link.as_deref() == Some(link) {
            y(link)
        } else if t.mirror.is_some() && t.mirror_link.as_deref() == Some(link) {
            y(t.link.as_deref()?).map(|v| -v)
        } else {
            None
        }
    })
}

/// A warning when the Gazebo plugin's `tracks_separation` is more than 10 % from the distance
/// between the mid-planes of the tracks on its left and right track links (issue 42: a plugin
/// saying 0.63 m of a robot whose tracks are 0.203 m apart).
fn separation_warning(robot: &UrdfRobot, spec: &VehicleSpec) -> Option<String> {
    let p = robot.plugin.as_ref()?;
    let said = p.tracks_separation?;
    let mean = |links: &[String]| {
        let ys: Vec<f64> = links
            .iter()
            .filter_map(|l| track_y(robot, spec, l))
            .collect();
        (!ys.is_empty()).then(|| ys.iter().sum::<f64>() / ys.len() as f64)
    };
    let found = (mean(&p.left_tracks)? - mean(&p.right_tracks)?).abs();
    (found > 0.0 && ((said - found) / found).abs() > 0.1).then(|| {
        format!(
            "warning: the plugin's <tracks_separation> {said} m is {:+.0} % off the {found:.4} m \
             between the left and right tracks' mid-planes (the odometry uses {said} m unless \
             [odometry] track_separation_m is set)",
            (said - found) / found * 100.0
        )
    })
}
