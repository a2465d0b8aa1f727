//! Line-tip grousers (issue 16.2, `okada2020_line_tips`): on flat ground each grouser meets the
//! ground through its tip capsule with at most 3 contact points instead of the box's 4 (the
//! exact hull does not touch the ground tile); the drive and ride height are the paper method's; a step is still hooked
//! by the exact hull.

use crate::common;
use common::*;
use rapier3d::prelude::ShapeType;
use tracksim::Scripted;

fn flat(method: &str) -> Scripted {
    let sc = packbot(
        |s| {
            s.simulation.method = method.into();
            s.simulation.duration_s = 3.0;
        },
        |_| {},
    );
    Scripted::new(&sc).unwrap()
}

#[test]
fn tips_give_two_points_per_grouser_and_hulls_skip_the_flat_ground() {
    let mut sim = flat("okada2020_line_tips");
    run_until(&mut sim, 1.0);
    let pairs = sim.contact_points_per_pair();
    let capsule: Vec<usize> = pairs
        .iter()
        .filter(|(t, _)| *t == ShapeType::Capsule)
        .map(|p| p.1)
        .collect();
    let cuboid: usize = pairs
        .iter()
        .filter(|(t, _)| *t == ShapeType::Cuboid)
        .map(|p| p.1)
        .sum();
    // A capsule against the box tile's face: parry clips the segment to 2 points and adds the
    // deepest point of the rounded shapes (2 against a half-space; examples/contact_floor).
    assert!(capsule.iter().all(|&n| n <= 3), "{capsule:?}");
    // The 2 x ~14 grousers under the lower runs (38 mm pitch on 510 mm) touch through tips.
    assert!(capsule.len() >= 24, "{} tip pairs", capsule.len());
    // Only the belt links' cuboids touch the ground (20 points without grousers, `tracksim
    // bench`); the 4-point grouser hulls would add ~130.
    assert!(cuboid <= 24, "{cuboid} cuboid points");
}

#[test]
fn drive_and_ride_height_match_the_paper_method() {
    let mut r = Vec::new();
    for m in ["okada2020", "okada2020_line_tips"] {
        let mut sim = flat(m);
        run_until(&mut sim, 1.0);
        let (x0, _, _) = pos(&sim);
        run_until(&mut sim, 3.0);
        let (x1, _, z) = pos(&sim);
        r.push(((x1 - x0) / 2.0, z));
    }
    eprintln!("okada2020 {:?}, line tips {:?}", r[0], r[1]);
    // Same belt speed, same ground friction: the mean speed over 2 s within 0.5 % (the
    // grousers' slip on rigid ground is below 0.3 % for both).
    assert!((r[0].0 - r[1].0).abs() < 0.005 * r[0].0, "{r:?}");
    // The tip capsule's outermost point is the grouser's tip: the same ride height within
    // 0.5 mm (contact softness differs with 2 instead of 4 points).
    assert!((r[0].1 - r[1].1).abs() < 5e-4, "{r:?}");
}

#[test]
fn the_exact_hull_still_hooks_a_step() {
    // 0.10 m: above the front pulley's centre (0.090 m), climbed only with grousers
    // (tests/suite/step_climb.rs).
    let h = 0.10;
    let sc = packbot(
        |s| {
            s.simulation.method = "okada2020_line_tips".into();
            s.simulation.duration_s = 8.0;
            s.terrain.boxes.push(step_box(0.5, 2.0, h));
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    run_until(&mut sim, 8.0);
    let p = sim.body_pose();
    // On top: past the edge at ride height (0.090 m) above the step, within 1 cm.
    assert!(p.x > 1.0 && (p.z - (h + 0.090)).abs() < 0.01, "{p:?}");
}

#[test]
fn alternating_grouser_shapes_are_refused_with_the_fix() {
    let sc = packbot(
        |s| s.simulation.method = "okada2020_line_tips".into(),
        |v| {
            for t in &mut v.tracks {
                let g = t.grousers.as_mut().unwrap();
                let again = g.shapes[0].clone();
                g.shapes.push(again);
            }
        },
    );
    let err = Scripted::new(&sc).err().expect("refused").to_string();
    assert!(
        err.contains("one grouser shape per track") && err.contains("use okada2020"),
        "{err}"
    );
}
