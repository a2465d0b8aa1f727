//! Segment links as a reduced-coordinate articulation (issue 16.3, `okada2020_multibody`): the
//! chassis tracks' links are multibody joints of the chassis, so they drive the PackBot like the
//! paper's impulse-jointed links, and a vehicle with flipper tracks (which keep impulse joints)
//! stays stable.

mod common;
use common::*;
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
fn drive_and_ride_height_match_the_paper_method() {
    let mut r = Vec::new();
    for m in ["okada2020", "okada2020_multibody"] {
        let mut sim = flat(m);
        run_until(&mut sim, 1.0);
        let (x0, _, _) = pos(&sim);
        run_until(&mut sim, 3.0);
        let (x1, _, z) = pos(&sim);
        r.push(((x1 - x0) / 2.0, z, sim.max_link_error()));
    }
    eprintln!("okada2020 {:?}, multibody {:?}", r[0], r[1]);
    // Same belt speed, same ground friction: the mean speed over 2 s within 0.5 %.
    assert!((r[0].0 - r[1].0).abs() < 0.005 * r[0].0, "{r:?}");
    // The same ride height within 0.5 mm.
    assert!((r[0].1 - r[1].1).abs() < 5e-4, "{r:?}");
    // The joint coordinates only drift by the motor's velocity error within a step: below
    // 0.1 mm and 2 mrad before the placement.
    assert!(r[1].2.0 < 1e-4 && r[1].2.1 < 2e-3, "{r:?}");
}

#[test]
fn flipper_tracks_on_impulse_joints_stay_stable() {
    let sc = with_vehicle(
        "vehicles/packbot510_flippers.toml",
        |s| {
            s.simulation.method = "okada2020_multibody".into();
            s.simulation.duration_s = 0.5;
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    // A flipper-rooted articulation was flung off within 15 ms.
    run_until(&mut sim, 0.5);
    let (_, _, z) = pos(&sim);
    assert!(z.is_finite() && z > 0.0 && z < 0.3, "{z}");
}
