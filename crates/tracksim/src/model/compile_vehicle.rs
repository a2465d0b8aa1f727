//! Compiling a [`VehicleSpec`] into a [`VehicleModel`], in named stages run in this order: the
//! name, the body (`body`), each flipper (`flipper`), each track (`compile_track.rs`), then the
//! track names (`check_track_names`). Every problem is reported with its key path, in that
//! order.

use super::compile_track::compile_track;
use super::mounts::Mounts;
use super::{BodyModel, CollisionShape, FlipperModel, TrackModel, UrdfRobot, VehicleModel};
use crate::check::{Checker, v3};
use crate::error::{Result, SpecIssue};
use crate::spec::{BodySpec, FlipperSpec, ShapeSpec, VehicleSpec};
use glam::DVec3;

/// Checks a collision shape and compiles it.
fn shape(c: &mut Checker, key: &str, s: &ShapeSpec) -> CollisionShape {
    match s {
        ShapeSpec::Box { size_m, centre_m } => {
            for (i, v) in size_m.iter().enumerate() {
                c.positive(&format!("{key}.size_m[{i}]"), *v, "m");
            }
            c.finite(&format!("{key}.centre_m"), centre_m);
            CollisionShape::Box {
                half: v3(*size_m) * 0.5,
                centre: v3(*centre_m),
            }
        }
        ShapeSpec::Convex { points_m } => {
            let pts = c.points(&format!("{key}.points_m"), points_m);
            CollisionShape::Convex(pts)
        }
    }
}

fn box_inertia(mass: f64, size: DVec3) -> DVec3 {
    DVec3::new(
        size.y * size.y + size.z * size.z,
        size.x * size.x + size.z * size.z,
        size.x * size.x + size.y * size.y,
    ) * (mass / 12.0)
}

/// Compiles a vehicle description, reporting every problem with its key path. A file with
/// `urdf` needs its folder: use [`compile_vehicle_in`].
pub fn compile_vehicle(spec: &VehicleSpec) -> Result<VehicleModel, Vec<SpecIssue>> {
    compile_vehicle_with(spec, None)
}

/// Compiles a vehicle description whose relative paths (`urdf`) are relative to `dir`: the
/// URDF robot is read and checked first, then the vehicle as [`compile_vehicle_with`] does.
pub fn compile_vehicle_in(
    spec: &VehicleSpec,
    dir: &std::path::Path,
) -> Result<VehicleModel, Vec<SpecIssue>> {
    match &spec.urdf {
        None => {
            if spec.sdf_model.is_some() {
                return Err(vec![SpecIssue::new(
                    "sdf_model",
                    "only used with `urdf` naming an SDF file: remove it",
                )]);
            }
            compile_vehicle_with(spec, None)
        }
        Some(file) => {
            let robot = UrdfRobot::load_with(
                &dir.join(file),
                spec.sdf_model.as_deref(),
                &joint_roles(spec),
            )?;
            compile_vehicle_with(spec, Some(&robot))
        }
    }
}

/// What `spec` says of its URDF robot's joints: `rigid_joints`, `flipper_joints` and the
/// links its tracks hang on.
pub fn joint_roles(spec: &VehicleSpec) -> crate::urdf::JointRoles {
    crate::urdf::JointRoles {
        rigid: spec.rigid_joints.clone(),
        flippers: spec.flipper_joints.clone(),
        track_links: spec
            .tracks
            .iter()
            .flat_map(|t| [t.link.clone(), t.mirror_link.clone()])
            .flatten()
            .collect(),
    }
}

/// Compiles a vehicle description with its URDF robot, if it has `urdf`.
pub fn compile_vehicle_with(
    spec: &VehicleSpec,
    robot: Option<&UrdfRobot>,
) -> Result<VehicleModel, Vec<SpecIssue>> {
    let mut c = Checker::default();
    if spec.name.trim().is_empty() {
        c.push("name", "must not be empty");
    }
    let (body, flippers, mounts, urdf, separation) = match (robot, &spec.urdf) {
        (Some(r), Some(_)) => {
            let parts = super::compile_urdf::compile_urdf(&mut c, spec, r);
            (
                parts.body,
                parts.flippers,
                Mounts::of_urdf(r),
                Some(parts.report),
                parts.tracks_separation,
            )
        }
        (_, urdf) => {
            if urdf.is_some() {
                c.push(
                    "urdf",
                    "the URDF file is read relative to the vehicle file: load the vehicle with \
                     load_vehicle or compile_vehicle_in",
                );
            }
            file_parts(&mut c, spec)
        }
    };
    let mut tracks: Vec<TrackModel> = Vec::new();
    if spec.tracks.is_empty() {
        c.push("tracks", "a vehicle needs at least one track");
    }
    for (i, t) in spec.tracks.iter().enumerate() {
        if t.path.spatial {
            c.push(
                format!("tracks[{i}].path.spatial"),
                "a vehicle's track runs in a plane; spatial loops are for [[terrain.conveyors]]: remove `spatial`",
            );
        }
        compile_track(&mut c, &mounts, &format!("tracks[{i}]"), t, &mut tracks);
    }
    check_track_names(&mut c, &tracks);
    let odometry_separation = spec
        .odometry
        .as_ref()
        .and_then(|o| o.track_separation_m)
        .or(separation);
    if let Some(b) = odometry_separation {
        c.positive("odometry.track_separation_m", b, "m");
    }
    let steering = steering(&mut c, spec, robot, separation, &tracks);
    let sensors = super::compile_sensor::compile_sensors(&mut c, &spec.sensors, &mounts);
    let colors = vehicle_colors(&mut c, spec, robot);
    if c.issues.is_empty() {
        Ok(VehicleModel {
            colors,
            name: spec.name.clone(),
            description: spec.description.clone(),
            body,
            flippers,
            tracks,
            odometry_separation,
            steering,
            sensors,
            urdf,
        })
    } else {
        Err(c.issues)
    }
}

