//! Track loops and grouser layout (issue 2): exact lengths, closure of pulley loops, equal
//! spacing by arc length (property test), and broken loops rejected with the segment named.

use glam::DVec3;
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};
use tracksim::geometry::{GrouserLayout, PathError, Pulley, Segment, TrackPath};

fn pulley(x: f64, z: f64, radius: f64) -> Pulley {
    Pulley { x, z, radius }
}

fn oval_segments(a: f64, r: f64) -> Vec<Segment> {
    let h = a / 2.0;
    vec![
        Segment::Straight {
            start: DVec3::new(-h, 0.0, r),
            direction: DVec3::X,
            length: a,
        },
        Segment::Arc {
            start: DVec3::new(h, 0.0, r),
            centre: DVec3::new(h, 0.0, 0.0),
            axis: DVec3::Y,
            angle: PI,
        },
        Segment::Straight {
            start: DVec3::new(h, 0.0, -r),
            direction: DVec3::NEG_X,
            length: a,
        },
        Segment::Arc {
            start: DVec3::new(-h, 0.0, -r),
            centre: DVec3::new(-h, 0.0, 0.0),
            axis: DVec3::Y,
            angle: PI,
        },
    ]
}

#[test]
fn explicit_oval_length_is_2a_plus_2_pi_r() {
    let p = TrackPath::new(oval_segments(0.51, 0.082)).unwrap();
    assert_eq!(p.length(), 2.0 * 0.51 + 2.0 * PI * 0.082);
}

#[test]
fn unequal_pulleys_close_with_the_exact_length() {
    let (r1, r2, d) = (0.10, 0.05, 0.40);
    let p = TrackPath::from_pulleys(&[pulley(0.0, 0.0, r1), pulley(d, 0.0, r2)], 0.0).unwrap();
    let a = ((r1 - r2) / d).asin();
    let expected =
        2.0 * (d * d - (r1 - r2).powi(2)).sqrt() + r1 * (PI + 2.0 * a) + r2 * (PI - 2.0 * a);
    assert!(
        (p.length() - expected).abs() < 1e-12,
        "{} vs {expected}",
        p.length()
    );
    assert_eq!(p.segments().len(), 4);
}

#[test]
fn triangle_and_trapezoid_close() {
    let r = 0.05;
    let tri = [
        pulley(-0.3, 0.0, r),
        pulley(0.3, 0.0, r),
        pulley(0.0, 0.3, r),
    ];
    let p = TrackPath::from_pulleys(&tri, 0.1).unwrap();
    let perimeter = 0.6 + 2.0 * (0.3f64.powi(2) + 0.3f64.powi(2)).sqrt();
    assert!((p.length() - (perimeter + TAU * r)).abs() < 1e-12);
    assert_eq!(p.segments().len(), 6);
    assert!(
        p.segments()
            .iter()
            .all(|s| (s.start().y - 0.1).abs() < 1e-15)
    );
    // Listing the pulleys the other way round gives the same loop (same length, same sense).
    let rev: Vec<_> = tri.iter().rev().copied().collect();
    let q = TrackPath::from_pulleys(&rev, 0.1).unwrap();
    assert!((q.length() - p.length()).abs() < 1e-12);
    assert!((q.axis() - DVec3::Y).length() < 1e-12);
    // A tank-like trapezoid with a small idler.
    let trap = [
        pulley(-0.4, 0.0, 0.06),
        pulley(0.4, 0.0, 0.06),
        pulley(0.5, 0.2, 0.1),
        pulley(-0.5, 0.2, 0.04),
    ];
    assert!(TrackPath::from_pulleys(&trap, 0.0).is_ok());
}

fn arc_params(s: &Segment) -> Option<(DVec3, f64)> {
    Some((s.arc_centre()?, s.radius()?))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]
    /// For random valid loops (convex pulley arrangements) and random N, every footprint lies on
    /// its segment and consecutive footprints are exactly L/N apart along the path, measured by
    /// a fine polyline independent of the closed-form parameterisation.
    #[test]
    fn grousers_are_equally_spaced_by_arc_length(
        n_pulleys in 2usize..6,
        spread in 0.15f64..0.6,
        radii in prop::collection::vec(0.02f64..0.09, 6),
        jitter in prop::collection::vec(-0.3f64..0.3, 6),
        count in 1usize..90,
        offset in -1.0f64..1.0,
    ) {
        let pulleys: Vec<Pulley> = (0..n_pulleys)
            .map(|i| {
                let a = TAU * (i as f64 + 0.5 * jitter[i]) / n_pulleys as f64;
                pulley(spread * a.cos(), spread * a.sin(), radii[i])
            })
            .collect();
        let path = TrackPath::from_pulleys(&pulleys, 0.0);
        prop_assume!(path.is_ok());
        let path = path.unwrap();
        let layout = GrouserLayout { count, offset };
        let pitch = layout.pitch(&path);
        let feet = layout.footprints(&path);
        prop_assert_eq!(feet.len(), count);
        for (k, (seg, frame)) in feet.iter().enumerate() {
            // On its segment's line or circle.
            let s = &path.segments()[*seg];
            if let Some((c, r)) = arc_params(s) {
                prop_assert!(((frame.origin - c).length() - r).abs() < 1e-9);
            }
            // Orthonormal, right-handed frame with the normal pointing away from the loop.
            prop_assert!((frame.tangent.cross(frame.lateral) - frame.normal).length() < 1e-9);
            // Walk a fine polyline from this footprint to the next: its length is the pitch.
            let s0 = layout.footprint_s(&path, k);
            let m = (pitch / 2e-4).ceil() as usize;
            let mut walked = 0.0;
            let mut prev = frame.origin;
            for i in 1..=m {
                let q = path.frame_at(s0 + pitch * i as f64 / m as f64).origin;
                walked += (q - prev).length();
                prev = q;
            }
            // Chords of step h underestimate an arc of radius r >= 0.02 m by a relative (h/r)^2/24
            // <= 4.2e-6 with h <= 0.2 mm.
            prop_assert!((walked - pitch).abs() < 1e-5 * pitch, "walked {} pitch {}", walked, pitch);
            let next = path.frame_at(s0 + pitch).origin;
            prop_assert!((prev - next).length() < 1e-9);
        }
        // The loop closes on itself.
        prop_assert!((path.frame_at(0.0).origin - path.frame_at(path.length()).origin).length() < 1e-9);
    }
}

