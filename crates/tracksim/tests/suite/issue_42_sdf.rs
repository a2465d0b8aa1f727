//! Issue 42 (SDF part): a robot and its world brought as SDFormat. gz-sim's
//! `tracked_vehicle_simple.sdf` (from `../shared/robots`, skipped when absent) loads as the
//! robot its file describes: masses summed, the plugin's links read, the locked flippers
//! merged, link and collision poses where the SDF puts them; the frame rules (`relative_to`,
//! a turned parent, `expressed_in`, a joint `<pose>`) on small files checked against
//! transforms computed by hand; the world's static models become terrain entries; bad input
//! is refused naming the file, the element and its line; the classic text form of the
//! tracked-vehicle plugin is read in a URDF; a vehicle file naming the SDF compiles.
//!
//! Tolerances: the importer computes in f64 and goes through roll-pitch-yaw once (a URDF
//! origin), so positions agree with the hand computation to round-off: 1e-9 m and 1e-9 for
//! unit vectors, far below any physical meaning. The world's yaw of 1.5708 (not pi/2) is kept
//! as written, so world positions are compared with the file's own 1.5708 too.

use crate::common::root;
use glam::{DQuat, DVec3, EulerRot};
use std::path::{Path, PathBuf};
use tracksim::geometry::CollisionShape;
use tracksim::urdf::{LinkJoint, Owner, UrdfRobot};

const TOL: f64 = 1e-9;

/// The quarter turn as the gz-sim file writes it, rad (not pi/2 exactly).
#[allow(clippy::approx_constant)]
const FILE_QUARTER_TURN: f64 = 1.5708;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue42sdf-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The third-party models' folder, or `None` (with a message) when it is absent.
fn shared(file: &str) -> Option<PathBuf> {
    let p = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/robots"
    ))
    .join("gz_sim_examples")
    .join(file);
    if p.is_file() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent (../shared/robots)", p.display());
        None
    }
}

