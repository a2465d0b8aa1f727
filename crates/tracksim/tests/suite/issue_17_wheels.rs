//! Issue 17.1: lugged wheels (paper Fig. 8). A wheel is a track whose path is one full circle
//! (`[tracks.path] wheel`), built by the paper's method as one segment link with its lugs,
//! rolled back by one lug pitch. The bundled rover (vehicles/rover4_lugged.toml): rim 0.09 m,
//! 12 thin plates 30 mm high (tips at 0.12 m), friction 0.5.

use crate::common;
use common::root;
use tracksim::Scripted;
use tracksim::model::{compile_vehicle, read_toml};
use tracksim::spec::{ScenarioSpec, VehicleSpec};

/// Outer radius of the rover's wheels (rim 0.09 m + lugs 0.03 m), m.
const TIP_RADIUS_M: f64 = 0.12;

/// The bundled step scenario (0.08 m step, edge at x = 0.6 m) with the rover on lugged
/// wheels, or on smooth wheels of the same outer radius and friction (`smooth`).
fn step_run(smooth: bool) -> tracksim::RunResult {
    let path = root().join("scenarios/rover4_lugged_step.toml");
    let spec: ScenarioSpec = read_toml(&path).unwrap();
    let mut v: VehicleSpec = read_toml(&root().join("vehicles/rover4_lugged.toml")).unwrap();
    if smooth {
        for t in &mut v.tracks {
            t.grousers = None;
            t.path.wheel.as_mut().unwrap().radius_m = TIP_RADIUS_M;
        }
    }
    let vehicle = compile_vehicle(&v).unwrap();
    let sc = tracksim::compile_scenario(&spec, vehicle, &root().join("scenarios")).unwrap();
    tracksim::run_scenario(&sc, |_, _| {}).unwrap()
}

/// Why the outcome is the physics: the rear wheels decide it (the front pair gets up, pushed
/// by the rear pair and helped by the load the horizontal forces shift backwards). Once the
/// front pair is on top, a smooth rear wheel of radius R = 0.12 m can only be lifted by its
/// contact with the 0.08 m edge, whose normal lies phi = acos((R - h) / R) = 70.5 deg from the
/// vertical; the contact force lies within the friction cone of half angle atan 0.5 = 26.6
/// deg about it, so every newton it lifts comes with at least tan(43.9 deg) = 0.96 N pushing
/// the rover back, which the front wheels must balance with traction of at most 0.5 times
/// their load: the edge can carry at most 0.52 times the front load, 34 % of the weight. It
/// has to carry 65 %: the edge contact lies R sin(phi) = 0.113 m ahead of the rear axle, so
/// with the centre of mass midway along the 0.5 m wheelbase the moments give it
/// 0.25 / (0.25 + 0.137) of the weight (both horizontal forces act at the step's height, so
/// they add no moment). A lug hooked over the
/// edge instead pushes on it with its face, along the wheel's tangent, which lifts without
/// needing friction, so the lugged wheel climbs.
#[test]
fn lugged_wheels_climb_a_step_that_smooth_wheels_of_the_same_radius_cannot() {
    let lugged = step_run(false);
    let smooth = step_run(true);
    let end = |r: &tracksim::RunResult| {
        let s = r.samples.last().unwrap();
        (s.pose.x, s.pose.z)
    };
    println!(
        "lugged: {} at {:?}; smooth: {} at {:?}",
        lugged.outcome.reason(),
        end(&lugged),
        smooth.outcome.reason(),
        end(&smooth)
    );
    assert_eq!(
        lugged.outcome.name(),
        "success",
        "{}",
        lugged.outcome.reason()
    );
    // On top: the body rests on the lug tips 0.12 m above the 0.08 m step (1 cm band for the
    // polygonal rolling, whose dip is R (1 - cos(15 deg)) = 4 mm, and the contact slop).
    let (x, z) = end(&lugged);
    assert!(x > 1.3 && (z - 0.20).abs() < 0.01, "lugged end {x} {z}");
    assert_ne!(smooth.outcome.name(), "success");
    // Stuck: the front wheels get up (pulled by nothing but pushed by the rear pair, which
    // is the easier case), the rear wheels stay at the foot: their axle (0.25 m behind the
    // body origin) short of the edge at 0.6 m.
    let (x, _) = end(&smooth);
    assert!(x - 0.25 < 0.6, "smooth end {x}");
}

/// On flat ground the rover rolls at its belt speed: the wheel's path is its rolling circle
/// (the perimeter of the hull of its lug tips over 2 pi), not its rim; a rim-radius wheel would
/// roll 0.12 / 0.09 = 33 % too fast. Tolerance 3 %, as the PackBot's flat-ground test.
#[test]
fn a_lugged_wheel_rolls_at_the_commanded_speed_on_flat_ground() {
    let sc = common::with_vehicle("vehicles/rover4_lugged.toml", |_| {}, |_| {});
    let mut sim = Scripted::new(&sc).unwrap();
    common::run_until(&mut sim, 2.0);
    let (x2, y2, _) = common::pos(&sim);
    common::run_until(&mut sim, 8.0);
    let (x8, y8, z8) = common::pos(&sim);
    let v = (x8 - x2) / 6.0;
    println!("mean speed {v} m/s, drift {} m, height {z8} m", y8 - y2);
    assert!((v - 0.3).abs() < 0.009, "mean forward speed {v} m/s");
    assert!((y8 - y2).abs() < 0.01, "drift {}", y8 - y2);
    // Axle height between the polygon's inradius and the tip radius (plus the slop).
    assert!(
        z8 > TIP_RADIUS_M * (15f64.to_radians().cos()) - 0.001 && z8 < TIP_RADIUS_M + 0.001,
        "height {z8}"
    );
}
