//! Issue 60: CTU's Absolem as run in the SubT competition (`../shared/robots/ctu_absolem_subt`,
//! unchanged; skipped when absent) imports as the robot it is. Its `specifications.md` says:
//! two main tracks and "4 additional subtracks (flippers)" that "can continuously rotate" (SDF
//! revolute joints with SDFormat's +-1e16 "no limit"), and a lidar on a gimbal about x with
//! hard stops at +-2.36 rad. Before: the four flippers were merged into the main tracks as one
//! rigid 1.15 m loop, and the gimbal became a "flipper" with 2,000 N m/rad gains, silently.

use std::path::{Path, PathBuf};

fn absolem() -> Option<PathBuf> {
    let p = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/robots/ctu_absolem_subt/model.sdf"
    ))
    .to_path_buf();
    if p.is_file() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent (../shared/robots)", p.display());
        None
    }
}

/// The sum of every `<mass>` in the file's text, kg (the model's own total, read without
/// tracksim's reader).
fn file_masses(text: &str) -> f64 {
    text.split("<mass>")
        .skip(1)
        .map(|s| {
            s.split("</mass>")
                .next()
                .unwrap()
                .trim()
                .parse::<f64>()
                .unwrap()
        })
        .sum()
}

#[test]
fn absolem_imports_with_its_four_flippers_as_tracked_arms_and_its_gimbal_rigid() {
    let Some(model) = absolem() else { return };
    let out = std::env::temp_dir().join(format!("tracksim-60-absolem-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let imported = tracksim::import::import(&model, &out, true).unwrap();
    let r = &imported.report;
    let names: Vec<&str> = r.tracks.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "left_track",
            "right_track",
            "front_left_flipper",
            "rear_left_flipper",
            "front_right_flipper",
            "rear_right_flipper"
        ],
        "{:#?}",
        r.lines()
    );
    let mut flippers = r.flippers.clone();
    flippers.sort();
    assert_eq!(
        flippers,
        [
            "front_left_flipper_j",
            "front_right_flipper_j",
            "rear_left_flipper_j",
            "rear_right_flipper_j"
        ]
    );
    let rigid: Vec<&str> = r.rigid.iter().map(|(j, _)| j.as_str()).collect();
    assert_eq!(rigid, ["laser_j"]);
    // Nothing silent: each of these is a warning of the report (and a comment of the file).
    let warnings = r.warnings();
    for j in ["laser_j", "front_left_flipper_j", "rear_right_flipper_j"] {
        assert!(
            warnings.iter().any(|w| w.contains(j)),
            "{j} not said: {warnings:#?}"
        );
    }
    // The main tracks: the two 0.089 m pulleys 0.5 m apart of the track links, not a loop
    // round the flippers' tips (the merged loop was 2.52 m round, a pulley at x +-0.574 m).
    let main = &r.tracks[0];
    let perimeter = main.perimeter().unwrap();
    let want = 2.0 * 0.5 + 2.0 * std::f64::consts::PI * 0.089;
    assert!(
        (perimeter - want).abs() < 0.02,
        "perimeter {perimeter} m, want {want} m"
    );
    // Separation: between the track links' own y (+-0.1985 m) and their pulleys' (one at
    // -0.015 m in the link).
    let sep = r.geometry.separation.unwrap();
    assert!((0.367..=0.397).contains(&sep), "separation {sep} m");
    // The flipper tracks: round the 0.089 m pulley at the pivot and the 0.029 m one 0.33 m out.
    for t in &r.tracks[2..] {
        let p = t.perimeter().unwrap();
        let want = 2.0 * 0.33 + std::f64::consts::PI * (0.089 + 0.029);
        assert!(
            (p - want).abs() < 0.02,
            "{}: {p} m, want about {want} m",
            t.name
        );
    }
    // It runs as the robot it is: the file's mass, and the flat scenario at its belt speed.
    let sc = tracksim::load_scenario(&imported.scenario).unwrap();
    let result = tracksim::run::run_scenario(&sc, |_, _| {}).unwrap();
    let s = &result.summary;
    let text = std::fs::read_to_string(&model).unwrap();
    let total = file_masses(&text);
    println!(
        "Absolem: {} tracks, separation {sep:.4} m, mass {:.3} kg (file {total:.3} kg), speed {:.4} m/s, pitch {:.2} deg",
        names.len(),
        s.mass.total_simulated_kg,
        s.mean_speed_mps,
        s.final_pose.pitch.to_degrees()
    );
    // The model's masses, plus the belts the import adds on top of each track link (a guess
    // its report states: 10 % of the link's mass, at least 0.05 kg).
    let belts: f64 = r.tracks.iter().map(|t| t.belt_mass).sum();
    assert!(
        (s.mass.total_simulated_kg - total - belts).abs() < 1e-3,
        "{} kg simulated, {total} kg in the file and {belts} kg of belts",
        s.mass.total_simulated_kg
    );
    let v = tracksim::import::FLAT_BELT_SPEED_MPS;
    assert!(
        (s.mean_speed_mps - v).abs() < 0.02 * v,
        "mean speed {} m/s at belts of {v} m/s",
        s.mean_speed_mps
    );
    assert!(
        s.final_pose.pitch.abs() < 2f64.to_radians(),
        "pitch {}",
        s.final_pose.pitch
    );
    // Issue 61: its `/robot_description` is a URDF (it was the 50 kB SDF text, which RViz and
    // Foxglove cannot draw), with every flipper a revolute joint.
    let description = tracksim::output::urdf_export::robot_description(&sc);
    let urdf = urdf_rs::read_from_string(&description).expect("a URDF");
    let revolute = urdf
        .joints
        .iter()
        .filter(|u| u.joint_type != urdf_rs::JointType::Fixed)
        .count();
    assert_eq!(revolute, 4, "{description}");
    assert!(!description.contains("<sdf"));
    let _ = std::fs::remove_dir_all(&out);
}
