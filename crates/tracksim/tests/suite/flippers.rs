//! Sub-tracks on flipper arms (issue 2): position-controlled joints with a torque limit, tracks
//! hanging on the arms.

use crate::common;
use common::*;
use tracksim::Scripted;
use tracksim::spec::{CommandSpec, PerTrack};

fn flipper_cmd(t: f64, deg: f64, belt: f64) -> CommandSpec {
    CommandSpec {
        t_s: t,
        belt_speed_mps: Some(PerTrack::All(belt)),
        sprocket_rad_s: None,
        flipper_angle_deg: [
            ("front_left".to_string(), deg),
            ("front_right".to_string(), deg),
        ]
        .into(),
        ..Default::default()
    }
}

#[test]
fn flippers_reach_their_target_and_their_tracks_drive() {
    let sc = with_vehicle(
        "vehicles/packbot510_flippers.toml",
        |s| s.commands = vec![flipper_cmd(0.0, 45.0, 0.2)],
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    run_until(&mut sim, 2.0);
    let x0 = sim.body_pose().x;
    for i in 0..2 {
        let a = sim.flipper_angle(i).to_degrees();
        // Position servo against gravity with 2000 N m/rad: steady error ~ 1 N m / 2000 rad.
        assert!((a - 45.0).abs() < 1.0, "flipper {i} at {a} deg");
    }
    run_until(&mut sim, 6.0);
    let v = (sim.body_pose().x - x0) / 4.0;
    assert!((v - 0.2).abs() < 0.01, "speed {v} m/s with raised flippers");
    // Sub-track belts run at the commanded speed too (tracks 2 and 3 hang on the arms).
    let s = sim.sample();
    assert_eq!(s.belt_speed.len(), 4);
    for b in &s.belt_speed {
        assert!((b - 0.2).abs() < 0.005, "belt {b}");
    }
}

#[test]
fn the_torque_limit_decides_whether_flippers_can_lift_the_body() {
    // Pressing the flippers down (-30 deg) lifts the front: about 13 kg * 9.81 * 0.15 m ~ 20 N m
    // per side is needed. 60 N m does it; 2 N m does not.
    let pitch_after = |torque: f64| {
        let sc = with_vehicle(
            "vehicles/packbot510_flippers.toml",
            |s| s.commands = vec![flipper_cmd(0.0, -30.0, 0.0)],
            |v| {
                for f in &mut v.flippers {
                    f.max_torque = torque;
                }
            },
        );
        let mut sim = Scripted::new(&sc).unwrap();
        run_until(&mut sim, 2.0);
        sim.body_pose().pitch.to_degrees()
    };
    let strong = pitch_after(60.0);
    let weak = pitch_after(2.0);
    // REP 103: nose up is negative pitch.
    assert!(
        strong < -5.0,
        "strong flippers pitch the body to {strong} deg"
    );
    assert!(
        weak.abs() < 2.0,
        "weak flippers pitch the body to {weak} deg"
    );
}
