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
