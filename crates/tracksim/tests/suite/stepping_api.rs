//! The stepping API (issue 10): the caller's controls are the only ones a `Simulation` applies,
//! `Scripted` applies the file's `[[commands]]`, and `reset` rebuilds the same world.

use crate::common;
use common::root;
use tracksim::{Controls, Scripted, Simulation};

fn flat() -> tracksim::Scenario {
    tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap()
}

#[test]
fn step_applies_no_file_command_behind_the_callers_back() {
    let sc = flat(); // its [[commands]] run the belts at 0.3 m/s from t = 0
    let mut bare = Simulation::new(&sc).unwrap();
    let mut scripted = Scripted::new(&sc).unwrap();
    let (x0, _, _) = common::pos(&scripted);
    for _ in 0..1000 {
        bare.step().unwrap();
        scripted.step().unwrap();
    }
    // Belts at rest: the landing settles the body by well under 1 mm along x.
    assert!(
        (bare.body_pose().x - x0).abs() < 0.001,
        "{}",
        bare.body_pose().x
    );
    // The file's 0.3 m/s for 1 s, less the start-up (`tracksim run ... --duration 1`: 0.292 m).
    let moved = scripted.body_pose().x - x0;
    assert!(moved > 0.2 && moved < 0.31, "{moved}");
    // The caller's own controls drive the bare simulation the same way.
    bare.apply(&Controls::belts(&sc.vehicle, 0.3));
    assert_eq!(bare.commanded_belt_speed(0), 0.3);
}

#[test]
fn reset_rebuilds_the_same_world_with_the_new_seed() {
    let sc = flat();
    let drive = |sim: &mut Simulation| {
        sim.set_twist(0.3, 0.2);
        for _ in 0..500 {
            sim.step().unwrap();
        }
        sim.body_pose()
    };
    let mut sim = Simulation::new(&sc).unwrap();
    let first = drive(&mut sim);
    sim.reset(Some(7)).unwrap();
    assert_eq!((sim.time(), sim.steps(), sim.seed()), (0.0, 0, 7));
    // Deterministic: the same controls from the same rebuilt state give the same pose, bit
    // for bit.
    assert_eq!(drive(&mut sim), first);
    // A scripted run starts its command timeline again too.
    let mut s = Scripted::new(&sc).unwrap();
    for _ in 0..300 {
        s.step().unwrap();
    }
    let before = s.body_pose();
    s.reset(None).unwrap();
    for _ in 0..300 {
        s.step().unwrap();
    }
    assert_eq!(s.body_pose(), before);
    assert_eq!(s.seed(), sc.seed);
}