/// The twist rule of `spec` (`[steering]`): per side by default when the robot's
/// tracked-vehicle plugin names sides (its `tracks_separation` the default B), else per track.
fn steering(
    c: &mut Checker,
    spec: &VehicleSpec,
    robot: Option<&UrdfRobot>,
    plugin_separation: Option<f64>,
    tracks: &[TrackModel],
) -> super::Steering {
    let given = spec.steering.clone().unwrap_or_default();
    let plugin_sides = robot
        .and_then(|r| r.plugin.as_ref())
        .is_some_and(|p| !p.left_tracks.is_empty() || !p.right_tracks.is_empty());
    let per_side = given.one_speed_per_side.unwrap_or(plugin_sides);
    if !per_side {
        if given.track_separation_m.is_some() {
            c.push(
                "steering.track_separation_m",
                "is the separation of the per-side rule: set `one_speed_per_side = true` or \
                 remove it",
            );
        }
        return super::Steering::PER_TRACK;
    }
    let offsets: Vec<f64> = tracks.iter().map(TrackModel::lateral_offset).collect();
    let separation = given
        .track_separation_m
        .or(plugin_separation)
        .unwrap_or_else(|| super::side_separation(&offsets));
    if separation <= 0.0 && given.track_separation_m.is_none() && !tracks.is_empty() {
        c.push(
            "steering.one_speed_per_side",
            "needs tracks on both sides of the chassis (or `track_separation_m`)",
        );
    } else {
        c.positive("steering.track_separation_m", separation, "m");
    }
    super::Steering {
        per_side,
        separation,
    }
}

/// The chassis and flippers of a vehicle file without `urdf` (`[body]`, `[[flippers]]`).
#[allow(clippy::type_complexity)]
fn file_parts(
    c: &mut Checker,
    spec: &VehicleSpec,
) -> (
    BodyModel,
    Vec<FlipperModel>,
    Mounts,
    Option<super::UrdfReport>,
    Option<f64>,
) {
    for (key, given) in [
        ("body_friction", spec.body_friction.is_some()),
        ("joints", !spec.joints.is_empty()),
        ("rigid_joints", !spec.rigid_joints.is_empty()),
        ("flipper_joints", spec.flipper_joints.is_some()),
    ] {
        if given {
            c.push(
                key,
                "only used with `urdf` (without it the chassis is [body], with its own friction, \
                 and the arms [[flippers]])",
            );
        }
    }
    let body = match &spec.body {
        Some(b) => body(c, b),
        None => {
            c.push(
                "body",
                "missing: a vehicle needs [body] (the chassis), or `urdf` naming the robot's \
                 URDF file",
            );
            body(c, &placeholder_body())
        }
    };
    let mut flippers = Vec::new();
    for (i, f) in spec.flippers.iter().enumerate() {
        flippers.push(flipper(c, &spec.flippers, i, f));
    }
    let mounts = Mounts::of_flippers(spec.flippers.iter().map(|f| f.name.as_str()));
    (body, flippers, mounts, None, None)
}

/// A chassis to go on checking with when [body] is missing (never simulated).
fn placeholder_body() -> BodySpec {
    BodySpec {
        mass_kg: 1.0,
        centre_of_mass_m: [0.0; 3],
        inertia_kgm2: None,
        shape: ShapeSpec::Box {
            size_m: [0.1; 3],
            centre_m: [0.0; 3],
        },
        friction: 0.6,
    }
}

