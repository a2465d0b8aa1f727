//! Issue 26: a robot brought as URDF. The bundled PackBot URDF with its track file compiles to
//! the same model as packbot510_flippers.toml and gives the same trajectory on the stairs and
//! the step (tolerance: none, the trajectory.csv files are byte-identical, because the import
//! produces the same numbers); merged fixed links obey the parallel-axis theorem and drive
//! like the one-link robot (1 mm); inertial frames turn the tensor; meshes collide as their
//! hull; joint limits hold the flippers; sensors and tracks bind to links; the Gazebo plugin
//! gives the odometry separation; bad URDF is refused with the element named.

use crate::common;

use common::root;
use glam::DVec3;
use std::path::{Path, PathBuf};
use tracksim::model::{CollisionShape, Mount, Parent, load_vehicle};

/// A fresh scratch folder for one test.
/// The flipper joints' `<limit upper>` as the bundled URDF writes it, rad (not pi/2 exactly).
#[allow(clippy::approx_constant)]
const URDF_LIMIT_RAD: f64 = 1.5708;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue26-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn bundled_urdf() -> String {
    std::fs::read_to_string(root().join("vehicles/urdf/packbot510_flippers.urdf")).unwrap()
}

fn bundled_tracks() -> String {
    std::fs::read_to_string(root().join("vehicles/packbot510_urdf.toml"))
        .unwrap()
        .replace(
            "urdf = \"urdf/packbot510_flippers.urdf\"",
            "urdf = \"robot.urdf\"",
        )
}

/// Writes `urdf` and the track file `tracks` into `dir`; returns the track file.
fn write_robot(dir: &Path, urdf: &str, tracks: &str) -> PathBuf {
    std::fs::write(dir.join("robot.urdf"), urdf).unwrap();
    let v = dir.join("robot.toml");
    std::fs::write(&v, tracks).unwrap();
    v
}

/// Replaces `old` (which must occur) by `new`.
fn edit(text: &str, old: &str, new: &str) -> String {
    assert!(text.contains(old), "{old:?} not in the text");
    text.replacen(old, new, 1)
}

/// The problems of loading vehicle file `v`, as one string (it must fail).
fn refused(v: &Path) -> String {
    match load_vehicle(v) {
        Ok(_) => panic!("{} was accepted", v.display()),
        Err(e) => e.to_string(),
    }
}

/// Runs bundled scenario `scenario` with its vehicle replaced by `vehicle` (repository paths)
/// to its end; returns trajectory.csv.
fn trajectory(dir: &Path, scenario: &str, vehicle: &str) -> String {
    let text = std::fs::read_to_string(root().join(scenario)).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("file = "))
        .expect("a vehicle file line")
        .to_string();
    let text = text.replace(
        &line,
        &format!("file = {:?}", root().join(vehicle).display().to_string()),
    );
    let f = dir.join(format!(
        "{}-{}",
        vehicle.replace('/', "_"),
        Path::new(scenario).file_name().unwrap().to_string_lossy()
    ));
    std::fs::write(&f, text).unwrap();
    let sc = tracksim::load_scenario(&f).unwrap_or_else(|e| panic!("{e}"));
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    tracksim::output::trajectory_csv(&r)
}

#[test]
fn bundled_urdf_compiles_to_the_toml_model() {
    let a = load_vehicle(&root().join("vehicles/packbot510_flippers.toml")).unwrap();
    let b = load_vehicle(&root().join("vehicles/packbot510_urdf.toml")).unwrap();
    assert_eq!(a.body.mass, b.body.mass);
    assert_eq!(a.body.com, b.body.com);
    assert_eq!(a.body.inertia, b.body.inertia);
    assert_eq!(b.body.inertia_products, DVec3::ZERO);
    assert_eq!(
        a.body.shape, b.body.shape,
        "the track links' boxes are not used"
    );
    assert_eq!(a.body.friction, b.body.friction);
    assert_eq!(a.flippers.len(), b.flippers.len());
    for (f, g) in a.flippers.iter().zip(&b.flippers) {
        assert_eq!(f.name, g.name);
        assert_eq!((f.pivot, f.axis, f.com), (g.pivot, g.axis, g.com));
        assert_eq!((f.mass, f.inertia), (g.mass, g.inertia));
        assert_eq!(
            (f.max_torque, f.stiffness, f.damping),
            (g.max_torque, g.stiffness, g.damping)
        );
        assert_eq!(
            g.shape, None,
            "a flipper link carrying a track drops its box"
        );
        let [lo, hi] = g.limits.expect("URDF limits");
        assert!((lo + URDF_LIMIT_RAD).abs() < 1e-12 && (hi - URDF_LIMIT_RAD).abs() < 1e-12);
    }
    assert_eq!(a.tracks.len(), b.tracks.len());
    for (t, u) in a.tracks.iter().zip(&b.tracks) {
        assert_eq!((&t.name, t.parent), (&u.name, u.parent));
        for (s, r) in t.path.segments().iter().zip(u.path.segments()) {
            // The flipper paths are built in the link frame and moved: 1e-15 m of rounding.
            assert!((s.start() - r.start()).length() < 1e-12, "{} path", t.name);
        }
        assert!((t.path.length() - u.path.length()).abs() < 1e-12);
    }
    // The Gazebo plugin's tracks_separation is the odometry's.
    assert_eq!(b.odometry_separation, Some(0.325));
}

