//! The multiple-plate track (paper Sec. II-B): a closed chain of hinged plates around a driven
//! sprocket and a sprung idler. Slow, but it must drive at the commanded speed on flat ground
//! and stay stable over a step at dt = 1 ms.

use crate::common;
use common::*;
use tracksim::Method as TrackMethod;
use tracksim::Scripted;

/// Ride height of the body on the chain: cleat 0.008 + plate 0.010 + wheel radius 0.069 m
/// (the wheel fits inside the 40-plate polygon on the 0.082 m belt loop).
const RIDE_HEIGHT_M: f64 = 0.087;

#[test]
fn drives_at_the_commanded_speed_on_flat_ground() {
    let sc = load_with(
        "scenarios/packbot_flat.toml",
        tracksim::Overrides {
            method: Some(TrackMethod::Plates),
            ..Default::default()
        },
    );
    assert_eq!(sc.solver.dt, 0.001);
    let mut sim = Scripted::new(&sc).unwrap();
    run_until(&mut sim, 2.0);
    let x0 = pos(&sim).0;
    let (mut z_min, mut z_max) = (f64::MAX, f64::MIN);
    let mut belt = Vec::new();
    while sim.time() < 6.0 - 1e-9 {
        sim.step().expect("stable");
        let s = sim.sample();
        z_min = z_min.min(s.pose.z);
        z_max = z_max.max(s.pose.z);
        belt.push(s.belt_speed[0]);
        assert!(
            s.pose.pitch.abs() < 0.03 && s.pose.roll.abs() < 0.03,
            "{:?}",
            s.pose
        );
        assert!(s.pose.y.abs() < 0.05, "{:?}", s.pose);
    }
    let (x1, _, _) = pos(&sim);
    let v = (x1 - x0) / 4.0;
    let belt = belt.iter().sum::<f64>() / belt.len() as f64;
    eprintln!("speed {v:.4} m/s, belt {belt:.4} m/s, z in [{z_min:.4}, {z_max:.4}] m");
    assert!((v - 0.3).abs() < 0.015, "mean speed {v} m/s");
    assert!((belt - 0.3).abs() < 0.015, "measured belt speed {belt} m/s");
    assert!(
        z_min > RIDE_HEIGHT_M - 0.006 && z_max < RIDE_HEIGHT_M + 0.006,
        "body height in [{z_min}, {z_max}] m"
    );
}

#[test]
fn climbs_a_low_step_and_stays_stable() {
    let h = 0.05;
    let sc = packbot(
        |s| {
            s.terrain.boxes.push(step_box(0.5, 1.4, h));
            s.simulation.method = TrackMethod::Plates.name();
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    let mut max_pitch: f64 = 0.0;
    while sim.time() < 4.0 - 1e-9 {
        sim.step().expect("stable");
        let p = sim.body_pose();
        max_pitch = max_pitch.max(p.pitch.abs());
        assert!(p.roll.abs() < 0.1, "{p:?}");
    }
    let p = sim.body_pose();
    eprintln!("after 4 s: {p:?}, largest |pitch| {max_pitch:.3} rad");
    // The step's edge is at x = 0.5 m; the whole vehicle (axles at x +- 0.255 m) is on top.
    assert!(p.x > 0.5 + 0.3, "x = {}", p.x);
    assert!((p.z - (h + RIDE_HEIGHT_M)).abs() < 0.01, "z = {}", p.z);
    assert!(p.pitch.abs() < 0.03, "pitch = {}", p.pitch);
    assert!(max_pitch > 0.05, "it never tilted: did it meet the step?");
}