/// Body stage: checks the chassis and compiles it (inertia from the shape's bounding box when
/// not given).
fn body(c: &mut Checker, b: &BodySpec) -> BodyModel {
    c.positive("body.mass_kg", b.mass_kg, "kg");
    c.non_negative("body.friction", b.friction, "");
    c.finite("body.centre_of_mass_m", &b.centre_of_mass_m);
    let body_shape = shape(c, "body.shape", &b.shape);
    let inertia = match b.inertia_kgm2 {
        Some(i) => {
            for (k, v) in i.iter().enumerate() {
                c.positive(&format!("body.inertia_kgm2[{k}]"), *v, "kg m^2");
            }
            v3(i)
        }
        None => {
            let (lo, hi) = body_shape.bounds();
            box_inertia(b.mass_kg, hi - lo)
        }
    };
    BodyModel {
        mass: b.mass_kg,
        com: v3(b.centre_of_mass_m),
        inertia,
        inertia_products: DVec3::ZERO,
        shape: body_shape,
        friction: b.friction,
    }
}

/// Flipper stage: checks flipper `i` of `all` and compiles it (initial angle to radians).
fn flipper(c: &mut Checker, all: &[FlipperSpec], i: usize, f: &FlipperSpec) -> FlipperModel {
    let k = format!("flippers[{i}]");
    if f.name == "body" {
        c.push(format!("{k}.name"), "must be a name other than \"body\"");
    } else {
        c.column_name(&format!("{k}.name"), &f.name);
    }
    if all[..i].iter().any(|g| g.name == f.name) {
        c.push(
            format!("{k}.name"),
            format!("duplicate flipper name \"{}\"", f.name),
        );
    }
    c.finite(&format!("{k}.pivot_m"), &f.pivot_m);
    let axis = c.unit_vector(&format!("{k}.axis"), f.axis);
    c.positive(&format!("{k}.mass_kg"), f.mass_kg, "kg");
    c.positive(&format!("{k}.max_torque_nm"), f.max_torque_nm, "N m");
    c.positive(
        &format!("{k}.stiffness_nm_per_rad"),
        f.stiffness_nm_per_rad,
        "N m/rad",
    );
    c.non_negative(
        &format!("{k}.damping_nms_per_rad"),
        f.damping_nms_per_rad,
        "N m s/rad",
    );
    c.finite(&format!("{k}.initial_angle_deg"), &[f.initial_angle_deg]);
    let shape = f.shape.as_ref().map(|s| shape(c, &format!("{k}.shape"), s));
    if let Some(com) = &f.centre_of_mass_m {
        c.finite(&format!("{k}.centre_of_mass_m"), com);
    }
    let com = f.centre_of_mass_m.map(v3).unwrap_or(v3(f.pivot_m));
    let inertia = match f.inertia_kgm2 {
        Some(i) => {
            for (j, v) in i.iter().enumerate() {
                c.positive(&format!("{k}.inertia_kgm2[{j}]"), *v, "kg m^2");
            }
            v3(i)
        }
        None => match &shape {
            Some(s) => {
                let (lo, hi) = s.bounds();
                box_inertia(f.mass_kg, hi - lo)
            }
            None => DVec3::splat(f.mass_kg * 0.01),
        },
    };
    FlipperModel {
        name: f.name.clone(),
        pivot: v3(f.pivot_m),
        axis,
        mass: f.mass_kg,
        com,
        inertia,
        inertia_products: DVec3::ZERO,
        limits: None,
        shape,
        initial_angle: f.initial_angle_deg.to_radians(),
        max_torque: f.max_torque_nm,
        stiffness: f.stiffness_nm_per_rad,
        damping: f.damping_nms_per_rad,
    }
}

/// Track-name stage: every compiled track (mirror images included) needs a unique, non-empty
/// name.
fn check_track_names(c: &mut Checker, tracks: &[TrackModel]) {
    for (i, t) in tracks.iter().enumerate() {
        if t.name.trim().is_empty() {
            c.push("tracks", "every track needs a non-empty name");
        } else if tracks[..i].iter().any(|u| u.name == t.name) {
            c.push(
                "tracks",
                format!(
                    "duplicate track name \"{}\" (check `name` and `mirror`)",
                    t.name
                ),
            );
        }
    }
}

/// The vehicle's `[colors]`: each given colour, else the URDF root link's material colour for
/// the chassis, else the palette's.
fn vehicle_colors(
    c: &mut Checker,
    spec: &VehicleSpec,
    robot: Option<&UrdfRobot>,
) -> super::vehicle::VehicleColors {
    use crate::render::Rgb;
    let mut out = super::vehicle::VehicleColors::default();
    if let Some(urdf) = robot.and_then(|r| r.root_color()) {
        out.body = urdf;
    }
    let Some(s) = &spec.colors else { return out };
    let mut read = |key: &str, v: &Option<String>, into: &mut Rgb| {
        let Some(v) = v else { return };
        match Rgb::parse(v) {
            Some(rgb) => *into = rgb,
            None => c.push(
                format!("colors.{key}"),
                format!(
                    "{:?} is not a colour: write \"#rrggbb\", six hexadecimal digits after a \
                     '#' (e.g. \"#5b633a\")",
                    crate::check::echoed(v)
                ),
            ),
        }
    };
    read("body", &s.body, &mut out.body);
    read("tracks", &s.tracks, &mut out.tracks);
    read("flippers", &s.flippers, &mut out.flippers);
    out
}
