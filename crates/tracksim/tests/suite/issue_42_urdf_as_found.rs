//! Issue 42 (first part): URDF as it is found. An expanded URDF that keeps the xacro namespace
//! declaration or commented-out xacro lines is read (xacro is told by its elements, in the
//! xacro namespace, or by an undeclared `xacro:` prefix); a revolute joint locked at one angle
//! (gz-sim's `<limit lower="0" upper="0">`) is fixed, not an arm; a URDF or SDF file given
//! where a tracksim file is read is named as such, with what to write instead.

use crate::common::root;
use std::path::{Path, PathBuf};
use tracksim::load_vehicle;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue42-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes the bundled URDF PackBot with `urdf` as its robot into `dir`; its vehicle file.
fn robot(dir: &Path, urdf: &str) -> PathBuf {
    std::fs::write(dir.join("robot.urdf"), urdf).unwrap();
    let tracks = std::fs::read_to_string(root().join("vehicles/packbot510_urdf.toml"))
        .unwrap()
        .replace(
            "urdf = \"urdf/packbot510_flippers.urdf\"",
            "urdf = \"robot.urdf\"",
        );
    let v = dir.join("robot.toml");
    std::fs::write(&v, tracks).unwrap();
    v
}

fn bundled() -> String {
    std::fs::read_to_string(root().join("vehicles/urdf/packbot510_flippers.urdf")).unwrap()
}

const XACRO_NS: &str = "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" name=";

#[test]
fn xacro_is_told_by_its_elements_not_by_comments() {
    let dir = scratch("xacro");
    let expanded = bundled().replacen("<robot name=", XACRO_NS, 1).replacen(
        "</robot>",
        "<!-- <xacro:include filename=\"$(find robot)/urdf/parts.xacro\"/> --></robot>",
        1,
    );
    let v = load_vehicle(&robot(&dir, &expanded)).expect("an expanded URDF is read");
    assert_eq!(v.flippers.len(), 2);
    let macro_file = expanded.replacen(
        "</robot>",
        "<xacro:macro name=\"wheel\" params=\"side\"/></robot>",
        1,
    );
    let e = load_vehicle(&robot(&dir, &macro_file))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("xacro file") && e.contains("expand it first"),
        "{e}"
    );
    let undeclared = bundled().replacen(
        "</robot>",
        "<xacro:property name=\"r\" value=\"0.1\"/></robot>",
        1,
    );
    let e = load_vehicle(&robot(&dir, &undeclared))
        .unwrap_err()
        .to_string();
    assert!(e.contains("xacro file"), "{e}");
}

/// A lidar gimbal locked by `<limit lower="a" upper="a">` (gz-sim's habit) is part of the
/// chassis: the robot keeps its two flippers and gains the gimbal's mass.
#[test]
fn a_locked_revolute_joint_is_fixed() {
    let dir = scratch("locked");
    let base = load_vehicle(&robot(&dir, &bundled())).unwrap();
    for angle in ["0", "0.5"] {
        let gimbal = format!(
            r#"<link name="gimbal"><inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="gimbal_joint" type="revolute"><parent link="base_link"/><child link="gimbal"/><origin xyz="0.1 0 0.08"/><axis xyz="0 0 1"/><limit lower="{angle}" upper="{angle}" effort="1" velocity="1"/></joint>
</robot>"#
        );
        let urdf = bundled().replacen("</robot>", &gimbal, 1);
        let v = load_vehicle(&robot(&dir, &urdf)).expect("a locked joint is read");
        assert_eq!(v.flippers.len(), 2, "the gimbal is no flipper");
        assert!(
            (v.body.mass - base.body.mass - 0.5).abs() < 1e-9,
            "{} against {} + 0.5 kg",
            v.body.mass,
            base.body.mass
        );
    }
}

#[test]
fn a_robot_model_given_for_a_tracksim_file_is_named() {
    let dir = scratch("xml");
    for (file, text, kind) in [
        ("r.urdf", bundled(), "a URDF robot"),
        (
            "w.sdf",
            "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\"><world name=\"w\"/></sdf>\n".to_string(),
            "an SDF model or world",
        ),
    ] {
        let p = dir.join(file);
        std::fs::write(&p, text).unwrap();
        for e in [
            load_vehicle(&p).unwrap_err().to_string(),
            tracksim::load_scenario(&p).unwrap_err().to_string(),
        ] {
            assert!(e.contains(kind) && e.contains("urdf = "), "{e}");
            assert!(!e.contains("TOML parse error"), "{e}");
        }
    }
}

/// The bundled robot with a gimbal link (0.5 kg) on joint `gimbal_joint` of type `kind`, its
/// inertia `inertia` and inertial origin `com`, and `keys` added to the vehicle.
fn with_gimbal(dir: &Path, kind: &str, inertia: &str, com: &str, keys: &str) -> PathBuf {
    let limit = if kind == "revolute" {
        r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#
    } else {
        ""
    };
    let gimbal = format!(
        r#"<link name="gimbal"><inertial><origin xyz="{com}"/><mass value="0.5"/><inertia {inertia}/></inertial>
  <collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="gimbal_joint" type="{kind}">{limit}<parent link="base_link"/><child link="gimbal"/><origin xyz="0.1 0 0.08"/><axis xyz="0 0 1"/></joint>
</robot>"#
    );
    let v = robot(dir, &bundled().replacen("</robot>", &gimbal, 1));
    let text = std::fs::read_to_string(&v).unwrap().replacen(
        "urdf = \"robot.urdf\"",
        &format!("urdf = \"robot.urdf\"\n{keys}"),
        1,
    );
    std::fs::write(&v, text).unwrap();
    v
}