#[test]
fn bundled_urdf_drives_the_stairs_and_the_step_like_the_toml() {
    let dir = scratch("same");
    for scenario in [
        "scenarios/packbot_stairs.toml",
        "scenarios/packbot_step.toml",
    ] {
        let a = trajectory(&dir, scenario, "vehicles/packbot510_flippers.toml");
        let b = trajectory(&dir, scenario, "vehicles/packbot510_urdf.toml");
        assert!(a.lines().count() > 100, "{scenario} ran");
        assert!(a == b, "{scenario}: the URDF robot's trajectory differs");
    }
}

/// The bundled URDF with the chassis split into a front and a rear half on a fixed joint.
fn split_chassis() -> String {
    // Each half: 5.5 kg, a 0.25 x 0.25 x 0.10 m box; its inertia about its own centre.
    let (m, sx, sy, sz) = (5.5_f64, 0.25_f64, 0.25_f64, 0.10_f64);
    let i = |a: f64, b: f64| m / 12.0 * (a * a + b * b);
    let half = |name: &str, x: f64| {
        format!(
            r#"<link name="{name}">
    <inertial><origin xyz="{x} 0 0"/><mass value="{m}"/>
      <inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{}"/></inertial>
    <collision><origin xyz="{x} 0 0"/><geometry><box size="{sx} {sy} {sz}"/></geometry></collision>
  </link>"#,
            i(sy, sz),
            i(sx, sz),
            i(sx, sy)
        )
    };
    let urdf = bundled_urdf();
    let start = urdf.find("<link name=\"base_link\">").unwrap();
    let end = start + urdf[start..].find("</link>").unwrap() + "</link>".len();
    format!(
        "{}{}\n  {}\n  <joint name=\"rear_joint\" type=\"fixed\"><parent link=\"base_link\"/>\
         <child link=\"rear_half\"/><origin xyz=\"-0.25 0 0\"/></joint>{}",
        &urdf[..start],
        half("base_link", 0.125),
        half("rear_half", 0.125),
        &urdf[end..]
    )
}

#[test]
fn fixed_links_merge_by_the_parallel_axis_theorem() {
    let dir = scratch("split");
    let v = write_robot(&dir, &split_chassis(), &bundled_tracks());
    let split = load_vehicle(&v).unwrap_or_else(|e| panic!("{e}"));
    let whole = load_vehicle(&root().join("vehicles/packbot510_flippers.toml")).unwrap();
    assert!((split.body.mass - 11.0).abs() < 1e-12);
    assert!(split.body.com.length() < 1e-12, "{:?}", split.body.com);
    let rel = (split.body.inertia - whole.body.inertia).abs() / whole.body.inertia;
    assert!(
        rel.max_element() < 1e-12,
        "{:?} vs {:?}",
        split.body.inertia,
        whole.body.inertia
    );
    assert!(split.body.inertia_products.length() < 1e-15);
    let (lo, hi) = split.body.shape.bounds();
    assert!((lo - DVec3::new(-0.25, -0.125, -0.05)).length() < 1e-12);
    assert!((hi - DVec3::new(0.25, 0.125, 0.05)).length() < 1e-12);
    assert_eq!(split.body.shape.parts().len(), 2);
    // It drives like the one-link robot: 4 s on the flat, within 1 mm.
    let run = |file: &Path| {
        let sc = common::with_vehicle(
            "vehicles/packbot510.toml",
            |s| s.simulation.duration_s = 4.0,
            |v| *v = load_vehicle(file).unwrap(),
        );
        let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
        let p = r.samples.last().unwrap().pose;
        DVec3::new(p.x, p.y, p.z)
    };
    let a = run(&v);
    let b = run(&root().join("vehicles/packbot510_urdf.toml"));
    assert!(a.x > 0.5, "it drove ({a:?})");
    assert!((a - b).length() < 1e-3, "split {a:?} vs one link {b:?}");
}

