//! Issue 62: every run's margins (`summary.json` `margins`) against closed forms, on bundled
//! scenarios run to their end:
//! - parked on the 20 deg slope, the peak |pitch| is the slope's (the robot lies on it), the tilt
//!   margin the tip limit less it, and the two tracks share the weight's normal part m g cos 20;
//! - on flat ground at 0.3 m/s, each track carries half the weight (mirror symmetry) and the
//!   peak tilt is under 1 deg.

use crate::common::root;

fn run(name: &str) -> tracksim::RunResult {
    let sc = tracksim::load_scenario(&root().join("scenarios").join(name)).unwrap();
    tracksim::run::run_scenario(&sc, |_, _| {}).unwrap()
}

#[test]
fn a_robot_parked_on_a_slope_has_the_slope_as_its_peak_pitch() {
    let r = run("packbot_parked_slope.toml");
    let m = &r.summary.margins;
    let pitch = m.peak_abs_pitch_deg.unwrap().value;
    let mass = r.summary.mass.total_simulated_kg;
    let weight_normal = mass * 9.81 * 20f64.to_radians().cos();
    let loads: Vec<f64> = m
        .tracks
        .iter()
        .map(|t| t.min_normal_load_n.unwrap().value)
        .collect();
    println!(
        "parked on 20 deg: peak pitch {pitch:.3} deg, margin {:.3} deg of {:.1}; smallest loads {loads:?} N (m g cos = {weight_normal:.2} N)",
        m.tilt_margin_deg, m.tip_limit_deg
    );
    // The grousers lift the body 0.1 deg at most off the slope's plane over a 0.5 m base.
    assert!((pitch - 20.0).abs() < 0.5, "peak pitch {pitch} deg");
    assert!((m.tilt_margin_deg - (m.tip_limit_deg - pitch)).abs() < 1e-9);
    // Each track's smallest load: at least 40 % of the normal weight (half each, within the
    // load the grousers shift between the two sides as contacts come and go).
    for l in &loads {
        assert!(*l > 0.4 * weight_normal, "{loads:?} N of {weight_normal} N");
    }
}

#[test]
fn on_flat_ground_each_track_carries_about_half_the_weight() {
    let r = run("packbot_flat.toml");
    let m = &r.summary.margins;
    let w = r.summary.mass.total_simulated_kg * 9.81;
    let loads: Vec<f64> = m
        .tracks
        .iter()
        .map(|t| t.min_normal_load_n.unwrap().value)
        .collect();
    let (pitch, roll) = (
        m.peak_abs_pitch_deg.unwrap().value,
        m.peak_abs_roll_deg.unwrap().value,
    );
    println!(
        "flat: peak pitch {pitch:.3} deg, roll {roll:.3} deg; smallest loads {loads:?} N (m g / 2 = {:.2} N)",
        w / 2.0
    );
    assert!(pitch < 1.0 && roll < 1.0, "{pitch} {roll}");
    for l in &loads {
        // Never below 60 % of half the weight: the grousers' contacts come and go, but the
        // robot never lifts a side on flat ground.
        assert!(*l > 0.3 * w, "{loads:?} N, weight {w} N");
    }
    // Mirror symmetry: the two sides' smallest loads agree within 10 % of half the weight.
    assert!((loads[0] - loads[1]).abs() < 0.05 * w, "{loads:?}");
}

/// An ensemble gives each member's margins and their spread (issue 62: the developer read the
/// members' `trajectory.csv` files to find the peak pitch): every member's peak pitch in the
/// report equals the one its own run gives, and the spread covers them.
#[test]
fn an_ensemble_gives_the_spread_of_its_members_margins() {
    let f = root().join("scenarios/packbot_step.toml");
    let t = tracksim::load_template(&f).unwrap();
    let mut opts = tracksim::ensemble::EnsembleOptions::new(4);
    opts.seed = 62;
    let r = tracksim::ensemble::run_ensemble(&t, &opts, |_, _| {}).unwrap();
    let spreads = r.margin_spreads();
    let pitch = spreads.peak_abs_pitch_deg.unwrap();
    println!("{}", r.text());
    let plain = run("packbot_step.toml");
    let tip = plain.summary.margins.tip_limit_deg;
    for m in &r.members {
        let g = m.margins.unwrap();
        assert!(pitch.min <= g.peak_abs_pitch_deg && g.peak_abs_pitch_deg <= pitch.max);
        let worst = g.peak_abs_pitch_deg.max(g.peak_abs_roll_deg);
        assert!((g.tilt_margin_deg - (tip - worst)).abs() < 1e-9, "{g:?}");
    }
    // Member 0 is the file as written: its margins are the plain run's.
    let m0 = r.members[0].margins.unwrap();
    assert_eq!(
        m0.peak_abs_pitch_deg,
        plain.summary.margins.peak_abs_pitch_deg.unwrap().value
    );
    assert!(r.text().contains("margins: peak pitch"));
    // Climbing a 0.1 m step tilts the PackBot well off flat (the sine of its pitch times its
    // 0.5 m wheelbase is more than half the step) and far from tipping.
    assert!(pitch.min > 10.0 && pitch.max < 45.0, "{pitch:?}");
}
