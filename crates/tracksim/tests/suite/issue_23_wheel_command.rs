//! Issue 23.6: `vehicles/rover4_lugged.toml` stated its rim as `sprocket_pitch_radius_m`
//! (0.09 m), while a wheel's path is its rolling circle (0.119 m with its lugs), so a
//! `sprocket_rad_s` command turned the wheels at 0.76x the command. The command radius of a
//! wheel is now derived from its rolling circle, and a file stating another one is refused.

use crate::common;
use common::root;
use tracksim::spec::{PerTrack, ScenarioSpec, VehicleSpec};

#[test]
fn a_sprocket_command_turns_a_lugged_wheel_at_the_commanded_rate() {
    let dir = root().join("scenarios");
    let mut spec: ScenarioSpec =
        tracksim::model::read_toml(&dir.join("packbot_flat.toml")).unwrap();
    spec.vehicle.file = Some("../vehicles/rover4_lugged.toml".into());
    spec.simulation.duration_s = 6.0;
    for c in &mut spec.commands {
        c.belt_speed_mps = None;
        c.sprocket_rad_s = Some(PerTrack::All(2.0));
    }
    let vehicle =
        tracksim::model::load_vehicle(&root().join("vehicles/rover4_lugged.toml")).unwrap();
    let rolling = vehicle.tracks[0].path.length() / std::f64::consts::TAU;
    let sc = tracksim::compile_scenario(&spec, vehicle, &dir).unwrap();
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    // Speed over the last 3 s (past the start): 2 rad/s at the rolling radius, less a little
    // slip; at the rim's 0.09 m it was 0.18 m/s.
    let s = &r.samples.to_vec();
    let (a, b) = (&s[s.len() / 2], s.last().unwrap());
    let v = (b.pose.x - a.pose.x) / (b.t - a.t);
    println!(
        "rolling radius {rolling:.4} m: {v:.4} m/s for {:.4}",
        2.0 * rolling
    );
    assert!((rolling - 0.119).abs() < 0.001, "{rolling}");
    assert!((v - 2.0 * rolling).abs() < 0.02 * 2.0 * rolling, "{v} m/s");
}

#[test]
fn a_wheel_stating_another_command_radius_is_refused() {
    let mut v: VehicleSpec =
        tracksim::model::read_toml(&root().join("vehicles/rover4_lugged.toml")).unwrap();
    v.tracks[0].sprocket_pitch_radius_m = Some(0.09);
    let e = tracksim::model::compile_vehicle(&v).unwrap_err();
    let text = e
        .iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join("\n");
    assert!(text.contains("tracks[0].sprocket_pitch_radius_m"), "{text}");
    assert!(text.contains("rolling radius"), "{text}");
}