#[test]
fn an_inertial_frame_turns_the_tensor() {
    let dir = scratch("turned");
    let turn = |rpy: &str| {
        let urdf = edit(
            &bundled_urdf(),
            r#"<origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="11.0"/>
      <inertia ixx="0.06645833333333334" ixy="0" ixz="0" iyy="0.23833333333333334" iyz="0" izz="0.2864583333333333"/>"#,
            &format!(
                r#"<origin xyz="0.01 0 0" rpy="{rpy}"/>
      <mass value="11.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/>"#
            ),
        );
        load_vehicle(&write_robot(&dir, &urdf, &bundled_tracks())).unwrap()
    };
    // A quarter turn about z swaps the x and y moments.
    let q = turn("0 0 1.5707963267948966");
    assert!((q.body.inertia - DVec3::new(0.2, 0.1, 0.25)).length() < 1e-12);
    assert!(q.body.inertia_products.length() < 1e-12);
    assert!((q.body.com - DVec3::new(0.01, 0.0, 0.0)).length() < 1e-15);
    // An eighth turn: Ixx = Iyy = 0.15 and Ixy = -(0.2 - 0.1)/2 (the tensor R I R^T).
    let e = turn("0 0 0.7853981633974483");
    assert!((e.body.inertia - DVec3::new(0.15, 0.15, 0.25)).length() < 1e-12);
    assert!((e.body.inertia_products - DVec3::new(-0.05, 0.0, 0.0)).length() < 1e-12);
    // The world takes the full tensor: the robot settles on flat ground (1 s) without drifting
    // sideways or turning.
    let sc = common::with_vehicle(
        "vehicles/packbot510.toml",
        |s| {
            s.simulation.duration_s = 1.0;
            s.commands.clear();
        },
        |v| *v = e,
    );
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let p = r.samples.last().unwrap().pose;
    assert!(p.y.abs() < 2e-3 && p.yaw.abs() < 0.01, "{p:?}");
}

