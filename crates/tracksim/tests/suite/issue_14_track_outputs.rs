//! Issue 14.2 and 14.3: what a robot developer measures per track (slip, traction, normal load,
//! contacts) and what the robot's own encoders report (skid-steer odometry), checked against
//! statics and the ground truth. PackBot 510 (13.0 kg simulated, two body tracks).

use crate::common;
use common::{packbot, root};
use tracksim::Scripted;
use tracksim::model::{load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;

const G: f64 = 9.81;

/// Steps `sim` to `t` s and returns the per-track loads averaged over the last `window` s,
/// summed over the tracks: (normal N, traction N, contacts).
fn mean_loads(sim: &mut Scripted, t: f64, window: f64) -> (f64, f64, f64) {
    let (mut n, mut tr, mut c, mut k) = (0.0, 0.0, 0.0, 0.0);
    while sim.time() < t - 1e-9 {
        sim.step().unwrap();
        if sim.time() > t - window {
            let s = sim.sample();
            n += s.loads.iter().map(|l| l.normal_n).sum::<f64>();
            tr += s.loads.iter().map(|l| l.traction_n).sum::<f64>();
            c += s.loads.iter().map(|l| l.contacts as f64).sum::<f64>();
            k += 1.0;
        }
    }
    (n / k, tr / k, c / k)
}

fn parked_on(slope_deg: f64) -> tracksim::Scenario {
    let path = root().join("scenarios/packbot_parked_slope.toml");
    let mut spec: ScenarioSpec = read_toml(&path).unwrap();
    let a = slope_deg.to_radians();
    spec.vehicle.pitch_deg = -slope_deg;
    spec.terrain.boxes[0].pitch_deg = -slope_deg;
    spec.terrain.boxes[0].centre_m = [0.5 * a.sin(), 0.0, -0.5 * a.cos()];
    let dir = root().join("scenarios");
    let vehicle = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    tracksim::compile_scenario(&spec, vehicle, &dir).unwrap()
}

#[test]
fn at_rest_the_tracks_carry_the_weight_and_on_a_slope_the_traction_holds_it() {
    for slope in [0.0f64, 20.0] {
        let sc = parked_on(slope);
        let mut sim = Scripted::new(&sc).unwrap();
        let m = sim.mass_report().total_simulated_kg;
        let (n, tr, c) = mean_loads(&mut sim, 3.0, 1.0);
        let a = slope.to_radians();
        println!(
            "{slope} deg: normal {n:.2} N (m g cos {:.2}), traction {tr:.2} N (m g sin {:.2}), {c:.0} contacts",
            m * G * a.cos(),
            m * G * a.sin()
        );
        // At rest the contact forces balance gravity (the chassis touches nothing): 2 % for the
        // solver's residual and the one-step impulse averaging.
        assert!(c > 0.0);
        assert!((n - m * G * a.cos()).abs() < 0.02 * m * G, "normal {n}");
        assert!((tr - m * G * a.sin()).abs() < 0.02 * m * G, "traction {tr}");
    }
}

#[test]
fn on_flat_ground_at_constant_speed_slip_and_traction_are_near_zero() {
    let sc = packbot(|_| {}, |_| {});
    let mut sim = Scripted::new(&sc).unwrap();
    let m = sim.mass_report().total_simulated_kg;
    let (_, tr, _) = mean_loads(&mut sim, 4.0, 2.0);
    let s = sim.sample();
    println!(
        "flat 0.3 m/s: traction {tr:.3} N, slip {:?}, cmd {:?}",
        s.slip, s.belt_cmd
    );
    // Rigid ground and rigid belts: no rolling resistance but the solver's; less than 1 % of
    // the weight, and the belts run at the ground speed within 2 %.
    assert!(tr.abs() < 0.01 * m * G, "traction {tr} N");
    for (slip, cmd) in s.slip.iter().zip(&s.belt_cmd) {
        assert!(slip.abs() < 0.02, "slip {slip}");
        assert_eq!(*cmd, 0.3);
    }
}

/// Odometry of a straight drive and of a skid turn, against the ground truth.
#[test]
fn odometry_is_exact_without_slip_and_overturns_in_a_skid_turn() {
    // Straight at 0.3 m/s from 1 s (after the start-up slip: the belts start at full speed)
    // to 5 s: the encoders see what the body does.
    let sc = packbot(|_| {}, |_| {});
    let mut sim = Scripted::new(&sc).unwrap();
    common::run_until(&mut sim, 1.0);
    let (s0, p0) = (sim.sample(), sim.body_pose());
    common::run_until(&mut sim, 5.0);
    let (s, p) = (sim.sample(), sim.body_pose());
    let (dx, dy) = (p.x - p0.x, p.y - p0.y);
    let (ox, oy) = (s.odom[0] - s0.odom[0], s.odom[1] - s0.odom[1]);
    let err = ((ox - dx).powi(2) + (oy - dy).powi(2)).sqrt();
    println!(
        "straight 1-5 s: truth ({dx:.4}, {dy:.4}) m, odometry ({ox:.4}, {oy:.4}) m, error {:.2} mm",
        err * 1e3
    );
    // 0.5 % of the distance: the belts' measured speed against the body's (no slip).
    assert!(dx > 1.0 && err < 0.005 * dx, "error {err} m over {dx} m");

    // Skid turn on the spot at 0.5 rad/s commanded: the tracks skid, so the geometric
    // separation overestimates the yaw; the effective separation B_eff = (v_r - v_l) / w
    // measured from the truth, set as `odometry.track_separation_m`, makes odometry match.
    let turn = |separation: Option<f64>| {
        let sc = packbot(|_| {}, |v| v.odometry_separation = separation);
        let mut sim = Scripted::new(&sc).unwrap();
        sim.step().unwrap(); // the file's t = 0 command, then the turn replaces it
        sim.set_twist(0.0, 0.5);
        let mut yaw0 = None;
        let (mut dv, mut k) = (0.0, 0.0);
        while sim.time() < 4.0 {
            sim.step().unwrap();
            if sim.time() >= 1.0 {
                let s = sim.sample();
                yaw0.get_or_insert((sim.body_pose().yaw, s.odom[2]));
                dv += s.belt_speed[1] - s.belt_speed[0];
                k += 1.0;
            }
        }
        let (t0, o0) = yaw0.unwrap();
        let truth = sim.body_pose().yaw - t0;
        let odom = sim.sample().odom[2] - o0;
        (truth, odom, dv / k)
    };
    let (truth, odom, dv) = turn(None);
    let b_geo = {
        let v = packbot(|_| {}, |_| {}).vehicle.clone();
        v.tracks[0].lateral_offset() - v.tracks[1].lateral_offset()
    };
    let b_eff = dv * 3.0 / truth;
    println!(
        "skid turn 3 s: truth {truth:.4} rad, odometry {odom:.4} rad (B {b_geo:.3} m), B_eff {b_eff:.3} m"
    );
    assert!(truth > 0.1, "it turned left");
    // Skid: the odometry over-turns by B_eff / B (the skid-steer model's prediction).
    assert!(odom > 1.05 * truth, "no skid seen: {odom} vs {truth}");
    assert!((odom / truth - b_eff / b_geo).abs() < 0.03 * b_eff / b_geo);
    let (truth2, odom2, _) = turn(Some(b_eff));
    println!("with B_eff: truth {truth2:.4} rad, odometry {odom2:.4} rad");
    assert!((odom2 - truth2).abs() < 0.03 * truth2);
}

/// Issue 14.4: every run also draws `signals.png` / `.svg` (position, speed, yaw, flippers,
/// slip and traction against time) with one legend entry per track.
#[test]
fn a_run_draws_its_signals() {
    let sc = packbot(|s| s.simulation.duration_s = 0.5, |_| {});
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let dir = std::env::temp_dir().join(format!("tracksim_signals_{}", std::process::id()));
    let written = tracksim::output::write_run_plots(&sc, &r, &dir).unwrap();
    let svg = dir.join("signals.svg");
    assert!(written.contains(&svg) && written.contains(&dir.join("signals.png")));
    let text = std::fs::read_to_string(&svg).unwrap();
    for label in ["slip ratio", "traction (N)", "yaw (°)", "left", "right"] {
        assert!(text.contains(label), "signals.svg lacks {label}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
