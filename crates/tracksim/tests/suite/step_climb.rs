//! Grousers matter (issue 2): a PackBot step just above the front pulley's centre is climbed with
//! grousers and not without, at friction 0.6 (the paper's Sec. IV-B observation).

use crate::common;
use common::*;
use tracksim::Scripted;

/// Front pulley centre height with 8 mm grousers on the ground: 0.082 + 0.008 m.
const PULLEY_CENTRE_M: f64 = 0.090;
/// Pulley top plus grouser height: 0.090 + 0.082 + 0.008 m.
const PULLEY_TOP_PLUS_GROUSER_M: f64 = 0.180;

/// Drives at 0.3 m/s for 8 s towards a 2 m long step of height `h` starting at x = 0.5 m;
/// returns whether the body ended up on top of it (x past the edge, z at ride height on top).
fn climbs(h: f64, grousers: bool) -> bool {
    let sc = packbot(
        |s| {
            s.simulation.duration_s = 8.0;
            s.terrain.boxes.push(step_box(0.5, 2.0, h));
            if !grousers {
                s.vehicle.grouser_count = Some(0);
            }
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    run_until(&mut sim, 8.0);
    let p = sim.body_pose();
    let ride = if grousers { PULLEY_CENTRE_M } else { 0.082 };
    p.x > 1.0 && (p.z - (h + ride)).abs() < 0.01
}

#[test]
fn step_above_the_pulley_centre_is_climbed_with_grousers_only() {
    let h = 0.10;
    assert!(h > PULLEY_CENTRE_M && h < PULLEY_TOP_PLUS_GROUSER_M);
    assert!(
        climbs(h, true),
        "with grousers the {h} m step must be climbed"
    );
    assert!(
        !climbs(h, false),
        "without grousers the {h} m step must not be climbed"
    );
}

#[test]
fn a_low_step_is_climbed_without_grousers_too() {
    // The smooth belt is not simply unable to climb: a step well below the pulley centre works.
    assert!(climbs(0.05, false));
}