/// A binary STL of the axis-aligned box [lo, hi].
fn box_stl(lo: DVec3, hi: DVec3) -> Vec<u8> {
    let faces = crate::common::box_triangles(lo, hi);
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for f in faces {
        b.extend_from_slice(&[0u8; 12]);
        for v in f {
            for x in v.to_array() {
                b.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

#[test]
fn collision_meshes_collide_as_their_hull() {
    let dir = scratch("mesh");
    // A package folder, as ROS lays it out: pkg/urdf/robot.urdf, pkg/meshes/chassis.stl.
    let pkg = dir.join("packbot_description");
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    let (lo, hi) = (
        DVec3::new(-0.25, -0.125, -0.05),
        DVec3::new(0.25, 0.125, 0.05),
    );
    // Stored in millimetres, scaled by the URDF's <mesh scale>.
    std::fs::write(pkg.join("meshes/chassis.stl"), box_stl(lo * 1e3, hi * 1e3)).unwrap();
    let obj: String = (0..8)
        .map(|i| {
            format!(
                "v {} {} {}\n",
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z }
            )
        })
        .collect::<String>()
        + "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";
    std::fs::write(pkg.join("meshes/chassis.obj"), obj).unwrap();
    let collision = r#"<collision>
      <geometry><box size="0.50 0.25 0.10"/></geometry>"#;
    for mesh in [
        r#"<mesh filename="package://packbot_description/meshes/chassis.stl" scale="0.001 0.001 0.001"/>"#,
        r#"<mesh filename="../meshes/chassis.obj"/>"#,
    ] {
        let urdf = edit(
            &bundled_urdf(),
            collision,
            &format!("<collision>\n      <geometry>{mesh}</geometry>"),
        );
        std::fs::write(pkg.join("urdf/robot.urdf"), urdf).unwrap();
        let v = pkg.join("urdf/robot.toml");
        std::fs::write(&v, bundled_tracks()).unwrap();
        let m = load_vehicle(&v).unwrap_or_else(|e| panic!("{mesh}: {e}"));
        let CollisionShape::Convex(pts) = &m.body.shape else {
            panic!("{mesh}: a mesh is a convex hull, got {:?}", m.body.shape)
        };
        assert_eq!(pts.len(), 8, "{mesh}: the hull of a box has its 8 corners");
        let (a, b) = m.body.shape.bounds();
        assert!(
            (a - lo).length() < 1e-6 && (b - hi).length() < 1e-6,
            "{mesh}: {a} {b}"
        );
    }
}

#[test]
fn joint_limits_hold_the_flippers() {
    // Commanded to 143 deg, the flippers stop at the URDF's 90 deg (1.5708 rad).
    let dir = scratch("limits");
    let f = dir.join("limits.toml");
    std::fs::write(
        &f,
        format!(
            "description = \"flippers beyond their limits\"\n[vehicle]\nfile = {:?}\n\
             [terrain.ground]\nfriction = 0.6\n[simulation]\nduration_s = 3.0\n\
             [[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.0\n\
             flipper_angle_deg = {{ front_left = 143.0, front_right = 143.0 }}\n",
            root()
                .join("vehicles/packbot510_urdf.toml")
                .display()
                .to_string()
        ),
    )
    .unwrap();
    let sc = tracksim::load_scenario(&f).unwrap_or_else(|e| panic!("{e}"));
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let max = r
        .samples
        .iter()
        .flat_map(|s| s.flipper_angle.clone())
        .fold(f64::MIN, f64::max);
    let limit = URDF_LIMIT_RAD;
    assert!(max < limit + 0.01, "a flipper passed its limit: {max} rad");
    assert!(
        max > limit - 0.05,
        "the flippers did not reach the limit: {max} rad"
    );
}

#[test]
fn sensors_mount_on_links() {
    let dir = scratch("sensors");
    let tracks = bundled_tracks()
        + r#"
[[sensors]]
name = "arm_imu"
kind = "imu"
mount = "front_left_flipper"
xyz_m = [0.1, 0.0, 0.02]

[[sensors]]
name = "track_imu"
kind = "imu"
mount = "right_track"
"#;
    let v = load_vehicle(&write_robot(&dir, &bundled_urdf(), &tracks)).unwrap();
    assert_eq!(v.sensors[0].mount, Mount::Flipper(0));
    assert!((v.sensors[0].position - DVec3::new(0.355, 0.225, 0.02)).length() < 1e-12);
    assert_eq!(v.sensors[1].mount, Mount::Body);
    assert!((v.sensors[1].position - DVec3::new(0.0, -0.1625, 0.0)).length() < 1e-12);
    assert_eq!(v.tracks[2].parent, Parent::Flipper(0));
    assert_eq!(v.tracks[3].parent, Parent::Flipper(1));
}

#[test]
fn bad_urdf_is_refused_with_the_element_named() {
    let dir = scratch("bad");
    let u = bundled_urdf();
    let t = bundled_tracks();
    let case = |name: &str, urdf: &str, tracks: &str, wants: &[&str]| {
        let d = dir.join(name);
        std::fs::create_dir_all(&d).unwrap();
        let msg = refused(&write_robot(&d, urdf, tracks));
        for w in wants {
            assert!(msg.contains(w), "{name}: {w:?} not in:\n{msg}");
        }
    };
    refused_masses(&case, &u, &t);
    refused_joint_trees(&case, &u, &t);
    refused_tracks_and_forms(&case, &u, &t);
    refused_meshes(&case, &dir, &u, &t);
}

/// One refusal case: (name, URDF text, tracks file text, what the message must say).
type RefusalCase<'a> = &'a dyn Fn(&str, &str, &str, &[&str]);

/// Masses and inertias that no body has.
fn refused_masses(case: RefusalCase, u: &str, t: &str) {
    case(
        "zero mass",
        &edit(u, r#"<mass value="11.0"/>"#, r#"<mass value="0"/>"#),
        t,
        &[r#"<link name="base_link">"#, "<inertial>", "mass"],
    );
    case(
        "negative mass",
        &edit(u, r#"<mass value="11.0"/>"#, r#"<mass value="-3"/>"#),
        t,
        &[r#"<link name="base_link">"#, "mass"],
    );
    case(
        "negative inertia",
        &edit(u, r#"ixx="0.06645833333333334""#, r#"ixx="-0.1""#),
        t,
        &[r#"<link name="base_link">"#, "positive definite"],
    );
    case(
        "zero inertia",
        &edit(u, r#"izz="0.2864583333333333""#, r#"izz="0""#),
        t,
        &[r#"<link name="base_link">"#, "positive definite"],
    );
    case(
        "impossible inertia",
        &edit(u, r#"izz="0.2864583333333333""#, r#"izz="0.5""#),
        t,
        &[r#"<link name="base_link">"#, "triangle inequality"],
    );
}

/// Joint trees that are not trees, and joints the simulator cannot model.
fn refused_joint_trees(case: RefusalCase, u: &str, t: &str) {
    case(
        "missing link",
        &edit(
            u,
            r#"<child link="left_track"/>"#,
            r#"<child link="left_trak"/>"#,
        ),
        t,
        &[
            r#"<joint name="left_track_joint">"#,
            "line 34",
            "left_trak",
            "is not a link",
        ],
    );
    let looped = edit(
        u,
        "</robot>",
        r#"<joint name="back" type="fixed"><parent link="front_left_flipper"/><child link="base_link"/></joint></robot>"#,
    );
    case("loop", &looped, t, &["loop"]);
    let two_parents = edit(
        u,
        "</robot>",
        r#"<joint name="again" type="fixed"><parent link="front_left_flipper"/><child link="left_track"/></joint></robot>"#,
    );
    case(
        "two parents",
        &two_parents,
        t,
        &[
            r#"<joint name="again">"#,
            "already the child of joint \"left_track_joint\"",
        ],
    );
    case(
        "prismatic",
        &edit(
            u,
            r#"<joint name="front_left" type="revolute">"#,
            r#"<joint name="front_left" type="prismatic">"#,
        ),
        t,
        &[r#"<joint name="front_left">"#, "prismatic"],
    );
    case(
        "no effort",
        &edit(
            u,
            r#"effort="60" velocity="2.0"/>
  </joint>
  <link name="front_right_flipper">"#,
            r#"effort="0" velocity="2.0"/>
  </joint>
  <link name="front_right_flipper">"#,
        ),
        t,
        &[r#"<joint name="front_left">"#, "effort"],
    );
}

/// Track entries that name no link, and files in forms the reader refuses.
fn refused_tracks_and_forms(case: RefusalCase, u: &str, t: &str) {
    case(
        "unknown track link",
        u,
        &edit(t, r#"link = "left_track""#, r#"link = "left_trak""#),
        &["tracks[0].link", "did you mean `left_track`"],
    );
    case(
        "plugin track without a track",
        u,
        &t.replace("mirror_link = \"right_track\"\n", ""),
        &["<plugin><right_track>", "right_track"],
    );
    case(
        "body with urdf",
        u,
        &(t.to_string()
            + "\n[body]\nmass_kg = 1.0\nshape = { type = \"box\", size_m = [0.1, 0.1, 0.1] }\n"),
        &["body", "remove [body]"],
    );
    case(
        "xacro",
        &edit(
            &edit(
                u,
                "<robot name=",
                "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" name=",
            ),
            "</robot>",
            "<xacro:property name=\"wheel_radius\" value=\"0.1\"/></robot>",
        ),
        t,
        &["xacro"],
    );
    case(
        "not finite",
        &edit(
            u,
            r#"<origin xyz="0 0.1625 0" rpy="0 0 0"/>"#,
            r#"<origin xyz="0 nan 0" rpy="0 0 0"/>"#,
        ),
        t,
        &[r#"<joint name="left_track_joint">"#, "not finite"],
    );
}

/// Collision meshes missing, or too large by their header or their size.
fn refused_meshes(case: RefusalCase, dir: &std::path::Path, u: &str, t: &str) {
    let with_mesh = |file: &str| {
        edit(
            u,
            r#"<collision>
      <geometry><box size="0.50 0.25 0.10"/></geometry>"#,
            &format!("<collision>\n      <geometry><mesh filename=\"{file}\"/></geometry>"),
        )
    };
    case(
        "missing mesh",
        &with_mesh("meshes/nowhere.stl"),
        t,
        &[r#"<link name="base_link">"#, "<collision> 1", "nowhere.stl"],
    );
    // 10^8 triangles: a header that says so (refused before anything is read) ...
    let d = dir.join("huge");
    std::fs::create_dir_all(&d).unwrap();
    let mut head = vec![0u8; 80];
    head.extend_from_slice(&100_000_000u32.to_le_bytes());
    head.extend_from_slice(&[0u8; 50]);
    std::fs::write(d.join("huge.stl"), &head).unwrap();
    case(
        "huge",
        &with_mesh("../huge/huge.stl"),
        t,
        &[r#"<link name="base_link">"#, "100000000 triangles"],
    );
    // ... and a file of that size (5 GB, sparse): refused by its size.
    let big = std::fs::File::create(d.join("big.stl")).unwrap();
    big.set_len(84 + 50 * 100_000_000).unwrap();
    drop(big);
    case(
        "big",
        &with_mesh("../huge/big.stl"),
        t,
        &[r#"<link name="base_link">"#, "<collision> 1"],
    );
}