const SMALL_INERTIA: &str = r#"ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001""#;

#[test]
fn rigid_joints_and_flipper_joints_choose_the_arms() {
    let dir = scratch("roles");
    let base = load_vehicle(&robot(&dir, &bundled())).unwrap();
    let load =
        |keys: &str| load_vehicle(&with_gimbal(&dir, "revolute", SMALL_INERTIA, "0 0 0", keys));
    // A free revolute gimbal is an arm by default (the trouble the issue reports) ...
    let v = load("").unwrap();
    assert_eq!(v.flippers.len(), 3);
    // ... kept rigid by name, or left out of the named flippers: part of the chassis.
    for keys in [
        "rigid_joints = [\"gimbal_joint\"]",
        "flipper_joints = [\"front_left\", \"front_right\"]",
    ] {
        let v = load(keys).unwrap();
        let names: Vec<&str> = v.flippers.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["front_left", "front_right"], "{keys}");
        assert!((v.body.mass - base.body.mass - 0.5).abs() < 1e-9, "{keys}");
    }
    for (keys, want) in [
        ("rigid_joints = [\"gimbl_joint\"]", "rigid_joints[0]"),
        ("flipper_joints = [\"front_lft\"]", "flipper_joints[0]"),
        (
            "rigid_joints = [\"front_left\"]\nflipper_joints = [\"front_left\"]",
            "also in `rigid_joints`",
        ),
    ] {
        let e = load(keys).unwrap_err().to_string();
        assert!(e.contains(want), "{keys}: {e}");
    }
    let e = load_vehicle(&with_gimbal(
        &dir,
        "revolute",
        SMALL_INERTIA,
        "0 0 0",
        "rigid_joints = [\"gimbl_joint\"]",
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("gimbal_joint"), "a suggestion: {e}");
}

#[test]
fn a_continuous_flipper_carrying_a_track_is_an_arm() {
    let dir = scratch("continuous");
    let urdf = bundled().replacen(
        "<joint name=\"front_left\" type=\"revolute\">",
        "<joint name=\"front_left\" type=\"continuous\">",
        1,
    );
    let v = load_vehicle(&robot(&dir, &urdf)).expect("a continuous flipper is read");
    let names: Vec<&str> = v.flippers.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["front_left", "front_right"]);
    assert_eq!(
        v.flippers[0].limits, None,
        "a continuous joint has no limits"
    );
    assert!(v.flippers[1].limits.is_some());
    // It is driven: the flipper of a run holds its commanded angle (its position controller).
    let path = root().join("scenarios/packbot_flat.toml");
    let spec: tracksim::spec::ScenarioSpec = tracksim::model::read_toml(&path).unwrap();
    let sc = tracksim::compile_scenario(&spec, v, &root().join("scenarios")).unwrap();
    let mut sim = tracksim::Scripted::new(&sc).unwrap();
    crate::common::run_until(&mut sim, 2.0);
    assert!(
        sim.flipper_angle(0).abs() < 0.02,
        "{}",
        sim.flipper_angle(0)
    );
}

#[test]
fn zero_inertia_on_a_merged_link_is_a_point_mass_with_a_warning() {
    let dir = scratch("point");
    let base = load_vehicle(&robot(&dir, &bundled())).unwrap();
    let zero = r#"ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0""#;
    let v = load_vehicle(&with_gimbal(&dir, "fixed", zero, "0 0 0", "")).unwrap();
    // 0.5 kg at (0.1, 0, 0.08) m: the mass adds, and the inertia about z grows by at least the
    // point's own m (x^2 + y^2) about the new centre of mass (parallel-axis theorem).
    assert!((v.body.mass - base.body.mass - 0.5).abs() < 1e-9);
    let m = base.body.mass;
    let d = glam::DVec3::new(0.1, 0.0, 0.08) - base.body.com;
    let mu = m * 0.5 / (m + 0.5);
    let want_izz = base.body.inertia.z + mu * (d.x * d.x + d.y * d.y);
    assert!(
        (v.body.inertia.z - want_izz).abs() < 1e-9 * want_izz,
        "{} vs {want_izz}",
        v.body.inertia.z
    );
    let report = v.urdf.as_ref().unwrap().lines().join("\n");
    assert!(
        report.contains("warning") && report.contains("point mass"),
        "{report}"
    );
    // On a body of its own (the root link), zero inertia is still refused.
    let root_zero = bundled().replacen(
        r#"ixx="0.06645833333333334" ixy="0" ixz="0" iyy="0.23833333333333334" iyz="0" izz="0.2864583333333333""#,
        zero,
        1,
    );
    assert_ne!(root_zero, bundled());
    let e = load_vehicle(&robot(&dir, &root_zero))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("base_link") && e.contains("not positive definite"),
        "{e}"
    );
}

#[test]
fn a_centre_of_mass_far_outside_its_link_is_warned() {
    let dir = scratch("far");
    let near = load_vehicle(&with_gimbal(&dir, "fixed", SMALL_INERTIA, "0.01 0 0", "")).unwrap();
    let text = near.urdf.as_ref().unwrap().lines().join("\n");
    assert!(!text.contains("centre of mass is"), "{text}");
    let far = load_vehicle(&with_gimbal(&dir, "fixed", SMALL_INERTIA, "5 0 0", "")).unwrap();
    let text = far.urdf.as_ref().unwrap().lines().join("\n");
    assert!(
        text.contains("centre of mass is") && text.contains("gimbal"),
        "{text}"
    );
}
