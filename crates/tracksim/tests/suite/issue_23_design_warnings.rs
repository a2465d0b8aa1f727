//! Issue 23.7: `tracksim check` printed "ground clearance -60.0 mm (body above the track
//! bottoms)" with exit 0 for a body hanging below its tracks, and said nothing about tracks
//! placed inside the body (one vehicle's colliders never collide, so such a track runs through
//! the body silently). Both are now warnings of the design report; the bundled vehicles have
//! neither.

use crate::common;
use common::root;
use tracksim::model::{compile_vehicle, design_report, read_toml};
use tracksim::spec::{ShapeSpec, VehicleSpec};

fn packbot() -> VehicleSpec {
    read_toml(&root().join("vehicles/packbot510.toml")).unwrap()
}

fn warnings(spec: &VehicleSpec) -> Vec<String> {
    design_report(&compile_vehicle(spec).unwrap()).warnings
}

#[test]
fn a_body_below_its_tracks_is_warned_about() {
    let mut v = packbot();
    // The PackBot's box is 0.10 m high on a chassis frame at the axles; the track bottoms
    // (grouser tips) are 0.090 m below them. A 0.30 m high box reaches 0.15 m down: 60 mm
    // below the tracks.
    v.body.as_mut().unwrap().shape = ShapeSpec::Box {
        size_m: [0.50, 0.25, 0.30],
        centre_m: [0.0, 0.0, 0.0],
    };
    let r = design_report(&compile_vehicle(&v).unwrap());
    assert!(
        (r.ground_clearance_m.unwrap() + 0.060).abs() < 1e-3,
        "{r:?}"
    );
    let w = r.warnings.join("\n");
    assert!(w.contains("hangs 60.0 mm below"), "{w}");
}

#[test]
fn a_track_inside_the_body_is_warned_about() {
    let mut v = packbot();
    // The left track's plane at y = 0.05 m: its 75 mm belt lies within the 0.25 m wide body,
    // and a body 0.20 m high from z = -0.05 m holds the top run (z = +0.082 m).
    v.tracks[0].path.plane_y_m = Some(0.05);
    v.body.as_mut().unwrap().shape = ShapeSpec::Box {
        size_m: [0.50, 0.25, 0.20],
        centre_m: [0.0, 0.0, 0.05],
    };
    let w = warnings(&v).join("\n");
    assert!(w.contains("track left runs inside the body"), "{w}");
    // Its mirror too (the right track is the left one mirrored).
    assert!(w.contains("track right runs inside the body"), "{w}");
    // At its place (y = 0.1625 m, outside the 0.125 m half-width) nothing is said.
    let mut v = packbot();
    v.body.as_mut().unwrap().shape = ShapeSpec::Box {
        size_m: [0.50, 0.25, 0.20],
        centre_m: [0.0, 0.0, 0.05],
    };
    assert!(!warnings(&v).join("\n").contains("inside the body"));
}

#[test]
fn bundled_vehicles_have_neither_warning() {
    for f in std::fs::read_dir(root().join("vehicles")).unwrap() {
        let p = f.unwrap().path();
        if p.extension().is_none_or(|e| e != "toml") {
            continue; // vehicles/urdf/: the URDF robots' files
        }
        let v = tracksim::model::load_vehicle(&p).unwrap();
        let w = design_report(&v).warnings.join("\n");
        assert!(
            !w.contains("hangs") && !w.contains("inside the body"),
            "{}: {w}",
            p.display()
        );
    }
}
