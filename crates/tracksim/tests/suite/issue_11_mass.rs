//! Issue 11.2: the simulated vehicle weighed more than its file. `min_link_mass_kg` (0.5 kg)
//! floors every track link: the PackBot (11 kg body, 1 kg belts) was simulated at 15 kg, a
//! 20 kg robot with 1.5 kg belts on 6 links at about 23 kg. The floor stays (light links hop),
//! but the excess is taken back from the track's parent (`world/mass.rs`): the total and the
//! centre of mass are the file's, for every bundled scenario and every track method.

use crate::common;
use tracksim::{Method, Simulation};

/// The file's centre of mass of a vehicle without flippers, body frame, m.
fn file_com(v: &tracksim::VehicleModel) -> glam::DVec3 {
    let mut moment = v.body.com * v.body.mass;
    let mut m = v.body.mass;
    for t in &v.tracks {
        let n = 512;
        let l = t.path.length();
        let c = (0..n)
            .map(|i| t.path.frame_at(l * (i as f64 + 0.5) / n as f64).origin)
            .sum::<glam::DVec3>()
            / n as f64;
        moment += c * t.belt_mass;
        m += t.belt_mass;
    }
    moment / m
}

#[test]
fn every_bundled_vehicle_weighs_what_its_file_says_under_every_method() {
    let files = common::bundled_scenarios();
    for f in &files {
        for m in Method::COMPARED {
            let o = tracksim::Overrides {
                method: Some(*m),
                ..Default::default()
            };
            // A method that cannot model the vehicle (a motor) is refused when compiling.
            let Ok(sc) = tracksim::load_scenario_with(f, &o) else {
                continue;
            };
            let Ok(sim) = Simulation::new(&sc) else {
                continue; // e.g. plates on a vehicle whose loops they cannot wrap
            };
            let r = sim.mass_report();
            // f32 masses: 1e-7 relative.
            assert!(
                (r.total_simulated_kg - r.total_file_kg).abs() < 1e-4,
                "{} {m}: {} kg simulated, {} kg in the file",
                f.display(),
                r.total_simulated_kg,
                r.total_file_kg
            );
        }
    }
}

#[test]
fn a_light_belt_vehicle_keeps_its_mass_and_centre_of_mass() {
    for belt in [1.0, 0.2] {
        // The floor at 0.5 kg (the default until issue 23), so that it applies to both belts.
        let sc = common::packbot(
            |s| {
                s.vehicle.belt_mass_kg = Some(belt);
                s.simulation.min_link_mass_kg = 0.5;
            },
            |_| {},
        );
        let sim = Simulation::new(&sc).unwrap();
        let r = sim.mass_report();
        let want = 11.0 + 2.0 * belt;
        assert!((r.total_file_kg - want).abs() < 1e-9);
        assert!((r.total_simulated_kg - want).abs() < 1e-4, "{belt}: {r:?}");
        // Four links of at least 0.5 kg per track: 2 kg each, the body gives back the rest.
        let track = r.parts.iter().find(|p| p.part == "track left").unwrap();
        assert!((track.simulated_kg - 2.0).abs() < 1e-4, "{track:?}");
        let c = file_com(&sc.vehicle);
        let got = glam::DVec3::from_array(r.centre_of_mass_body_m);
        // Both sides sample the belt (64 points per link for its mass properties, 512 along the
        // loop here) and Rapier stores f32: they agree to micrometres; 0.1 mm is the bound.
        assert!((got - c).length() < 1e-4, "{belt}: {got} vs {c}");
    }
}

#[test]
fn a_floor_the_body_cannot_pay_for_is_refused_naming_the_key() {
    let sc = common::packbot(|s| s.simulation.min_link_mass_kg = 3.0, |_| {});
    let e = Simulation::new(&sc).err().expect("refused").to_string();
    assert!(e.contains("simulation.min_link_mass_kg"), "{e}");
}