fn near(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

/// The problems of `r`, one per line, as `key: message`.
fn problems<T: std::fmt::Debug>(r: Result<T, Vec<tracksim::SpecIssue>>) -> String {
    match r {
        Ok(v) => panic!("accepted: {v:?}"),
        Err(e) => e
            .iter()
            .map(|i| format!("{}: {}", i.key, i.message))
            .collect::<Vec<_>>()
            .join("\n"),
    }
}

/// Writes `text` as `robot.sdf` in a fresh folder.
fn sdf(name: &str, text: &str) -> PathBuf {
    let p = scratch(name).join("robot.sdf");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_gz_sim_tracked_vehicle_loads_as_its_file_says() {
    let Some(path) = shared("tracked_vehicle_simple.sdf") else {
        return;
    };
    let r = UrdfRobot::load(&path).expect("tracked_vehicle_simple.sdf loads");
    assert_eq!(r.name, "simple_tracked");
    // 13.14 + 2 x 6.06 + 4 x 0.75 kg, all one body: the flippers are locked (0..0).
    let mut issues = Vec::new();
    let m = r.mass_part(Owner::Chassis, &mut issues);
    assert!(issues.is_empty(), "{issues:?}");
    assert!((m.mass - 28.26).abs() < 1e-12, "{}", m.mass);
    assert!(r.arms.is_empty(), "locked flippers are not arms");
    for f in [
        "front_left_flipper",
        "rear_left_flipper",
        "front_right_flipper",
        "rear_right_flipper",
    ] {
        let l = r.link(f).unwrap();
        assert_eq!((l.kind, l.owner), (LinkJoint::Fixed, Owner::Chassis), "{f}");
    }
    let p = r.plugin.as_ref().expect("the TrackedVehicle plugin");
    assert_eq!(
        p.left_tracks,
        ["left_track", "front_left_flipper", "rear_left_flipper"]
    );
    assert_eq!(
        p.right_tracks,
        ["right_track", "front_right_flipper", "rear_right_flipper"]
    );
    assert_eq!(p.tracks_separation, Some(0.4));
    assert_eq!(p.tracks_height, Some(0.18094));
    assert!(p.line > 1000, "{}", p.line);
    // Track links at y = +-0.1985 (their <pose> in the model frame), not turned.
    for (l, y) in [("left_track", 0.1985), ("right_track", -0.1985)] {
        let pose = r.link(l).unwrap().pose;
        assert!(near(pose.translation, DVec3::new(0.0, y, 0.0), TOL), "{l}");
    }
    // front_left_flipper: <pose>0.25 0.272 0.0195 0 -0.5 0</pose> in the model frame; its
    // small wheel's <collision> at 0.33 0 0 (rpy 1.5708 0 0) in the link frame, so at
    // (0.25 + 0.33 cos 0.5, 0.272, 0.0195 + 0.33 sin 0.5), its axis Ry(-0.5) Rx(1.5708) z.
    let l = r.link("front_left_flipper").unwrap();
    let small = l
        .shapes
        .iter()
        .find_map(|s| match s {
            CollisionShape::Cylinder {
                radius,
                centre,
                rotation,
                ..
            } if (*radius - 0.029).abs() < 1e-12 => Some((*centre, *rotation)),
            _ => None,
        })
        .expect("the small wheel's cylinder");
    let want = DVec3::new(
        0.25 + 0.33 * 0.5f64.cos(),
        0.272,
        0.0195 + 0.33 * 0.5f64.sin(),
    );
    assert!(near(small.0, want, TOL), "{:?} vs {want:?}", small.0);
    let a = FILE_QUARTER_TURN;
    let axis = DVec3::new(
        a.cos() * (-0.5f64).sin(),
        -a.sin(),
        a.cos() * (-0.5f64).cos(),
    );
    assert!(
        near(small.1 * DVec3::Z, axis, TOL),
        "{:?}",
        small.1 * DVec3::Z
    );
    // The model's <pose>3 0 0.1 0 0 0</pose> in the world is the start pose.
    let start = r.start_pose.expect("a model in a world has a start pose");
    assert!(near(start.translation, DVec3::new(3.0, 0.0, 0.1), TOL));
}

/// A small model: `links` and `joints` inside `<model name="m">` of an SDF 1.9 file.
fn model(body: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n<model name=\"m\">\n{body}\n</model>\n</sdf>\n"
    )
}

const INERTIAL: &str = "<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy>\
                        <izz>0.01</izz></inertia></inertial>";

fn link(name: &str, pose: &str, extra: &str) -> String {
    format!("<link name=\"{name}\">{pose}{INERTIAL}{extra}</link>\n")
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, extra: &str) -> String {
    format!(
        "<joint name=\"{name}\" type=\"{kind}\"><parent>{parent}</parent><child>{child}</child>\
         {extra}</joint>\n"
    )
}

#[test]
fn poses_follow_the_sdformat_frame_rules() {
    let q = std::f64::consts::FRAC_PI_2;
    // The root link sits 0.1 m up in the model: the chassis frame is the model frame, so its
    // centre of mass is at z = 0.1. Link a: yaw 90 deg at x = 1. Link b: 1 m along a's x
    // (relative_to="a"), so at (1, 1, 0); its sphere 0.5 m along b's x: (1, 1.5, 0).
    let text = model(&format!(
        "{}{}{}{}{}",
        link(
            "base",
            "<pose>0 0 0.1 0 0 0</pose>",
            "<collision name=\"c\"><geometry><plane/></geometry><surface><friction><ode>\
             <mu>0.9</mu></ode></friction></surface></collision>"
        ),
        link("a", &format!("<pose>1 0 0 0 0 {q}</pose>"), ""),
        link(
            "b",
            "<pose relative_to=\"a\">1 0 0 0 0 0</pose>",
            "<collision name=\"s\"><pose>0.5 0 0 0 0 0</pose><geometry><sphere><radius>0.1\
             </radius></sphere></geometry></collision>"
        ),
        joint("ja", "fixed", "base", "a", ""),
        joint("jb", "fixed", "a", "b", ""),
    ));
    let r = UrdfRobot::load(&sdf("frames", &text)).unwrap();
    let mut issues = Vec::new();
    let m = r.mass_part(Owner::Chassis, &mut issues);
    // base (0, 0, 0.1), a (1, 0, 0), b (1, 1, 0): 1 kg each.
    assert!(
        near(m.com, DVec3::new(2.0, 1.0, 0.1) / 3.0, TOL),
        "{:?}",
        m.com
    );
    assert!(near(
        r.link("b").unwrap().pose.translation,
        DVec3::new(1.0, 1.0, 0.0),
        TOL
    ));
    let CollisionShape::Sphere { centre, .. } = r.link("b").unwrap().shapes[0] else {
        panic!("a sphere")
    };
    assert!(near(centre, DVec3::new(1.0, 1.5, 0.0), TOL), "{centre:?}");
    assert_eq!(r.start_pose, None, "a model file's model without <pose>");
    // The root link's <mu> is the body's friction; its <plane> is no shape of a robot.
    assert_eq!(r.root_friction, Some(0.9));
    assert!(r.links[0].shapes.is_empty());
}

/// A chassis and one revolute arm on a link turned 90 deg about z at (0.3, 0.2, 0), with
/// `axis` (the `<axis>` element) and `pose` (the joint's `<pose>`).
fn arm_robot(name: &str, axis: &str, pose: &str) -> Result<UrdfRobot, Vec<tracksim::SpecIssue>> {
    let q = std::f64::consts::FRAC_PI_2;
    let text = model(&format!(
        "{}{}{}",
        link("base", "", ""),
        link("arm", &format!("<pose>0.3 0.2 0 0 0 {q}</pose>"), ""),
        joint(
            "pivot",
            "revolute",
            "base",
            "arm",
            &format!(
                "{pose}<axis>{axis}<limit><lower>-1</lower><upper>1</upper><effort>10\
                      </effort></limit></axis>"
            ),
        ),
    ));
    UrdfRobot::load(&sdf(name, &text))
}

#[test]
fn joint_axes_are_turned_from_the_frame_they_are_expressed_in() {
    // x of the joint frame (= the child's, turned 90 deg) is the model's y.
    let r = arm_robot("axis_joint", "<xyz>1 0 0</xyz>", "").unwrap();
    let a = &r.arms[0];
    assert!(near(a.axis, DVec3::Y, TOL), "{:?}", a.axis);
    assert!(near(a.pivot, DVec3::new(0.3, 0.2, 0.0), TOL));
    assert_eq!(a.limits, Some([-1.0, 1.0]));
    assert_eq!(a.effort, 10.0);
    // The same axis written in the model frame.
    let r = arm_robot(
        "axis_model",
        "<xyz expressed_in=\"__model__\">0 1 0</xyz>",
        "",
    )
    .unwrap();
    assert!(near(r.arms[0].axis, DVec3::Y, TOL), "{:?}", r.arms[0].axis);
    // Expressed in link "base" (the model frame here): x stays x.
    let r = arm_robot("axis_link", "<xyz expressed_in=\"base\">1 0 0</xyz>", "").unwrap();
    assert!(near(r.arms[0].axis, DVec3::X, TOL), "{:?}", r.arms[0].axis);
    // A joint <pose> turning the joint frame 0.3 rad about the child's z: the axis x of the
    // joint frame is Rz(pi/2 + 0.3) x in the model.
    let r = arm_robot(
        "axis_pose",
        "<xyz>1 0 0</xyz>",
        "<pose>0 0 0 0 0 0.3</pose>",
    )
    .unwrap();
    let t = std::f64::consts::FRAC_PI_2 + 0.3;
    assert!(near(r.arms[0].axis, DVec3::new(t.cos(), t.sin(), 0.0), TOL));
    // In degrees, and as a quaternion: the same frame.
    let deg = arm_robot(
        "axis_deg",
        "<xyz>1 0 0</xyz>",
        &format!(
            "<pose degrees=\"true\">0 0 0 0 0 {}</pose>",
            0.3f64.to_degrees()
        ),
    )
    .unwrap();
    assert!(near(deg.arms[0].axis, r.arms[0].axis, TOL));
    let h = DQuat::from_euler(EulerRot::ZYX, 0.3, 0.0, 0.0);
    let quat = arm_robot(
        "axis_quat",
        "<xyz>1 0 0</xyz>",
        &format!(
            "<pose rotation_format=\"quat_xyzw\">0 0 0 {} {} {} {}</pose>",
            h.x, h.y, h.z, h.w
        ),
    )
    .unwrap();
    assert!(near(quat.arms[0].axis, r.arms[0].axis, TOL));
    // A joint <pose> moving the axis off the child's origin: the pivot would move; refused.
    let e = problems(arm_robot(
        "axis_off",
        "<xyz>1 0 0</xyz>",
        "<pose>0.1 0 0 0 0 0</pose>",
    ));
    assert!(
        e.contains("<joint name=\"pivot\"> (robot.sdf line 6)") && e.contains("from its child"),
        "{e}"
    );
}

#[test]
fn the_world_gives_terrain_entries() {
    let Some(path) = shared("tracked_vehicle_simple.sdf") else {
        return;
    };
    // Strict: the cylinder obstacle (no cylinder terrain) and the Fuel pallet refuse it.
    let e = problems(tracksim::urdf::sdf::world_terrain(&path));
    assert!(
        e.contains(
            "<collision name=\"cylinder_collision\"> (tracked_vehicle_simple.sdf line 1663)"
        ),
        "{e}"
    );
    assert!(
        e.contains("<include> (tracked_vehicle_simple.sdf line 1719)") && e.contains("Fuel"),
        "{e}"
    );
    let w = tracksim::urdf::sdf::world_terrain_lenient(&path).unwrap();
    // Leniently: the pallet left out; the cylinder (r 0.15 m, 0.8 m long, as the file says)
    // kept apart as a solid for `tracksim import` to write as a mesh.
    assert_eq!(w.left_out.len(), 1, "{:?}", w.left_out);
    assert_eq!(w.solids.len(), 1);
    let c = &w.solids[0];
    assert_eq!((c.radius, c.length), (0.15, Some(0.8)));
    assert!(c.issue.key.contains("line 1663"));
    let t = &w.terrain;
    assert_eq!(t.ground.as_ref().map(|g| g.z_m), Some(0.0));
    // 20 stair boxes and the box obstacle.
    assert_eq!(t.boxes.len(), 21);
    // Stairs_3_Collision_13: <pose>0 -0.6125 1.0125 0 0 0</pose> in a model at 7 0 0 turned
    // 1.5708 about z: centre (7 + 0.6125 sin 1.5708, -0.6125 cos 1.5708, 1.0125).
    let y = FILE_QUARTER_TURN;
    let want = DVec3::new(7.0 + 0.6125 * y.sin(), -0.6125 * y.cos(), 1.0125);
    let b = t
        .boxes
        .iter()
        .find(|b| near(DVec3::from_array(b.centre_m), want, TOL))
        .expect("step 13");
    assert_eq!(b.size_m, [1.0, 0.175, 0.075]);
    assert!(
        (b.yaw_deg - y.to_degrees()).abs() < 1e-9 && b.pitch_deg.abs() < 1e-9,
        "{b:?}"
    );
    // The box obstacle, rolled 1.7821 rad: a yaw and a pitch with its sides swapped; its
    // corners are where the file's pose puts them (1.5708 for pi/2: 1e-4 m).
    let o = t
        .boxes
        .iter()
        .find(|b| {
            near(
                DVec3::from_array(b.centre_m),
                DVec3::new(2.0, 2.0, 0.028),
                TOL,
            )
        })
        .expect("the box obstacle");
    let corners = |r: DQuat, half: DVec3| -> Vec<DVec3> {
        (0..8)
            .map(|k| {
                let s = DVec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
                r * (half * s)
            })
            .collect()
    };
    let file = corners(
        DQuat::from_euler(EulerRot::ZYX, y, 0.0, 1.7821),
        DVec3::new(0.85, 0.15, 0.5) / 2.0,
    );
    let ours = corners(
        DQuat::from_rotation_z(o.yaw_deg.to_radians())
            * DQuat::from_rotation_y(o.pitch_deg.to_radians()),
        DVec3::from_array(o.size_m) / 2.0,
    );
    for c in &file {
        assert!(
            ours.iter().any(|d| near(*c, *d, 1e-4)),
            "corner {c:?} of {o:?}"
        );
    }
    let start = tracksim::urdf::sdf::model_start_pose(&path, None)
        .unwrap()
        .unwrap();
    assert!(near(start.translation, DVec3::new(3.0, 0.0, 0.1), TOL));
}

#[test]
fn bad_sdf_is_refused_with_the_file_element_and_line() {
    let e = problems(UrdfRobot::load(&sdf(
        "no_model",
        "<sdf version=\"1.7\">\n<world name=\"w\"/>\n</sdf>\n",
    )));
    assert!(e.contains("robot.sdf has no <model>"), "{e}");
    let two = "<sdf version=\"1.7\"><world name=\"w\">\n<model name=\"one\"><link name=\"l\"/>\
               </model>\n<model name=\"two\"><link name=\"l\"/></model>\n</world></sdf>\n";
    let e = problems(UrdfRobot::load(&sdf("two", two)));
    assert!(
        e.contains("sdf_model") && e.contains("\"one\", \"two\""),
        "{e}"
    );
    let e = problems(UrdfRobot::load_model(&sdf("unknown", two), Some("three")));
    assert!(
        e.contains("no <model name=\"three\">") && e.contains("\"one\", \"two\""),
        "{e}"
    );
    let included = model(&format!(
        "{}<include>\n<uri>model://wheel</uri></include>",
        link("base", "", "")
    ));
    let e = problems(UrdfRobot::load(&sdf("include", &included)));
    assert!(
        e.contains("<include> (robot.sdf line 5)") && e.contains("gz sdf -p"),
        "{e}"
    );
    let nan = model(&link("base", "<pose>0 0 nan 0 0 0</pose>", ""));
    let e = problems(UrdfRobot::load(&sdf("nan", &nan)));
    assert!(
        e.contains("<pose> (robot.sdf line 4)") && e.contains("`nan` is not a finite"),
        "{e}"
    );
    let fuel = model(&link(
        "base",
        "",
        "<collision name=\"c\"><geometry><mesh><uri>https://fuel.gazebosim.org/1.0/x/models/y\
         </uri></mesh></geometry></collision>",
    ));
    let e = problems(UrdfRobot::load(&sdf("fuel", &fuel)));
    assert!(
        e.contains("<uri> (robot.sdf line 4)") && e.contains("downloads nothing"),
        "{e}"
    );
    let old = model(&link("base", "", "")).replace("version=\"1.9\"", "version=\"1.4\"");
    let e = problems(UrdfRobot::load(&sdf("old", &old)));
    assert!(e.contains("<sdf> (robot.sdf line 2): version 1.4"), "{e}");
    if let Some(p) = shared("track_drive.sdf") {
        let e = problems(UrdfRobot::load(&p));
        assert!(e.contains("\"vehicle_blue\", \"vehicle_green\""), "{e}");
    }
}

#[test]
fn the_classic_plugin_text_form_is_read_in_a_urdf() {
    let urdf = std::fs::read_to_string(root().join("vehicles/urdf/packbot510_flippers.urdf"))
        .unwrap()
        .replace(
            "<left_track><link>left_track</link></left_track>",
            "<left_track>left_track</left_track>",
        )
        .replace(
            "<right_flipper><link>front_right_flipper</link></right_flipper>",
            "<right_flipper> front_right_flipper </right_flipper>",
        );
    let p = scratch("classic").join("robot.urdf");
    std::fs::write(&p, urdf).unwrap();
    let r = UrdfRobot::load(&p).unwrap();
    let plugin = r.plugin.unwrap();
    assert_eq!(plugin.left_tracks, ["left_track"]);
    assert_eq!(plugin.right_tracks, ["right_track"]);
    assert_eq!(plugin.right_flippers, ["front_right_flipper"]);
    assert_eq!(plugin.tracks_separation, Some(0.325));
}

/// A vehicle file naming the SDF with a simple track on each of the plugin's six links.
fn sdf_vehicle(dir: &Path, sdf: &Path) -> PathBuf {
    let mut v = format!(
        "name = \"gz simple_tracked\"\nurdf = \"{}\"\n",
        sdf.display().to_string().replace('\\', "/")
    );
    for (name, link, mlink, r, len) in [
        ("left", "left_track", "right_track", 0.09, 0.25),
        (
            "front_left",
            "front_left_flipper",
            "front_right_flipper",
            0.03,
            0.165,
        ),
        (
            "rear_left",
            "rear_left_flipper",
            "rear_right_flipper",
            0.03,
            0.165,
        ),
    ] {
        v.push_str(&format!(
            "\n[[tracks]]\nname = \"{name}\"\nlink = \"{link}\"\nmirror = \"{}\"\n\
             mirror_link = \"{mlink}\"\nwidth_m = 0.05\nbelt_mass_kg = 0.5\n\
             friction = 0.7\n[tracks.path]\nplane_y_m = 0.0\npulleys = [\n  \
             {{ x_m = -{len}, z_m = 0.0, radius_m = {r} }},\n  \
             {{ x_m = {len}, z_m = 0.0, radius_m = {r} }},\n]\n",
            name.replace("left", "right")
        ));
    }
    let p = dir.join("vehicle.toml");
    std::fs::write(&p, v).unwrap();
    p
}

#[test]
fn a_vehicle_file_naming_the_sdf_compiles() {
    let Some(path) = shared("tracked_vehicle_simple.sdf") else {
        return;
    };
    let dir = scratch("vehicle");
    let v = tracksim::load_vehicle(&sdf_vehicle(&dir, &path)).expect("the vehicle compiles");
    assert!((v.body.mass - 28.26).abs() < 1e-12, "{}", v.body.mass);
    assert!(v.flippers.is_empty());
    assert_eq!(v.tracks.len(), 6);
    assert_eq!(v.odometry_separation, Some(0.4));
    let report = v.urdf.as_ref().unwrap().lines().join("\n");
    assert!(
        report.starts_with("SDF ")
            && report.contains("robot \"simple_tracked\"")
            && report.contains("fixed joint front_left_flipper_j")
            && report.contains("(3.000, 0.000, 0.100) m"),
        "{report}"
    );
    // `sdf_model` names the model; an unknown one is refused with the models listed.
    let text = std::fs::read_to_string(dir.join("vehicle.toml")).unwrap();
    std::fs::write(
        dir.join("named.toml"),
        format!("sdf_model = \"simple_tracked\"\n{text}"),
    )
    .unwrap();
    tracksim::load_vehicle(&dir.join("named.toml")).expect("named model");
    std::fs::write(
        dir.join("wrong.toml"),
        format!("sdf_model = \"ground_plane\"\n{text}"),
    )
    .unwrap();
    let e = tracksim::load_vehicle(&dir.join("wrong.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("static"), "{e}");
}

#[test]
fn joints_without_links_and_nested_models_are_refused() {
    let text = model(&format!(
        "{}{}<model name=\"inner\"/>",
        link("base", "", ""),
        "<joint name=\"j\" type=\"fixed\"><parent>base</parent></joint>\n"
    ));
    let e = problems(UrdfRobot::load(&sdf("no_child", &text)));
    assert!(
        e.contains("<joint name=\"j\"> (robot.sdf line 5): has no <child> link"),
        "{e}"
    );
    assert!(
        e.contains("<model name=\"inner\"> (robot.sdf line 6)"),
        "{e}"
    );
    // A joint to the world, and a type tracksim does not simulate.
    let text = model(&format!(
        "{}{}{}",
        link("base", "", ""),
        link("w", "", ""),
        joint("j", "universal", "base", "w", "")
    ));
    let e = problems(UrdfRobot::load(&sdf("universal", &text)));
    assert!(
        e.contains("<joint name=\"j\"> (robot.sdf line 6): type \"universal\""),
        "{e}"
    );
    // Revolute without <limit>, or with SDF's 1e16 "no limit": a continuous wheel, merged.
    let text = model(&format!(
        "{}{}{}",
        link("base", "", ""),
        link("wheel", "<pose>0.2 0 0 0 0 0</pose>", ""),
        joint(
            "j",
            "revolute",
            "base",
            "wheel",
            "<axis><xyz>0 1 0</xyz><limit><lower>-1e16</lower><upper>1e16</upper></limit></axis>"
        )
    ));
    let r = UrdfRobot::load(&sdf("wheel", &text)).unwrap();
    assert!(r.arms.is_empty());
    assert_eq!(r.link("wheel").unwrap().kind, LinkJoint::Continuous);
}

/// An ASCII STL of the box from `lo` to `hi` (12 triangles), m.
fn box_stl(lo: DVec3, hi: DVec3) -> String {
    let mut s = String::from("solid box\n");
    for f in crate::common::box_triangles(lo, hi) {
        s.push_str("facet normal 0 0 0\nouter loop\n");
        for v in f {
            s.push_str(&format!("vertex {} {} {}\n", v.x, v.y, v.z));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s.push_str("endsolid box\n");
    s
}

#[test]
fn model_uris_and_a_small_world() {
    // models/wheel/meshes/w.stl, named from models/robot/robot.sdf as model://wheel/...
    let dir = scratch("model_uri");
    let meshes = dir.join("models/wheel/meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    std::fs::create_dir_all(dir.join("models/robot")).unwrap();
    let stl = box_stl(DVec3::splat(-0.1), DVec3::splat(0.1));
    std::fs::write(meshes.join("w.stl"), &stl).unwrap();
    let mesh = |uri: &str| {
        format!(
            "<collision name=\"c\"><pose>0 0 0.5 0 0 0</pose><geometry><mesh><uri>{uri}</uri>\
             </mesh></geometry></collision>"
        )
    };
    let text = model(&link("base", "", &mesh("model://wheel/meshes/w.stl")));
    let p = dir.join("models/robot/robot.sdf");
    std::fs::write(&p, text).unwrap();
    let r = UrdfRobot::load(&p).unwrap();
    let CollisionShape::Convex(pts) = &r.links[0].shapes[0] else {
        panic!("a hull")
    };
    let top = pts.iter().map(|v| v.z).fold(f64::MIN, f64::max);
    assert!((top - 0.6).abs() < 1e-6, "{top}"); // f32 hull: 1e-6 m
    let text = model(&link("base", "", &mesh("model://nowhere/w.stl")));
    std::fs::write(&p, text).unwrap();
    let e = problems(UrdfRobot::load(&p));
    assert!(
        e.contains("model \"nowhere\"") && e.contains("line 4"),
        "{e}"
    );
    // A world: a ground plane at z = 0.2, a box pitched 0.3 rad, a mesh turned 30 deg about
    // z, a sphere (refused) and the robot (not terrain).
    let world = "<sdf version=\"1.9\"><world name=\"w\">\n\
         <model name=\"g\"><static>true</static><pose>0 0 0.2 0 0 0</pose><link name=\"l\">\
         <collision name=\"p\"><geometry><plane><normal>0 0 1</normal></plane></geometry>\
         <surface><friction><ode><mu>0.8</mu></ode></friction></surface></collision></link></model>\n\
         <model name=\"b\"><static>1</static><pose>1 2 0 0 0.3 0</pose><link name=\"l\">\
         <collision name=\"bx\"><geometry><box><size>1 2 3</size></box></geometry></collision>\
         </link></model>\n\
         <model name=\"m\"><static>1</static><pose degrees=\"true\">0 0 0 0 0 30</pose>\
         <link name=\"l\"><collision name=\"mc\"><geometry><mesh><uri>w.stl</uri><scale>2 2 2\
         </scale></mesh></geometry></collision></link></model>\n\
         <model name=\"s\"><static>1</static><link name=\"l\"><collision name=\"sp\"><geometry>\
         <sphere><radius>1</radius></sphere></geometry></collision></link></model>\n\
         <model name=\"robot\"><link name=\"base\"/></model>\n\
         </world></sdf>\n";
    let wdir = scratch("world");
    std::fs::write(wdir.join("w.stl"), &stl).unwrap();
    let wp = wdir.join("world.sdf");
    std::fs::write(&wp, world).unwrap();
    let e = problems(tracksim::urdf::sdf::world_terrain(&wp));
    assert!(
        e.contains("<collision name=\"sp\"> (world.sdf line 5): a sphere"),
        "{e}"
    );
    let w = tracksim::urdf::sdf::world_terrain_lenient(&wp).unwrap();
    assert!(w.left_out.is_empty());
    assert_eq!(w.solids.len(), 1, "the sphere, kept apart");
    assert_eq!((w.solids[0].radius, w.solids[0].length), (1.0, None));
    let g = w.terrain.ground.as_ref().unwrap();
    assert_eq!((g.z_m, g.friction), (0.2, 0.8));
    let b = &w.terrain.boxes[0];
    assert_eq!((b.centre_m, b.size_m), ([1.0, 2.0, 0.0], [1.0, 2.0, 3.0]));
    assert!(b.yaw_deg.abs() < 1e-9 && (b.pitch_deg - 0.3f64.to_degrees()).abs() < 1e-9);
    let m = &w.terrain.meshes[0];
    assert_eq!(m.scale, 2.0);
    assert!(
        (m.yaw_deg - 30.0).abs() < 1e-9 && m.file == wdir.join("w.stl"),
        "{m:?}"
    );
    assert_eq!(
        tracksim::urdf::sdf::model_start_pose(&wp, Some("robot")).unwrap(),
        Some(glam::DAffine3::IDENTITY)
    );
}
