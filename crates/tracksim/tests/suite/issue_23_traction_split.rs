//! Issue 23.7: `max_traction_n` read 1458 N on a 245 N robot, because "traction" was the
//! terrain's whole contact force along the chassis's x, a wall's push included. It is now
//! split into the friction that drives (`friction_traction_n`) and the surfaces' normal
//! reactions (`reaction_n`), whose sum is the old traction.

use crate::common;
use common::root;

fn run(file: &str) -> tracksim::run::RunResult {
    let sc = tracksim::load_scenario(&root().join("scenarios").join(file)).unwrap();
    tracksim::run_scenario(&sc, |_, _| {}).unwrap()
}

#[test]
fn traction_is_friction_plus_reaction_and_a_wall_only_pushes_back() {
    // PackBot driving into a low-friction wall (paper Fig. 3): stalled against it.
    let r = run("wall_low_friction.toml");
    let weight = r.summary.mass.total_simulated_kg * 9.81;
    let mut stalled = 0;
    let (mut friction, mut reaction) = (0.0, 0.0);
    for s in &r.samples {
        for l in &s.loads {
            assert!((l.traction_n - l.friction_traction_n - l.reaction_n).abs() < 1e-6);
        }
        if s.t > 5.0 {
            stalled += 1;
            friction += s.loads.iter().map(|l| l.friction_traction_n).sum::<f64>();
            reaction += s.loads.iter().map(|l| l.reaction_n).sum::<f64>();
        }
    }
    let (friction, reaction) = (friction / stalled as f64, reaction / stalled as f64);
    println!(
        "at the wall: friction {friction:.1} N forwards, reaction {reaction:.1} N (weight {weight:.1} N)"
    );
    // The belts grip the floor forwards; the wall's normal force pushes back as much (the
    // robot stands still), and neither is more than friction can give on the floor (mu 0.6
    // on the weight; 20 % for the per-manifold friction estimate of the track loads).
    assert!(
        friction > 0.0 && friction < 0.6 * weight * 1.2,
        "{friction}"
    );
    assert!(
        reaction < 0.0 && (friction + reaction).abs() < 0.1 * weight,
        "{reaction}"
    );
    for t in &r.summary.tracks {
        assert!(t.max_friction_traction_n < 0.6 * weight * 1.2, "{t:?}");
    }
}

#[test]
fn on_flat_ground_there_is_no_reaction_along_the_drive() {
    let r = run("packbot_flat.toml");
    for t in &r.summary.tracks {
        println!(
            "{}: friction {:.3} N, reaction {:.3} N",
            t.name, t.mean_friction_traction_n, t.mean_reaction_n
        );
        assert!(t.mean_reaction_n.abs() < 0.5, "{t:?}");
    }
}
