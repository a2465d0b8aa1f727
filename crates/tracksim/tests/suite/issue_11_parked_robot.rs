//! Issue 11.4: a parked robot crept. A PackBot 510 with its belts held at 0 on a 20 deg slope
//! (friction 0.6, tan 20 = 0.36: well inside the friction cone) moved steadily: 0.014 mm/s
//! along the slope, 0.20 mm/s sideways and 0.021 deg/s in yaw, about 12 deg of turn in
//! 10 minutes. The cause is Rapier's default of solving no friction in its position-correction
//! (bias) pass: each step the pass that pushes out penetrations and joint errors (the segment
//! links are re-placed on their joints every step) moved the vehicle with no friction to stop
//! it. `simulation.held_friction_in_bias_pass` (default true) solves friction there too while
//! every belt is held (not while driving, where it drags: 3-5 % lower speed on flat ground); the
//! held vehicle then holds. The second test keeps the mechanism visible: with the pass off the same
//! vehicle creeps, so the first test is not passing by accident.

use crate::common;
use common::root;
use tracksim::Scripted;
use tracksim::model::{load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;

/// The bundled parked-on-a-slope scenario for `duration` s.
fn parked(duration: f64, held_friction_in_bias_pass: bool) -> tracksim::Scenario {
    let path = root().join("scenarios/packbot_parked_slope.toml");
    let mut spec: ScenarioSpec = read_toml(&path).unwrap();
    spec.simulation.duration_s = duration;
    spec.simulation.held_friction_in_bias_pass = held_friction_in_bias_pass;
    let dir = root().join("scenarios");
    let vehicle = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    tracksim::compile_scenario(&spec, vehicle, &dir).unwrap()
}

/// Displacement (m) and yaw change (deg) of the body from `settle` s to `end` s.
fn drift(sc: &tracksim::Scenario, settle: f64, end: f64) -> (f64, f64) {
    let mut sim = Scripted::new(sc).unwrap();
    while sim.time() < settle - 1e-9 {
        sim.step().unwrap();
    }
    let a = sim.body_pose();
    while sim.time() < end - 1e-9 {
        sim.step().unwrap();
    }
    let b = sim.body_pose();
    let d = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2) + (b.z - a.z).powi(2)).sqrt();
    (d, (b.yaw - a.yaw).to_degrees())
}

#[test]
fn a_braked_packbot_holds_on_20_deg_for_10_minutes() {
    // 5 s to settle onto the slope (it is placed just above it), then 10 minutes held.
    let (d, yaw) = drift(&parked(605.0, true), 5.0, 605.0);
    println!(
        "held 600 s on 20 deg: moved {:.4} mm, turned {yaw:.5} deg",
        d * 1e3
    );
    assert!(d < 1e-3, "moved {:.3} mm in 600 s (limit 1 mm)", d * 1e3);
    assert!(
        yaw.abs() < 0.1,
        "turned {yaw:.4} deg in 600 s (limit 0.1 deg)"
    );
}

#[test]
fn without_friction_in_the_bias_pass_it_creeps() {
    // 20 s held: at the 0.2 mm/s measured before the fix that is ~4 mm, far above what the
    // fixed vehicle moves in 600 s.
    let (d, yaw) = drift(&parked(25.0, false), 5.0, 25.0);
    println!(
        "bias pass without friction, 20 s: moved {:.4} mm, turned {yaw:.5} deg",
        d * 1e3
    );
    assert!(
        d > 1e-3,
        "expected creep above 1 mm in 20 s, got {:.4} mm",
        d * 1e3
    );
}