fn names_segment(errs: &[PathError], i: usize) -> bool {
    errs.iter()
        .any(|e| e.to_string().contains(&format!("segment {i}")))
}

#[test]
fn a_gap_is_rejected_naming_the_segment() {
    let mut s = oval_segments(0.5, 0.08);
    if let Segment::Straight { length, .. } = &mut s[2] {
        *length -= 0.003;
    }
    let e = TrackPath::new(s).unwrap_err();
    assert!(
        matches!(
            e[0],
            PathError::Gap {
                segment: 2,
                next: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e[0].to_string().contains("0.003"), "{}", e[0]);
    assert!(names_segment(&e, 2));
}

#[test]
fn a_kink_is_rejected_naming_the_segment() {
    let mut s = oval_segments(0.5, 0.08);
    if let Segment::Straight { direction, .. } = &mut s[0] {
        *direction = DVec3::new(1.0, 0.0, 0.01);
    }
    let e = TrackPath::new(s).unwrap_err();
    assert!(
        e.iter().any(|e| matches!(
            e,
            PathError::Kink { segment: 0, .. } | PathError::Kink { next: 0, .. }
        )),
        "{e:?}"
    );
    assert!(names_segment(&e, 0));
}

#[test]
fn full_circle_arcs_are_rejected() {
    // The published mistake: every arc set to 2 pi.
    let mut s = oval_segments(0.5, 0.08);
    for seg in &mut s {
        if let Segment::Arc { angle, .. } = seg {
            *angle = TAU;
        }
    }
    let e = TrackPath::new(s).unwrap_err();
    assert!(
        matches!(e[0], PathError::BadArcAngle { segment: 1, .. }),
        "{e:?}"
    );
    assert!(names_segment(&e, 1) && names_segment(&e, 3));
    // Overlapping arcs short of a full turn still fail: the loop turns more than once.
    let mut s = oval_segments(0.5, 0.08);
    if let Segment::Arc { angle, .. } = &mut s[1] {
        *angle = PI + TAU * 0.9;
    }
    let e = TrackPath::new(s).unwrap_err();
    assert!(
        e.iter()
            .any(|e| matches!(e, PathError::BadArcAngle { segment: 1, .. })),
        "{e:?}"
    );
}

#[test]
fn non_positive_radius_and_length_are_rejected() {
    let mut s = oval_segments(0.5, 0.08);
    if let Segment::Arc { start, centre, .. } = &mut s[3] {
        *start = *centre;
    }
    if let Segment::Straight { length, .. } = &mut s[0] {
        *length = -0.5;
    }
    let e = TrackPath::new(s).unwrap_err();
    assert!(
        e.iter()
            .any(|e| matches!(e, PathError::NonPositiveRadius { segment: 3, .. })),
        "{e:?}"
    );
    assert!(
        e.iter()
            .any(|e| matches!(e, PathError::NonPositiveLength { segment: 0, .. })),
        "{e:?}"
    );
    let e =
        TrackPath::from_pulleys(&[pulley(0.0, 0.0, 0.1), pulley(0.5, 0.0, 0.0)], 0.0).unwrap_err();
    assert!(e[0].to_string().contains("pulley 1"), "{}", e[0]);
    let e = TrackPath::from_pulleys(&[pulley(0.0, 0.0, 0.1), pulley(0.02, 0.0, 0.05)], 0.0)
        .unwrap_err();
    assert!(matches!(e[0], PathError::PulleysOverlap { .. }), "{e:?}");
}

#[test]
fn pulleys_out_of_convex_order_are_rejected() {
    // A pulley inside the loop: the belt would have to bend inwards.
    let e = TrackPath::from_pulleys(
        &[
            pulley(-0.3, 0.0, 0.05),
            pulley(0.0, 0.2, 0.05),
            pulley(0.3, 0.0, 0.05),
            pulley(0.0, 0.1, 0.05),
        ],
        0.0,
    )
    .unwrap_err();
    // Named as the pulley the belt would bend backwards around (issue 24), not as a loop that
    // turns 720 deg.
    assert!(
        e.iter().any(|e| matches!(
            e,
            PathError::PulleyNotWrapped {
                pulley: 3,
                collinear: false,
                ..
            }
        )),
        "{e:?}"
    );
}

#[test]
fn zero_grousers_is_rejected_with_its_key() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../vehicles/packbot510.toml"
    ))
    .unwrap();
    let text = text.replace("count = 40", "count = 0");
    let spec: tracksim::spec::VehicleSpec = toml::from_str(&text).unwrap();
    let issues = tracksim::model::compile_vehicle(&spec).unwrap_err();
    assert!(
        issues
            .iter()
            .any(|i| i.key == "tracks[0].grousers.count" && i.message.contains(">= 1")),
        "{issues:?}"
    );
}
