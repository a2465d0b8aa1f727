//! The track models the paper compares against (issue 4): every method drives the PackBot on
//! flat ground at the belt speed, and the paper's Fig. 2 and Fig. 3 scenarios give the paper's
//! outcomes for its method and for 4 wheels.

use crate::common;
use common::{root, run_until};
use tracksim::Method as TrackMethod;
use tracksim::{Outcome, Scripted};

fn scenario(file: &str, method: TrackMethod) -> tracksim::Scenario {
    common::load_with(
        file,
        tracksim::Overrides {
            method: Some(method),
            ..Default::default()
        },
    )
}

#[test]
fn every_method_drives_at_belt_speed_on_flat_ground() {
    for m in [
        TrackMethod::Okada2020,
        TrackMethod::Okada2020NoGrousers,
        TrackMethod::Wheels(4),
        TrackMethod::Wheels(13),
        TrackMethod::ConstraintToGround,
        TrackMethod::Plates,
    ] {
        let mut sim = Scripted::new(&scenario("scenarios/packbot_flat.toml", m)).unwrap();
        run_until(&mut sim, 1.0);
        let x1 = sim.body_pose().x;
        run_until(&mut sim, 5.0);
        let p = sim.body_pose();
        let v = (p.x - x1) / 4.0;
        // Within 5 % of 0.3 m/s, straight.
        assert!((v - 0.3).abs() < 0.015, "{}: {v} m/s", m.name());
        // The plate chain, deformable, wanders sideways a little (measured 2-6 cm in 10 s).
        let drift = if m == TrackMethod::Plates { 0.05 } else { 0.01 };
        assert!(p.y.abs() < drift, "{}: drift {} m", m.name(), p.y);
    }
}

/// The paper's Fig. 2, as ensemble verdicts (issue 38): over 8 perturbed starts the track
/// climbs the bump every time; the 4-wheel model stalls astride it from some starts. With 2
/// position-correction passes the 4 wheels climb in 2 of 8 at seed 0 (member 0 among them) and
/// 6 of 8 at seed 2: a margin, not the paper's clean failure (VALIDATION.md).
#[test]
fn fig2_bump_is_climbed_by_the_track_not_by_4_wheels() {
    let f = "scenarios/bump_wheels_vs_track.toml";
    let ens = |m: TrackMethod| {
        let mut opts = tracksim::ensemble::EnsembleOptions::new(8);
        opts.jobs = 2;
        let o = tracksim::Overrides {
            method: Some(m),
            ..Default::default()
        };
        let t = tracksim::ScenarioTemplate::load_with(&root().join(f), &o).unwrap();
        tracksim::ensemble::run_ensemble(&t, &opts, |_, _| {}).unwrap()
    };
    let track = ens(TrackMethod::Okada2020);
    assert_eq!(track.verdict(), "S 8/8", "track: {}", track.text());
    let wheels = ens(TrackMethod::Wheels(4));
    assert!(
        wheels.success_fraction() < 1.0,
        "4 wheels: {}",
        wheels.text()
    );
}

#[test]
fn fig3_the_papers_method_does_not_climb_a_low_friction_wall() {
    let f = "scenarios/wall_low_friction.toml";
    let r = tracksim::run_scenario(&scenario(f, TrackMethod::Okada2020), |_, _| {}).unwrap();
    assert!(matches!(r.outcome, Outcome::Failure(_)), "{:?}", r.outcome);
    // It pushes against the wall with its front pulley, pitch and height unchanged.
    let last = r.samples.last().unwrap().pose;
    assert!(
        last.pitch.abs() < 0.02 && (last.z - 0.09).abs() < 0.005,
        "{last:?}"
    );
    assert!(
        last.x > 0.6 && last.x < 0.7,
        "stopped at the wall: {last:?}"
    );
}

/// `simulation.contact_slop_m` applies to every method, not only the paper's: with 10 mm of
/// uncorrected penetration allowed, each model settles measurably deeper into flat ground in
/// 3 s than with rigid contact (measured 4.6-10.7 mm against 0.2-3.2 mm), and no deeper than
/// the slop plus the 1 mm a rigid contact allows.
#[test]
fn contact_slop_applies_to_every_method() {
    let deepest = |m: TrackMethod, slop: f64| {
        let sc = common::file_with(
            "scenarios/packbot_flat.toml",
            |s| {
                s.simulation.method = m.name();
                s.simulation.contact_slop_m = slop;
            },
            |_| {},
        );
        let mut sim = Scripted::new(&sc).unwrap();
        let mut d: f64 = 0.0;
        while sim.time() < 3.0 - 1e-9 {
            sim.step().unwrap();
            if sim.steps().is_multiple_of(10) {
                d = d.max(sim.contact_stats().1);
            }
        }
        d
    };
    for m in [
        TrackMethod::Okada2020,
        TrackMethod::Okada2020NoGrousers,
        TrackMethod::Wheels(4),
        TrackMethod::ConstraintToGround,
        TrackMethod::Plates,
    ] {
        let (rigid, slop) = (deepest(m, 0.0), deepest(m, 0.01));
        assert!(
            slop > rigid + 1e-3,
            "{}: {slop} m with slop, {rigid} m without",
            m.name()
        );
        assert!(slop < 0.011 + 1e-3, "{}: sank {slop} m", m.name());
    }
}
