//! The physics of the terrain (issue 3): on a plane inclined at 25 deg with friction 0.6 the
//! PackBot climbs; at 35 deg (beyond atan 0.6 = 31 deg) it slides back although its belts drive
//! it uphill.

use crate::common;
use common::*;
use tracksim::Scripted;
use tracksim::spec::BoxSpec;

/// Drives uphill at 0.3 m/s on a plane inclined at `deg` (rising towards +x) for 4 s after a
/// 1 s start; returns the mean velocity along the slope, m/s (positive: uphill).
fn speed_along_slope(deg: f64) -> f64 {
    let th = deg.to_radians();
    let half_thickness = 0.5;
    let sc = packbot(
        |s| {
            s.terrain.ground = None;
            // A 20 m x 4 m plate whose top surface passes through the origin.
            s.terrain.boxes.push(BoxSpec {
                centre_m: [half_thickness * th.sin(), 0.0, -half_thickness * th.cos()],
                size_m: [20.0, 4.0, 2.0 * half_thickness],
                yaw_deg: 0.0,
                pitch_deg: -deg,
                friction: 0.6,
                soil: None,
                color: None,
            });
            s.vehicle.pitch_deg = -deg;
            s.outcome.fail_off_terrain = false;
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    run_until(&mut sim, 1.0);
    let (x1, _, z1) = pos(&sim);
    run_until(&mut sim, 5.0);
    let (x5, _, z5) = pos(&sim);
    let along = (x5 - x1) * th.cos() + (z5 - z1) * th.sin();
    along / 4.0
}

#[test]
fn climbs_a_25_degree_slope() {
    let v = speed_along_slope(25.0);
    eprintln!("25 deg: {v:.4} m/s along the slope");
    // tan 25 = 0.47 < 0.6: the belts grip; allow 5 % slip.
    assert!(v > 0.285 && v < 0.31, "uphill speed {v} m/s");
}

#[test]
fn slides_back_on_a_35_degree_slope() {
    let v = speed_along_slope(35.0);
    eprintln!("35 deg: {v:.4} m/s along the slope");
    // tan 35 = 0.70 > 0.6: friction cannot hold the vehicle; it slides downhill.
    assert!(v < -0.05, "speed along the slope {v} m/s");
}
